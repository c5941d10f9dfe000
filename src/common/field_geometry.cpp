#include "soccer_vision/common/field_geometry.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "soccer_vision/common/angle.h"
#include "soccer_vision/common/exchange_formats.h"

namespace soccer_vision {

namespace {

constexpr double kTwoPi = 2 * M_PI;
constexpr double kMaxFieldSize = 100.0;  // m: no real field is larger; beyond this a file is wrong
constexpr std::size_t kMaxMarkings = 1000;

[[noreturn]] void fail(const std::string& source, const std::string& what) {
  throw std::runtime_error("field geometry " + source + ": " + what);
}

// A finite number in [min, max] under `key`.
double number(const YAML::Node& node, const std::string& key, const std::string& source, double min,
              double max) {
  double v = 0;
  try {
    v = node.as<double>();
  } catch (const YAML::Exception&) {
    fail(source, "'" + key + "' must be a number");
  }
  if (!std::isfinite(v) || v < min || v > max) {
    fail(source, "'" + key + "' = " + std::to_string(v) + " is outside [" + std::to_string(min) + ", " +
                     std::to_string(max) + "]");
  }
  return v;
}

Eigen::Vector2d point(const YAML::Node& node, const std::string& key, const std::string& source) {
  if (!node.IsSequence() || node.size() != 2) fail(source, "'" + key + "' must be [x, y]");
  return {number(node[0], key + "[0]", source, -kMaxFieldSize, kMaxFieldSize),
          number(node[1], key + "[1]", source, -kMaxFieldSize, kMaxFieldSize)};
}

// yaml-cpp keeps the last of repeated keys; a file that repeats one is ambiguous, so refuse it.
void checkKeys(const YAML::Node& map, const std::set<std::string>& allowed, const std::string& where,
               const std::string& source) {
  std::set<std::string> seen;
  for (const auto& kv : map) {
    const std::string key = kv.first.as<std::string>();
    if (!allowed.count(key)) fail(source, "unknown key '" + key + "'" + where);
    if (!seen.insert(key).second) fail(source, "key '" + key + "' given twice" + where);
  }
}

}  // namespace

double LineSegment::distance(const Eigen::Vector2d& p) const {
  const Eigen::Vector2d d = b - a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return (a + t * d - p).norm();
}

bool CircleArc::fullCircle() const { return a2 - a1 >= kTwoPi - 1e-12; }

double CircleArc::distance(const Eigen::Vector2d& p) const {
  const Eigen::Vector2d d = p - centre;
  if (fullCircle()) return std::abs(d.norm() - radius);
  // Within the arc's angular range: radial distance; else the nearer end point.
  double along = wrapToPi(std::atan2(d.y(), d.x()) - a1);  // angle past a1 in [0, 2 pi)
  if (along < 0) along += kTwoPi;
  if (along <= a2 - a1) return std::abs(d.norm() - radius);
  const Eigen::Vector2d e1 = centre + radius * Eigen::Vector2d(std::cos(a1), std::sin(a1));
  const Eigen::Vector2d e2 = centre + radius * Eigen::Vector2d(std::cos(a2), std::sin(a2));
  return std::min((p - e1).norm(), (p - e2).norm());
}

std::vector<Eigen::Vector2d> CircleArc::points(int segments) const {
  std::vector<Eigen::Vector2d> p;
  for (int i = 0; i <= segments; ++i) {
    const double a = a1 + (a2 - a1) * i / segments;
    p.emplace_back(centre.x() + radius * std::cos(a), centre.y() + radius * std::sin(a));
  }
  return p;
}

std::vector<LineSegment> FieldGeometry::lines() const {
  if (!custom_lines.empty() || !custom_arcs.empty()) return custom_lines;
  const double hl = halfLength(), hw = halfWidth();
  std::vector<LineSegment> l = {
      {{-hl, -hw}, {hl, -hw}, "BottomTouchLine"}, {{-hl, hw}, {hl, hw}, "TopTouchLine"},
      {{-hl, -hw}, {-hl, hw}, "LeftGoalLine"},    {{hl, -hw}, {hl, hw}, "RightGoalLine"},
      {{0, -hw}, {0, hw}, "HalfwayLine"},
  };
  // Penalty (defence) areas: rectangles penalty_area_depth x penalty_area_width in front of each goal.
  const double pw = penalty_area_width / 2;
  for (double side : {-1.0, 1.0}) {
    const std::string field_side = side < 0 ? "Left" : "Right";
    const double gx = side * hl, fx = side * (hl - penalty_area_depth);
    l.push_back({{gx, -pw}, {fx, -pw}, field_side + "FieldLeftPenaltyStretch"});
    l.push_back({{gx, pw}, {fx, pw}, field_side + "FieldRightPenaltyStretch"});
    l.push_back({{fx, -pw}, {fx, pw}, field_side + "PenaltyStretch"});
  }
  if (centre_line) l.push_back({{-hl, 0}, {hl, 0}, "CenterLine"});
  return l;
}

std::vector<CircleArc> FieldGeometry::circles() const {
  if (!custom_lines.empty() || !custom_arcs.empty()) return custom_arcs;
  return {{{0.0, 0.0}, centre_radius, "CenterCircle"}};
}

std::vector<Eigen::Vector3d> FieldGeometry::landmarks() const {
  if (!custom_lines.empty() || !custom_arcs.empty()) {
    // Custom markings: the end points of the lines and where two lines cross, once each.
    std::vector<Eigen::Vector3d> p;
    const auto add = [&p](const Eigen::Vector2d& q) {
      for (const auto& e : p)
        if ((e.head<2>() - q).norm() < 1e-6) return;
      p.emplace_back(q.x(), q.y(), 0.0);
    };
    for (const LineSegment& s : custom_lines) {
      add(s.a);
      add(s.b);
    }
    for (std::size_t i = 0; i < custom_lines.size(); ++i) {
      for (std::size_t j = i + 1; j < custom_lines.size(); ++j) {
        const Eigen::Vector2d r = custom_lines[i].b - custom_lines[i].a;
        const Eigen::Vector2d s = custom_lines[j].b - custom_lines[j].a;
        const double den = r.x() * s.y() - r.y() * s.x();
        if (std::abs(den) < 1e-12) continue;  // parallel
        const Eigen::Vector2d q = custom_lines[j].a - custom_lines[i].a;
        const double t = (q.x() * s.y() - q.y() * s.x()) / den, u = (q.x() * r.y() - q.y() * r.x()) / den;
        if (t >= 0 && t <= 1 && u >= 0 && u <= 1) add(custom_lines[i].a + t * r);
      }
    }
    return p;
  }
  const double hl = halfLength(), hw = halfWidth(), pw = penalty_area_width / 2;
  std::vector<Eigen::Vector3d> p = {
      {0, 0, 0}, {0, -hw, 0}, {0, hw, 0}, {0, -centre_radius, 0}, {0, centre_radius, 0}};
  for (double side : {-1.0, 1.0}) {
    const double gx = side * hl, fx = side * (hl - penalty_area_depth);
    for (double y : {-hw, hw}) p.emplace_back(gx, y, 0);  // field corners
    for (double y : {-pw, pw}) p.emplace_back(gx, y, 0);  // penalty area on the goal line
    for (double y : {-pw, pw}) p.emplace_back(fx, y, 0);  // penalty area front corners
    if (centre_line) p.emplace_back(gx, 0, 0);            // centre line meets the goal line
  }
  if (centre_line) {
    p.emplace_back(-centre_radius, 0, 0);
    p.emplace_back(centre_radius, 0, 0);
  }
  return p;
}

double FieldGeometry::distanceToMarkings(const Eigen::Vector2d& p) const {
  double d = HUGE_VAL;
  for (const LineSegment& s : lines()) d = std::min(d, s.distance(p));
  for (const CircleArc& c : circles()) d = std::min(d, c.distance(p));
  return d;
}

double FieldGeometry::distanceToCarpetEdge(const Eigen::Vector2d& p) const {
  const double dx = std::abs(p.x()) - carpetHalfLength(), dy = std::abs(p.y()) - carpetHalfWidth();
  if (dx <= 0 && dy <= 0) return std::min(-dx, -dy);
  return std::hypot(std::max(dx, 0.0), std::max(dy, 0.0));
}

bool FieldGeometry::onCarpet(double x, double y, double margin) const {
  return std::abs(x) <= carpetHalfLength() + margin && std::abs(y) <= carpetHalfWidth() + margin;
}

bool FieldGeometry::inPlayingArea(double x, double y, double margin) const {
  const double edge = line_width / 2 + margin;
  return std::abs(x) <= halfLength() + edge && std::abs(y) <= halfWidth() + edge;
}

FieldGeometry FieldGeometry::divB() { return FieldGeometry{}; }

FieldGeometry FieldGeometry::divA() {
  FieldGeometry f;
  f.name = "div_a";
  f.length = 12.0;
  f.width = 9.0;
  f.penalty_area_depth = 1.8;
  f.penalty_area_width = 3.6;
  f.goal_width = 1.8;
  f.penalty_mark_distance = 8.0;
  f.centre_line = true;
  return f;
}

FieldGeometry parseFieldGeometry(const std::string& yaml_text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    fail(source, std::string("invalid YAML: ") + e.what());
  }
  if (!root.IsMap()) fail(source, "top level must be a map");
  checkKeys(root,
            {"name", "length", "width", "boundary", "line_width", "centre_radius", "penalty_area_depth",
             "penalty_area_width", "goal_width", "goal_depth", "goal_height", "penalty_mark_distance",
             "centre_line", "lines", "arcs"},
            "", source);
  FieldGeometry f;
  f.name = root["name"] ? root["name"].as<std::string>() : source;
  const auto set = [&](const char* key, double& field, double min, double max) {
    if (root[key]) field = number(root[key], key, source, min, max);
  };
  set("length", f.length, 0.5, kMaxFieldSize);
  set("width", f.width, 0.5, kMaxFieldSize);
  set("boundary", f.boundary, 0.0, 10.0);
  set("line_width", f.line_width, 0.001, 0.5);
  set("centre_radius", f.centre_radius, 0.0, kMaxFieldSize);
  set("penalty_area_depth", f.penalty_area_depth, 0.0, kMaxFieldSize);
  set("penalty_area_width", f.penalty_area_width, 0.0, kMaxFieldSize);
  set("goal_width", f.goal_width, 0.0, kMaxFieldSize);
  set("goal_depth", f.goal_depth, 0.0, 10.0);
  set("goal_height", f.goal_height, 0.0, 10.0);
  set("penalty_mark_distance", f.penalty_mark_distance, 0.0, kMaxFieldSize);
  if (root["centre_line"]) {
    try {
      f.centre_line = root["centre_line"].as<bool>();
    } catch (const YAML::Exception&) {
      fail(source, "'centre_line' must be true or false");
    }
  }
  if (f.penalty_area_depth > f.halfLength() || f.penalty_area_width > f.width) {
    fail(source, "the penalty area does not fit in the playing area");
  }
  if (f.centre_radius > f.halfWidth()) fail(source, "the centre circle does not fit in the playing area");

  if (const YAML::Node lines = root["lines"]) {
    if (!lines.IsSequence() || lines.size() > kMaxMarkings)
      fail(source, "'lines' must be a list (at most 1000)");
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const std::string where = " in lines[" + std::to_string(i) + "]";
      if (!lines[i].IsMap()) fail(source, "lines[" + std::to_string(i) + "] must be a map");
      checkKeys(lines[i], {"name", "p1", "p2"}, where, source);
      if (!lines[i]["p1"] || !lines[i]["p2"]) fail(source, "p1 and p2 are required" + where);
      LineSegment s{point(lines[i]["p1"], "p1", source), point(lines[i]["p2"], "p2", source),
                    lines[i]["name"] ? lines[i]["name"].as<std::string>() : "Line" + std::to_string(i)};
      if ((s.a - s.b).norm() < 1e-6) fail(source, "zero-length line" + where);
      f.custom_lines.push_back(s);
    }
  }
  if (const YAML::Node arcs = root["arcs"]) {
    if (!arcs.IsSequence() || arcs.size() > kMaxMarkings)
      fail(source, "'arcs' must be a list (at most 1000)");
    for (std::size_t i = 0; i < arcs.size(); ++i) {
      const std::string where = " in arcs[" + std::to_string(i) + "]";
      if (!arcs[i].IsMap()) fail(source, "arcs[" + std::to_string(i) + "] must be a map");
      checkKeys(arcs[i], {"name", "center", "radius", "a1", "a2"}, where, source);
      if (!arcs[i]["center"] || !arcs[i]["radius"]) fail(source, "center and radius are required" + where);
      CircleArc a{point(arcs[i]["center"], "center", source),
                  number(arcs[i]["radius"], "radius", source, 1e-3, kMaxFieldSize),
                  arcs[i]["name"] ? arcs[i]["name"].as<std::string>() : "Arc" + std::to_string(i)};
      if (arcs[i]["a1"]) a.a1 = number(arcs[i]["a1"], "a1", source, -kTwoPi, kTwoPi);
      if (arcs[i]["a2"]) a.a2 = number(arcs[i]["a2"], "a2", source, -2 * kTwoPi, 2 * kTwoPi);
      if (!(a.a2 > a.a1) || a.a2 - a.a1 > kTwoPi + 1e-9) fail(source, "need a1 < a2 <= a1 + 2 pi" + where);
      f.custom_arcs.push_back(a);
    }
  }
  return f;
}

FieldGeometry loadFieldGeometry(const std::string& path) {
  return parseFieldGeometry(readTextFile(path), path);
}

FieldGeometry fieldGeometryByName(const std::string& name_or_path) {
  if (name_or_path.empty() || name_or_path == "div_b") return FieldGeometry::divB();
  if (name_or_path == "div_a") return FieldGeometry::divA();
  const bool path = name_or_path.find('/') != std::string::npos ||
                    (name_or_path.size() > 5 && name_or_path.substr(name_or_path.size() - 5) == ".yaml");
  if (!path) {
    throw std::runtime_error("unknown field '" + name_or_path +
                             "': the built-in fields are div_b and div_a; else give a YAML file's path");
  }
  return loadFieldGeometry(name_or_path);
}

}  // namespace soccer_vision
