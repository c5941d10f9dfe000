#include "soccer_vision/common/field_markings_image.h"

#include <algorithm>
#include <cmath>

namespace soccer_vision {

std::vector<std::vector<Eigen::Vector2d>> fieldMarkingPolylines(const FieldGeometry& field, double step) {
  std::vector<std::vector<Eigen::Vector2d>> out;
  for (const LineSegment& l : field.lines()) {
    const int n = std::max(1, static_cast<int>(std::ceil((l.b - l.a).norm() / step)));
    std::vector<Eigen::Vector2d> line;
    for (int i = 0; i <= n; ++i) line.push_back(l.a + (l.b - l.a) * (static_cast<double>(i) / n));
    out.push_back(std::move(line));
  }
  for (const CircleArc& c : field.circles()) {
    const int n = std::max(2, static_cast<int>(std::ceil(c.radius * std::abs(c.a2 - c.a1) / step)));
    out.push_back(c.points(n));
  }
  return out;
}

std::vector<std::vector<Eigen::Vector2d>> projectFieldMarkings(const CameraModel& camera,
                                                               const FieldGeometry& field, double step,
                                                               double margin) {
  std::vector<std::vector<Eigen::Vector2d>> out;
  for (const auto& polyline : fieldMarkingPolylines(field, step)) {
    std::vector<Eigen::Vector2d> piece;
    for (const Eigen::Vector2d& p : polyline) {
      const auto px = camera.projectInImage({p.x(), p.y(), 0.0}, -margin);
      if (px) {
        piece.push_back(*px);
        continue;
      }
      if (piece.size() > 1) out.push_back(piece);
      piece.clear();
    }
    if (piece.size() > 1) out.push_back(piece);
  }
  return out;
}

}  // namespace soccer_vision
