// The field model drawn into a camera image and the landmarks offered for field calibration.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "soccer_vision/ui/field_overlay.h"

namespace soccer_vision {
namespace {

// Distance of a carpet point from the nearest painted line or arc.
double distanceToMarkings(const FieldGeometry& field, const Eigen::Vector2d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const LineSegment& l : field.lines()) {
    const Eigen::Vector2d d = l.b - l.a;
    const double t = std::clamp((p - l.a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (l.a + t * d - p).norm());
  }
  for (const CircleArc& a : field.circles()) best = std::min(best, a.distance(p));
  return best;
}

TEST(FieldOverlay, ProjectedMarkingsLieOnThePaintAndInsideTheImage) {
  const FieldGeometry field = FieldGeometry::divB();
  const CameraModel camera = CameraModel::defaultCamera(field, 0);
  const std::vector<PixelPolyline> lines = projectFieldMarkings(camera, field, 0.05);
  ASSERT_GE(lines.size(), 8u);  // touch lines, goal line, halfway line, penalty area, centre circle
  std::size_t points = 0;
  for (const PixelPolyline& line : lines) {
    ASSERT_GE(line.size(), 2u);
    for (const Eigen::Vector2d& px : line) {
      ASSERT_TRUE(camera.inImage(px)) << px.transpose();
      const auto back = camera.pixelToField(px, 0.0);
      ASSERT_TRUE(back.has_value());
      EXPECT_LT(distanceToMarkings(field, back->head<2>()), 1e-6) << back->transpose();
      ++points;
    }
  }
  EXPECT_GT(points, 300u);  // sampled every 5 cm: curved by the distortion as the paint is
}

TEST(FieldOverlay, AnotherPoseMovesTheLines) {
  const FieldGeometry field = FieldGeometry::divB();
  const CameraModel camera = CameraModel::defaultCamera(field, 0);
  Eigen::Isometry3d shifted = camera.fieldTCamera();
  shifted.translation().x() += 0.2;
  const CameraModel moved(camera.intrinsics(), shifted);
  const auto a = projectFieldMarkings(camera, field);
  const auto b = projectFieldMarkings(moved, field);
  ASSERT_FALSE(a.empty());
  ASSERT_FALSE(b.empty());
  EXPECT_GT((a.front().front() - b.front().front()).norm(), 10.0);  // 0.2 m at ~4 m height: tens of px
}

TEST(FieldOverlay, LandmarksInViewCarryTheirPixels) {
  const FieldGeometry field = FieldGeometry::divB();
  const CameraModel camera = CameraModel::defaultCamera(field, 0);
  const auto with_camera = suggestLandmarks(field, &camera);
  const auto without = suggestLandmarks(field, nullptr);
  ASSERT_EQ(with_camera.size(), field.landmarks().size());
  ASSERT_EQ(without.size(), field.landmarks().size());
  int in_view = 0;
  for (std::size_t i = 0; i < with_camera.size(); ++i) {
    EXPECT_FALSE(without[i].pixel.has_value());
    const auto& s = with_camera[i];
    if (!s.pixel) {
      EXPECT_GT(s.field.x(), 0.5) << "camera 0 sees the half x < 0: " << s.field.transpose();
      continue;
    }
    ++in_view;
    EXPECT_LT((*s.pixel - *camera.project(s.field)).norm(), 1e-9);
  }
  EXPECT_GE(in_view, 4);  // enough to solve a pose from
}

}  // namespace
}  // namespace soccer_vision
