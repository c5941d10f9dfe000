#include "soccer_vision/ui/ui_requests.h"

#include <cmath>

namespace soccer_vision {

namespace {

UiRequestError bad(const std::string& message) { return UiRequestError(400, message); }

double finiteNumber(const nlohmann::json& value, const std::string& where) {
  if (!value.is_number()) throw bad(where + " is not a number");
  const double v = value.get<double>();
  if (!std::isfinite(v)) throw bad(where + " is not finite");
  return v;
}

Eigen::Vector2d pixelInImage(const nlohmann::json& value, int width, int height, const std::string& where) {
  if (!value.is_array() || value.size() != 2) throw bad(where + " is not [u, v]");
  const Eigen::Vector2d p(finiteNumber(value[0], where + "[0]"), finiteNumber(value[1], where + "[1]"));
  // Pixel centres are integers (docs/formats.md): the image spans -0.5 .. size - 0.5.
  if (p.x() < -0.5 || p.y() < -0.5 || p.x() > width - 0.5 || p.y() > height - 0.5)
    throw bad(where + " (" + std::to_string(p.x()) + ", " + std::to_string(p.y()) + ") is outside the " +
              std::to_string(width) + "x" + std::to_string(height) + " image");
  return p;
}

}  // namespace

nlohmann::json parseJsonBody(const std::string& body, const UiRequestLimits& limits) {
  if (body.size() > limits.max_body_bytes)
    throw UiRequestError(413, "request body of " + std::to_string(body.size()) +
                                  " bytes exceeds the limit of " + std::to_string(limits.max_body_bytes));
  nlohmann::json j = nlohmann::json::parse(body, nullptr, false);
  if (j.is_discarded()) throw bad("request body is not valid JSON");
  if (!j.is_object()) throw bad("request body is not a JSON object");
  return j;
}

ColorSamples parseSamplesRequest(const nlohmann::json& body, int width, int height,
                                 const UiRequestLimits& limits) {
  const auto it = body.find("samples");
  if (it == body.end() || !it->is_object()) throw bad("`samples` is missing or not an object");
  ColorSamples samples;
  int polygons = 0;
  for (const auto& [name, list] : it->items()) {
    const std::optional<ColorClass> c = parseColorClass(name);
    if (!c || *c == ColorClass::None) throw bad("samples: unknown colour class '" + name + "'");
    if (!list.is_array()) throw bad("samples." + name + " is not a list of polygons");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string where = "samples." + name + "[" + std::to_string(i) + "]";
      if (++polygons > limits.max_polygons)
        throw bad("samples: more than " + std::to_string(limits.max_polygons) + " polygons");
      const nlohmann::json& poly = list[i];
      if (!poly.is_array() || poly.size() < 3 || poly.size() > static_cast<std::size_t>(limits.max_vertices))
        throw bad(where + " is not a polygon of 3.." + std::to_string(limits.max_vertices) + " vertices");
      Polygon polygon;
      for (std::size_t k = 0; k < poly.size(); ++k)
        polygon.push_back(pixelInImage(poly[k], width, height, where + "[" + std::to_string(k) + "]"));
      samples[*c].push_back(std::move(polygon));
    }
  }
  if (samples.empty()) throw bad("samples has no class with polygons");
  return samples;
}

std::vector<FieldCorrespondence> parseCorrespondencesRequest(const nlohmann::json& body, int width,
                                                             int height, const UiRequestLimits& limits) {
  const auto it = body.find("points");
  if (it == body.end() || !it->is_array()) throw bad("`points` is missing or not a list");
  if (it->size() < 4 || it->size() > static_cast<std::size_t>(limits.max_points))
    throw bad("points: " + std::to_string(it->size()) + " given, 4.." + std::to_string(limits.max_points) +
              " needed");
  std::vector<FieldCorrespondence> points;
  for (std::size_t i = 0; i < it->size(); ++i) {
    const std::string where = "points[" + std::to_string(i) + "]";
    const nlohmann::json& p = (*it)[i];
    if (!p.is_object() || !p.contains("pixel") || !p.contains("field"))
      throw bad(where + " is not {\"pixel\": [u, v], \"field\": [x, y, z]}");
    const nlohmann::json& f = p["field"];
    if (!f.is_array() || f.size() != 3) throw bad(where + ".field is not [x, y, z]");
    FieldCorrespondence c;
    c.pixel = pixelInImage(p["pixel"], width, height, where + ".pixel");
    for (int k = 0; k < 3; ++k) {
      c.field[k] = finiteNumber(f[k], where + ".field[" + std::to_string(k) + "]");
      if (std::abs(c.field[k]) > 100) throw bad(where + ".field is more than 100 m from the centre");
    }
    points.push_back(c);
  }
  return points;
}

int parseCameraId(const std::string& text) {
  if (text.empty() || text.size() > 3 || text.find_first_not_of("0123456789") != std::string::npos)
    throw UiRequestError(404, "no camera '" + text + "'");
  const int id = std::stoi(text);
  if (id > 255) throw UiRequestError(404, "no camera " + text);
  return id;
}

}  // namespace soccer_vision
