#include "soccer_vision/common/robot_pattern.h"

#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "soccer_vision/common/exchange_formats.h"

namespace soccer_vision {
namespace {

MarkerShape disc(double x, double y, double radius) {
  MarkerShape s;
  s.kind = MarkerShape::Kind::Disc;
  s.x = x;
  s.y = y;
  s.radius = radius;
  return s;
}

MarkerShape polarDisc(double angle_deg, double distance, double radius) {
  const double a = angle_deg * M_PI / 180.0;
  return disc(distance * std::cos(a), distance * std::sin(a), radius);
}

// Far above every real pattern (the SSL one has 4 slots and 16 ids).
constexpr std::size_t kMaxPatternSlots = 16;
constexpr std::size_t kMaxPatternIds = 256;

[[noreturn]] void fail(const std::string& source, const std::string& what) {
  throw std::runtime_error("pattern set " + source + ": " + what);
}

// `limit`: metres for lengths (nothing on a robot is a metre away), degrees for angles.
// `name` is how the error messages call the value.
double scalar(const YAML::Node& v, const std::string& name, const std::string& source, double limit) {
  double x = 0;
  try {
    x = v.as<double>();
  } catch (const YAML::Exception&) {
    fail(source, "'" + name + "' is not a number");
  }
  // NaN would pass every comparison below.
  if (!std::isfinite(x) || std::abs(x) > limit) {
    std::ostringstream os;
    os << "'" << name << "' must be a finite number within +-" << limit;
    fail(source, os.str());
  }
  return x;
}

double number(const YAML::Node& n, const char* key, const std::string& source, double limit = 1.0) {
  if (!n[key]) fail(source, std::string("missing '") + key + "'");
  return scalar(n[key], key, source, limit);
}

// A marker plane: above the carpet and below half a metre (the league's robots are at most
// 0.15 m high).
constexpr double kMaxRobotHeight = 0.5;

double height(const YAML::Node& v, const std::string& name, const std::string& source) {
  const double h = scalar(v, name, source, kMaxRobotHeight);
  if (h <= 0) fail(source, "'" + name + "' must be positive");
  return h;
}

// A typo ('slot:', 'id:') once made a team-only pattern silently: every key must be known.
void checkKeys(const YAML::Node& n, const std::set<std::string>& known, const std::string& where,
               const std::string& source) {
  for (const auto& kv : n) {
    const std::string key = kv.first.as<std::string>();
    if (known.count(key)) continue;
    std::string list;
    for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
    fail(source, "unknown key '" + key + "' in " + where + " (known: " + list + ")");
  }
}

// `robot_height: 0.150` (both teams) or `robot_height: {blue: 0.148, yellow: 0.135}`.
void parseHeights(const YAML::Node& n, PatternSet& p, const std::string& source) {
  if (n.IsScalar()) {
    p.robot_height = height(n, "robot_height", source);
    return;
  }
  if (!n.IsMap()) fail(source, "'robot_height' must be a number or a map {blue: h, yellow: h}");
  checkKeys(n, {"blue", "yellow"}, "'robot_height'", source);
  for (const Team team : {Team::Blue, Team::Yellow}) {
    const std::string key(teamName(team));
    if (!n[key]) fail(source, "'robot_height' as a map must give both teams (missing '" + key + "')");
    p.team_height[static_cast<std::size_t>(team)] = height(n[key], "robot_height." + key, source);
  }
}

MarkerShape parseShape(const YAML::Node& n, const std::string& source) {
  if (!n.IsMap()) fail(source, "a marker shape must be a map");
  const std::string kind = n["shape"] ? n["shape"].as<std::string>() : "";
  checkKeys(n, {"shape", "x", "y", "radius", "angle_deg", "distance", "size_x", "size_y"}, "a marker shape",
            source);
  MarkerShape s;
  if (kind == "disc") {
    // Either cartesian (x, y) or polar (angle_deg from the heading, distance from the centre).
    if (n["angle_deg"]) {
      s = polarDisc(number(n, "angle_deg", source, 360.0), number(n, "distance", source),
                    number(n, "radius", source));
    } else {
      s = disc(number(n, "x", source), number(n, "y", source), number(n, "radius", source));
    }
    if (s.radius <= 0) fail(source, "disc radius must be positive");
  } else if (kind == "rect") {
    s.kind = MarkerShape::Kind::Rect;
    s.x = number(n, "x", source);
    s.y = number(n, "y", source);
    s.size_x = number(n, "size_x", source);
    s.size_y = number(n, "size_y", source);
    if (s.size_x <= 0 || s.size_y <= 0) fail(source, "rect sizes must be positive");
  } else {
    fail(source, "shape must be 'disc' or 'rect', got '" + kind + "'");
  }
  return s;
}

// Farthest extent of a shape from the robot centre, to check it fits on the top.
double reach(const MarkerShape& s) {
  if (s.kind == MarkerShape::Kind::Disc) return std::hypot(s.x, s.y) + s.radius;
  return std::hypot(std::abs(s.x) + s.size_x / 2, std::abs(s.y) + s.size_y / 2);
}

}  // namespace

std::vector<ColoredMarker> PatternSet::markers(Team team, int id) const {
  std::vector<ColoredMarker> out;
  out.push_back({team_marker, teamColor(team)});
  if (id >= 0 && id < static_cast<int>(ids.size())) {
    for (std::size_t i = 0; i < slots.size(); ++i) out.push_back({slots[i], ids[id][i]});
  }
  return out;
}

void appendShapeOutline(const MarkerShape& m, double x, double y, double theta, double z,
                        std::vector<Eigen::Vector3d>& points) {
  const double c = std::cos(theta), s = std::sin(theta);
  const auto add = [&](double lx, double ly) {
    points.emplace_back(x + c * lx - s * ly, y + s * lx + c * ly, z);
  };
  if (m.kind == MarkerShape::Kind::Rect) {
    for (double sx : {-0.5, 0.5})
      for (double sy : {-0.5, 0.5}) add(m.x + sx * m.size_x, m.y + sy * m.size_y);
  } else {
    for (int k = 0; k < 8; ++k)
      add(m.x + m.radius * std::cos(k * M_PI / 4), m.y + m.radius * std::sin(k * M_PI / 4));
  }
}

std::vector<Eigen::Vector3d> markerOutlinePoints(const PatternSet& patterns, Team team, int id, double x,
                                                 double y, double theta) {
  std::vector<Eigen::Vector3d> points;
  for (const ColoredMarker& marker : patterns.markers(team, id))
    appendShapeOutline(marker.shape, x, y, theta, patterns.height(team), points);
  return points;
}

PatternSet PatternSet::twoTag() {
  PatternSet p;
  p.name = "two_tag";
  // Team tag 80 x 30 mm, 20 mm behind the centre, long side across the heading.
  p.team_marker.kind = MarkerShape::Kind::Rect;
  p.team_marker.x = -0.020;
  p.team_marker.size_x = 0.030;
  p.team_marker.size_y = 0.080;
  p.slots = {disc(0.045, 0.0, 0.020)};  // role disc 40 mm, 45 mm ahead
  for (ColorClass c :
       {ColorClass::Pink, ColorClass::Purple, ColorClass::SkyBlue, ColorClass::Green, ColorClass::Red}) {
    p.ids.push_back({c});
  }
  return p;
}

PatternSet PatternSet::ssl() {
  PatternSet p;
  p.name = "ssl";
  p.team_marker = disc(0.0, 0.0, 0.025);
  // Front right, front left, back left, back right; 4-bit id, front right most significant.
  p.slots = {polarDisc(-60, 0.065, 0.020), polarDisc(60, 0.065, 0.020), polarDisc(135, 0.065, 0.020),
             polarDisc(-135, 0.065, 0.020)};
  for (int id = 0; id < 16; ++id) {
    std::vector<ColorClass> row;
    for (int bit = 3; bit >= 0; --bit) {
      row.push_back((id >> bit) & 1 ? ColorClass::Pink : ColorClass::Green);
    }
    p.ids.push_back(row);
  }
  return p;
}

PatternSet PatternSet::teamOnly() {
  PatternSet p;
  p.name = "team_only";
  p.team_marker = disc(0.0, 0.0, 0.025);
  return p;
}

PatternSet parsePatternSet(const std::string& yaml_text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    fail(source, std::string("invalid YAML: ") + e.what());
  }
  if (!root.IsMap()) fail(source, "top level must be a map");
  checkKeys(root, {"name", "robot_radius", "robot_height", "team_marker", "slots", "ids"}, "the pattern set",
            source);
  PatternSet p;
  p.name = root["name"] ? root["name"].as<std::string>() : source;
  if (root["robot_radius"]) p.robot_radius = number(root, "robot_radius", source);
  if (root["robot_height"]) parseHeights(root["robot_height"], p, source);
  if (p.robot_radius <= 0) fail(source, "'robot_radius' must be positive");
  if (!root["team_marker"]) fail(source, "missing 'team_marker'");
  p.team_marker = parseShape(root["team_marker"], source);
  if (root["slots"]) {
    if (!root["slots"].IsSequence() || root["slots"].size() > kMaxPatternSlots)
      fail(source, "'slots' must be a list of at most " + std::to_string(kMaxPatternSlots) + " shapes");
    for (const auto& s : root["slots"]) p.slots.push_back(parseShape(s, source));
  }
  if (root["ids"]) {
    if (!root["ids"].IsSequence() || root["ids"].size() > kMaxPatternIds)
      fail(source, "'ids' must be a list of at most " + std::to_string(kMaxPatternIds) + " rows");
    for (const auto& row : root["ids"]) {
      if (!row.IsSequence() || row.size() != p.slots.size()) {
        fail(source, "id " + std::to_string(p.ids.size()) + " must list one colour per slot (" +
                         std::to_string(p.slots.size()) + ")");
      }
      std::vector<ColorClass> colors;
      for (const auto& c : row) {
        const auto cls = parseColorClass(c.as<std::string>());
        if (!cls || !isMarkerColor(*cls)) {
          fail(source, "'" + c.as<std::string>() + "' is not a marker colour");
        }
        // The ball's colour and the team colours are found as such, never as an id.
        if (*cls == ColorClass::Orange || isTeamColor(*cls)) {
          fail(source, "id " + std::to_string(p.ids.size()) + ": '" + c.as<std::string>() +
                           "' is not an id colour (orange is the ball's, blue and yellow the teams')");
        }
        colors.push_back(*cls);
      }
      p.ids.push_back(colors);
    }
  }
  if (!p.slots.empty() && p.ids.empty()) fail(source, "slots given but no ids");
  std::set<std::vector<ColorClass>> unique(p.ids.begin(), p.ids.end());
  if (unique.size() != p.ids.size()) fail(source, "two ids share the same colours");
  if (reach(p.team_marker) > p.robot_radius) fail(source, "team marker exceeds the robot top");
  for (const auto& s : p.slots) {
    if (reach(s) > p.robot_radius) fail(source, "an id marker exceeds the robot top");
  }
  return p;
}

PatternSet loadPatternSet(const std::string& path) { return parsePatternSet(readTextFile(path), path); }

PatternSet patternSetByName(const std::string& name_or_path) {
  if (name_or_path == "two_tag") return PatternSet::twoTag();
  if (name_or_path == "ssl") return PatternSet::ssl();
  if (name_or_path == "team_only") return PatternSet::teamOnly();
  return loadPatternSet(name_or_path);
}

}  // namespace soccer_vision
