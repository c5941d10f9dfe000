// The Division A field (config/fields/div_a.yaml, 12 x 9 m): the renderer draws it and
// identification finds robots and the ball where a Division B field has no carpet (beyond
// x = ±4.5 m), on one rendered frame per camera (render -> colour table from the frame's
// sample polygons -> segmentation -> identification through the true camera).
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "soccer_vision/calibration/color_calibration.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/identification/frame_identification.h"
#include "soccer_vision/segmentation/segmenter.h"
#include "soccer_vision/simulation/calibration_samples.h"
#include "soccer_vision/simulation/field_renderer.h"
#include "support/scene_objects.h"

using namespace soccer_vision;
using soccer_vision::test::robotState;

namespace {

// The scene on one camera's half (side -1: negative x), everything beyond 4.5 m but the
// control robot at 3 m; what identification found through the true camera.
CameraFrameDetections identifyHalf(const FieldGeometry& field, const FieldGeometry& identification_field,
                                   int side, SceneState& scene) {
  const double s = side;
  scene.robots = {robotState(Team::Blue, 0, s * 5.2, 1.0, 0.3), robotState(Team::Blue, 1, s * 4.8, -2.0, 2.0),
                  robotState(Team::Yellow, 0, s * 5.3, -0.5, -1.2),
                  robotState(Team::Yellow, 1, s * 3.0, 0.5, 1.0)};
  BallState ball;
  ball.x = s * 5.35;
  ball.y = 1.8;
  scene.balls = {ball};
  const PatternSet patterns = PatternSet::twoTag();
  const CameraModel camera = CameraModel::defaultCamera(field, side < 0 ? 0 : 1);
  ScenarioConfig scenario;
  scenario.field = field.name;
  const FieldRenderer renderer(camera, field, patterns, scenario);
  for (const RobotState& r : scene.robots) EXPECT_TRUE(renderer.robotVisible(r)) << r.x;
  EXPECT_TRUE(renderer.ballVisible(scene.balls[0], scene.robots));
  RenderedFrame frame;
  renderer.render(scene, 0, frame);
  SampleOptions options;
  options.shrink = 0.85;
  ColorTableParams params;
  params.s_bins = 8;
  params.v_bins = 8;
  const auto table = std::make_shared<const ColorTable>(calibrateColorTable(
      {{frame.image, calibrationSamples(scene, camera, field, patterns, options)}}, params));
  Segmenter segmenter;
  SegmentationResult seg;
  segmenter.process(*SegmentationModel::fromTable(table), frame.image, PixelLayout::Bgr, {}, seg);
  return FrameIdentifier(camera, patterns, identification_field).identify(seg.regions);
}

}  // namespace

TEST(DivisionAField, RobotsAndBallBeyondTheDivisionBFieldAreFound) {
  const FieldGeometry div_a = fieldGeometryByName("div_a");
  ASSERT_DOUBLE_EQ(div_a.length, 12.0);
  ASSERT_DOUBLE_EQ(div_a.width, 9.0);
  for (int side : {-1, 1}) {
    SceneState scene;
    const CameraFrameDetections d = identifyHalf(div_a, div_a, side, scene);
    ASSERT_EQ(d.robots.size(), scene.robots.size())
        << "side " << side << ", rejected " << d.rejections.summary();
    double worst = 0;
    for (const RobotState& t : scene.robots) {
      int matches = 0;
      for (const RobotDetection& r : d.robots) {
        if (r.team != t.team || r.id != t.id) continue;
        ++matches;
        worst = std::max(worst, std::hypot(r.x - t.x, r.y - t.y));
      }
      EXPECT_EQ(matches, 1) << teamName(t.team) << " " << t.id << " at x " << t.x;
    }
    EXPECT_LT(worst, 0.003);
    ASSERT_EQ(d.balls.size(), 1u) << d.rejections.summary();
    EXPECT_LT(std::hypot(d.balls[0].x - scene.balls[0].x, d.balls[0].y - scene.balls[0].y), 0.003);
    std::printf("[ div_a, side %+d ] %zu robots beyond 4.5 m found, worst %.2f mm; ball at x %.3f\n", side,
                d.robots.size() - 1, 1000 * worst, d.balls[0].x);
  }
}

// The same picture judged on a Division B field: its ball at x = -5.35 m is off the carpet (4.8 m + 0.1 m
// margin).
TEST(DivisionAField, ADivisionBFieldRejectsTheBallBeyondItsCarpet) {
  SceneState scene;
  const CameraFrameDetections d =
      identifyHalf(fieldGeometryByName("div_a"), FieldGeometry::divB(), -1, scene);
  EXPECT_TRUE(d.balls.empty());
  EXPECT_EQ(d.rejections[RejectionCause::BallOffField], 1) << d.rejections.summary();
}
