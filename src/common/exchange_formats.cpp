#include "soccer_vision/common/exchange_formats.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include "soccer_vision/common/atomic_file.h"

namespace soccer_vision {
namespace {

using nlohmann::json;

// Fixed decimals keep files diff-able and stamps exact to the microsecond.
json rounded(double v, int decimals) {
  const double scale = std::pow(10.0, decimals);
  return std::round(v * scale) / scale;
}

template <typename Record>
void addOptional(json& j, const Record& r) {
  if (r.visible) j["visible"] = *r.visible;
  if (r.confidence) j["confidence"] = rounded(*r.confidence, 4);
}

template <typename Record>
void readOptional(const json& j, Record& r) {
  if (j.contains("visible")) r.visible = j.at("visible").get<bool>();
  if (j.contains("confidence")) r.confidence = j.at("confidence").get<double>();
}

std::vector<double> numbers(const YAML::Node& n, std::size_t count, const std::string& what) {
  if (!n || !n.IsSequence() || n.size() != count) {
    throw std::runtime_error(what + " must be a list of " + std::to_string(count) + " numbers");
  }
  std::vector<double> v;
  for (const auto& e : n) {
    v.push_back(e.as<double>());
    if (!std::isfinite(v.back())) throw std::runtime_error(what + " must be finite numbers");
  }
  return v;
}

YAML::Node loadYaml(const std::string& text, const std::string& source) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(source + ": invalid YAML: " + e.what());
  }
}

}  // namespace

std::string toJsonLine(const FrameRecord& frame) {
  json j;
  j["stamp"] = rounded(frame.stamp, 6);
  j["robots"] = json::array();
  for (const auto& r : frame.robots) {
    json o = {{"team", std::string(teamName(r.team))},
              {"id", r.id},
              {"x", rounded(r.x, 4)},
              {"y", rounded(r.y, 4)},
              {"theta", rounded(r.theta, 4)}};
    addOptional(o, r);
    j["robots"].push_back(o);
  }
  j["balls"] = json::array();
  for (const auto& b : frame.balls) {
    json o = {{"x", rounded(b.x, 4)}, {"y", rounded(b.y, 4)}};
    addOptional(o, b);
    j["balls"].push_back(o);
  }
  return j.dump();
}

FrameRecord parseJsonLine(const std::string& line) {
  FrameRecord f;
  try {
    const json j = json::parse(line);
    f.stamp = j.at("stamp").get<double>();
    for (const auto& o : j.value("robots", json::array())) {
      RobotRecord r;
      const auto team = parseTeam(o.at("team").get<std::string>());
      if (!team) throw std::runtime_error("unknown team '" + o.at("team").get<std::string>() + "'");
      r.team = *team;
      r.id = o.at("id").get<int>();
      r.x = o.at("x").get<double>();
      r.y = o.at("y").get<double>();
      r.theta = o.value("theta", 0.0);
      readOptional(o, r);
      f.robots.push_back(r);
    }
    for (const auto& o : j.value("balls", json::array())) {
      BallRecord b;
      b.x = o.at("x").get<double>();
      b.y = o.at("y").get<double>();
      readOptional(o, b);
      f.balls.push_back(b);
    }
  } catch (const json::exception& e) {
    throw std::runtime_error(std::string("invalid frame record: ") + e.what());
  }
  return f;
}

void writeJsonLines(const std::string& path, const std::vector<FrameRecord>& frames) {
  std::string text;
  for (const auto& f : frames) text += toJsonLine(f) + "\n";
  writeTextFile(path, text);
}

std::vector<FrameRecord> readJsonLines(const std::string& path) {
  std::istringstream in(readTextFile(path));
  std::vector<FrameRecord> frames;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    try {
      frames.push_back(parseJsonLine(line));
    } catch (const std::exception& e) {
      throw std::runtime_error(path + ":" + std::to_string(number) + ": " + e.what());
    }
  }
  return frames;
}

std::string toYaml(const ColorSamples& samples) {
  std::ostringstream out;
  out << std::setprecision(10);
  for (const auto& [cls, polygons] : samples) {
    out << colorClassName(cls) << ":\n";
    for (const auto& poly : polygons) {
      out << "  - [";
      for (std::size_t i = 0; i < poly.size(); ++i) {
        out << (i ? ", " : "") << "[" << poly[i].x() << ", " << poly[i].y() << "]";
      }
      out << "]\n";
    }
  }
  return out.str();
}

ColorSamples parseColorSamples(const std::string& yaml_text, const std::string& source) {
  const YAML::Node root = loadYaml(yaml_text, source);
  if (!root.IsMap()) throw std::runtime_error(source + ": colour samples must be a map");
  ColorSamples samples;
  for (const auto& kv : root) {
    const auto name = kv.first.as<std::string>();
    const auto cls = parseColorClass(name);
    if (!cls || *cls == ColorClass::None) {
      throw std::runtime_error(source + ": unknown colour class '" + name + "'");
    }
    if (!kv.second.IsSequence()) throw std::runtime_error(source + ": '" + name + "' must be a list");
    for (const auto& poly : kv.second) {
      Polygon p;
      try {
        for (const auto& pt : poly) {
          const auto v = numbers(pt, 2, "a point");
          p.emplace_back(v[0], v[1]);
        }
      } catch (const std::exception& e) {
        throw std::runtime_error(source + ": '" + name + "': " + e.what());
      }
      if (p.size() < 3) throw std::runtime_error(source + ": '" + name + "': a polygon needs 3 points");
      samples[*cls].push_back(p);
    }
  }
  try {
    checkColorSamples(samples);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(source + ": " + e.what());
  }
  return samples;
}

std::string sampledClassNames(const ColorSamples& samples) {
  std::vector<ColorClass> sampled;
  for (const auto& [color, polygons] : samples) {
    if (!polygons.empty()) sampled.push_back(color);
  }
  return colorClassNames(sampled);
}

void checkColorSamples(const ColorSamples& samples) {
  std::size_t polygons = 0, vertices = 0;
  for (const auto& [cls, list] : samples) {
    const std::string name(colorClassName(cls));
    for (std::size_t i = 0; i < list.size(); ++i) {
      const Polygon& poly = list[i];
      const std::string where = "'" + name + "' polygon " + std::to_string(i);
      if (++polygons > kMaxSamplePolygons) {
        throw std::invalid_argument("more than " + std::to_string(kMaxSamplePolygons) + " sample polygons");
      }
      vertices += poly.size();
      if (vertices > kMaxSampleVertices) {
        throw std::invalid_argument("more than " + std::to_string(kMaxSampleVertices) +
                                    " sample vertices in all");
      }
      if (poly.size() < 3 || poly.size() > kMaxPolygonVertices) {
        throw std::invalid_argument(where + ": " + std::to_string(poly.size()) + " vertices, needs 3.." +
                                    std::to_string(kMaxPolygonVertices));
      }
      double twice_area = 0;
      for (std::size_t k = 0; k < poly.size(); ++k) {
        const Eigen::Vector2d& p = poly[k];
        if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || std::abs(p.x()) > kMaxSampleCoordinate ||
            std::abs(p.y()) > kMaxSampleCoordinate) {
          std::ostringstream os;
          os << where << " vertex " << k << ": (" << p.x() << ", " << p.y()
             << ") is not a finite pixel coordinate within +-" << kMaxSampleCoordinate;
          throw std::invalid_argument(os.str());
        }
        const Eigen::Vector2d& q = poly[(k + 1) % poly.size()];
        twice_area += p.x() * q.y() - q.x() * p.y();
      }
      // Below a millionth of a pixel: the vertices lie on one line, the polygon selects nothing.
      if (std::abs(twice_area) < 2e-6) throw std::invalid_argument(where + " has no area (degenerate)");
    }
  }
}

ColorSamples loadColorSamples(const std::string& path) { return parseColorSamples(readTextFile(path), path); }

std::string toYaml(const std::vector<FieldCorrespondence>& points) {
  std::ostringstream out;
  out << std::setprecision(10) << "points:\n";
  for (const auto& p : points) {
    out << "  - {pixel: [" << p.pixel.x() << ", " << p.pixel.y() << "], field: [" << p.field.x() << ", "
        << p.field.y() << ", " << p.field.z() << "]}\n";
  }
  return out.str();
}

std::vector<FieldCorrespondence> parseFieldCorrespondences(const std::string& yaml_text,
                                                           const std::string& source) {
  const YAML::Node root = loadYaml(yaml_text, source);
  if (!root.IsMap() || !root["points"] || !root["points"].IsSequence()) {
    throw std::runtime_error(source + ": expected 'points:' with a list of correspondences");
  }
  if (root["points"].size() > kMaxFieldCorrespondences) {
    throw std::runtime_error(source + ": 'points' has " + std::to_string(root["points"].size()) +
                             " correspondences, at most " + std::to_string(kMaxFieldCorrespondences));
  }
  std::vector<FieldCorrespondence> out;
  for (const auto& n : root["points"]) {
    try {
      const auto px = numbers(n["pixel"], 2, "pixel");
      const auto f = numbers(n["field"], 3, "field");
      out.push_back({{px[0], px[1]}, {f[0], f[1], f[2]}});
    } catch (const std::exception& e) {
      throw std::runtime_error(source + ": point " + std::to_string(out.size()) + ": " + e.what());
    }
  }
  return out;
}

std::vector<FieldCorrespondence> loadFieldCorrespondences(const std::string& path) {
  return parseFieldCorrespondences(readTextFile(path), path);
}

std::string readTextFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open file");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void writeTextFile(const std::string& path, const std::string& text) {
  writeFileAtomically(path, text.data(), text.size());
}

}  // namespace soccer_vision
