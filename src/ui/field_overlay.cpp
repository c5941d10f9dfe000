#include "soccer_vision/ui/field_overlay.h"

#include <algorithm>
#include <cmath>

namespace soccer_vision {

namespace {

// Far outside the view, a distortion polynomial can fold a point back into the image: only
// points whose ideal pinhole pixel lies near the image are drawn.
bool nearTheImage(const CameraModel& camera, const Eigen::Vector3d& point) {
  const std::optional<Eigen::Vector2d> ideal = camera.projectUndistorted(point);
  if (!ideal) return false;
  const double w = camera.width(), h = camera.height();
  return ideal->x() > -0.5 * w && ideal->x() < 1.5 * w && ideal->y() > -0.5 * h && ideal->y() < 1.5 * h;
}

// Appends the visible runs of the projected field points as polylines.
void appendVisibleRuns(const CameraModel& camera, const std::vector<Eigen::Vector2d>& field_points,
                       double margin, std::vector<PixelPolyline>& out) {
  PixelPolyline run;
  for (const Eigen::Vector2d& p : field_points) {
    const Eigen::Vector3d point(p.x(), p.y(), 0.0);
    const std::optional<Eigen::Vector2d> px = camera.projectInImage(point, -margin);
    if (px && nearTheImage(camera, point)) {
      run.push_back(*px);
    } else {
      if (run.size() >= 2) out.push_back(run);
      run.clear();
    }
  }
  if (run.size() >= 2) out.push_back(run);
}

}  // namespace

std::vector<PixelPolyline> projectFieldMarkings(const CameraModel& camera, const FieldGeometry& field,
                                                double step, double margin) {
  step = std::max(step, 1e-3);
  std::vector<PixelPolyline> out;
  for (const LineSegment& line : field.lines()) {
    const int n = std::max(1, static_cast<int>(std::ceil((line.b - line.a).norm() / step)));
    std::vector<Eigen::Vector2d> points;
    for (int i = 0; i <= n; ++i) points.push_back(line.a + (line.b - line.a) * (static_cast<double>(i) / n));
    appendVisibleRuns(camera, points, margin, out);
  }
  for (const CircleArc& arc : field.circles()) {
    const int n = std::max(8, static_cast<int>(std::ceil(std::abs(arc.a2 - arc.a1) * arc.radius / step)));
    appendVisibleRuns(camera, arc.points(n), margin, out);
  }
  return out;
}

std::vector<LandmarkSuggestion> suggestLandmarks(const FieldGeometry& field, const CameraModel* camera) {
  std::vector<LandmarkSuggestion> out;
  for (const Eigen::Vector3d& p : field.landmarks()) {
    LandmarkSuggestion s{p, std::nullopt};
    if (camera) {
      const std::optional<Eigen::Vector2d> px = camera->projectInImage(p);
      if (px && nearTheImage(*camera, p)) s.pixel = *px;
    }
    out.push_back(s);
  }
  return out;
}

}  // namespace soccer_vision
