// What the simulated user paints (calibration_samples.h): every marker of a robot wholly in
// view (one the ground truth counts), however near the image's border. Until 2026-12-07
// polygons within 8 px of the border were skipped, and held-out seed 9075's purple dot, 6.5 px
// from the lower border all recording, was never sampled: the table had no purple, and blue 1
// was read as blue 0 in every frame.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "soccer_vision/simulation/calibration_samples.h"

using namespace soccer_vision;

namespace {

// Pixels of robot `r`'s marker outlines.
std::vector<Eigen::Vector2d> outlinePixels(const CameraModel& camera, const PatternSet& patterns,
                                           const RobotState& r) {
  std::vector<Eigen::Vector2d> out;
  for (const Eigen::Vector3d& p : markerOutlinePoints(patterns, r.team, r.id, r.x, r.y, r.theta)) {
    const auto px = camera.project(p);
    EXPECT_TRUE(px);
    if (px) out.push_back(*px);
  }
  return out;
}

double lowestRow(const std::vector<Eigen::Vector2d>& pixels) {
  double lowest = -1;
  for (const Eigen::Vector2d& px : pixels) lowest = std::max(lowest, px.y());
  return lowest;
}

}  // namespace

TEST(CalibrationSamples, AUserPaintsAMarkerWhollyInViewAtTheImageBorder) {
  const FieldGeometry field;
  const PatternSet patterns = PatternSet::twoTag();
  const CameraModel camera = CameraModel::defaultCamera(field, 0);
  const double z = patterns.height(Team::Blue);
  // Blue 1 (purple dot) below the image's middle, heading down the image.
  const auto near = camera.pixelToField({640, camera.height() - 60.0}, z);
  const auto nearer = camera.pixelToField({640, camera.height() - 20.0}, z);
  ASSERT_TRUE(near && nearer);
  const Eigen::Vector3d down = (*nearer - *near).normalized();
  RobotState robot;
  robot.team = Team::Blue;
  robot.id = 1;
  robot.theta = std::atan2(down.y(), down.x());
  robot.x = near->x();
  robot.y = near->y();
  // Moved down in 0.5 mm steps while every marker outline stays 1.5 px inside the image.
  const double last_row = camera.height() - 0.5;
  for (double s = 0; s < 0.5; s += 0.0005) {
    RobotState moved = robot;
    moved.x = near->x() + s * down.x();
    moved.y = near->y() + s * down.y();
    if (lowestRow(outlinePixels(camera, patterns, moved)) > last_row - 1.5) break;
    robot = moved;
  }
  const auto pixels = outlinePixels(camera, patterns, robot);
  for (const Eigen::Vector2d& px : pixels) ASSERT_TRUE(camera.inImage(px)) << px.transpose();
  EXPECT_GT(lowestRow(pixels), last_row - 2.0);  // the dot's rim within 2 px of the border

  SceneState scene;
  scene.robots.push_back(robot);
  const ColorSamples drawn =
      calibrationSamples(scene, camera, field, patterns, SampleOptions::drawnByUser(2));
  ASSERT_EQ(drawn.count(ColorClass::Purple), 1u);
  ASSERT_EQ(drawn.at(ColorClass::Purple).size(), 1u);
  for (const Eigen::Vector2d& p : drawn.at(ColorClass::Purple).front()) {
    EXPECT_TRUE(camera.inImage(p));
    EXPECT_GT(p.y(), last_row - 12.0);  // the dot's polygon near the border indeed
  }
  EXPECT_EQ(drawn.count(ColorClass::Blue), 1u);

  // The synthetic calibration's polygons (SampleOptions{}) keep 8 px off the border.
  EXPECT_EQ(calibrationSamples(scene, camera, field, patterns).count(ColorClass::Purple), 0u);
}
