#include "soccer_vision/common/field_geometry.h"

#include <cmath>

namespace soccer_vision {

std::vector<LineSegment> FieldGeometry::lines() const {
  const double hl = halfLength(), hw = halfWidth();
  std::vector<LineSegment> l = {
      {{-hl, -hw}, {hl, -hw}},                           // touch lines
      {{-hl, hw}, {hl, hw}},   {{-hl, -hw}, {-hl, hw}},  // goal lines
      {{hl, -hw}, {hl, hw}},   {{0, -hw}, {0, hw}},      // halfway line
  };
  // Defence areas: rectangles defense_depth x defense_width in front of each goal.
  const double dw = defense_width / 2;
  for (double side : {-1.0, 1.0}) {
    const double gx = side * hl, fx = side * (hl - defense_depth);
    l.push_back({{gx, -dw}, {fx, -dw}});
    l.push_back({{gx, dw}, {fx, dw}});
    l.push_back({{fx, -dw}, {fx, dw}});
  }
  return l;
}

std::vector<CircleArc> FieldGeometry::circles() const { return {{{0.0, 0.0}, centre_radius}}; }

std::vector<Eigen::Vector3d> FieldGeometry::landmarks() const {
  const double hl = halfLength(), hw = halfWidth(), dw = defense_width / 2;
  std::vector<Eigen::Vector3d> p = {
      {0, 0, 0}, {0, -hw, 0}, {0, hw, 0}, {0, -centre_radius, 0}, {0, centre_radius, 0}};
  for (double side : {-1.0, 1.0}) {
    const double gx = side * hl, fx = side * (hl - defense_depth);
    for (double y : {-hw, hw}) p.emplace_back(gx, y, 0);  // field corners
    for (double y : {-dw, dw}) p.emplace_back(gx, y, 0);  // defence area on the goal line
    for (double y : {-dw, dw}) p.emplace_back(fx, y, 0);  // defence area front corners
  }
  return p;
}

bool FieldGeometry::onCarpet(double x, double y, double margin) const {
  return std::abs(x) <= halfLength() + boundary + margin && std::abs(y) <= halfWidth() + boundary + margin;
}

}  // namespace soccer_vision
