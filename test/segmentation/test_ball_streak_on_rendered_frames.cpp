// A kicked ball (issue 14): 12 m/s over a 6 ms exposure is a streak 72 mm longer than the
// ball, no pixel of which shows the ball for more than 60 % of the exposure. Calibrated
// from one frame as a user does (rand_fast, its tuning seed), the colour table's orange
// misses such streaks; in the ball's window the streak table finds them where the frame
// shows the ball (mid-exposure), and nothing else there becomes a ball.
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "soccer_vision/calibration/color_calibration.h"
#include "soccer_vision/identification/frame_identification.h"
#include "soccer_vision/segmentation/segmenter.h"
#include "soccer_vision/simulation/calibration_samples.h"
#include "soccer_vision/simulation/field_renderer.h"
#include "soccer_vision/simulation/game_simulator.h"
#include "soccer_vision/simulation/scenario_camera.h"

using namespace soccer_vision;

TEST(BallStreakOnRenderedFrames, AKickedBallIsFoundInItsWindowAndNothingElseIs) {
  const ScenarioConfig scenario =
      loadScenario(std::string(SOCCER_VISION_SOURCE_DIR) + "/config/scenarios/rand_fast.yaml");
  const FieldGeometry field;
  const PatternSet patterns = patternSetByName(scenario.pattern);
  const CameraModel camera = scenarioCamera(field, 0, scenario);
  GameSimulator sim(scenario, field, patterns.maxRobotsPerTeam());
  const FieldRenderer renderer(camera, field, patterns, scenario);
  ASSERT_EQ(renderer.encoding(), "bgr8");
  const double shown = shownTimeAfterStamp(scenario.sensor);
  ASSERT_GT(shown, 0.0);  // blurred: the frame shows mid-exposure

  // One frame, polygons 2 px inside each marker where the frame shows them.
  RenderedFrame frame;
  renderer.render(sim.state(), 0, frame);
  const SampleOptions drawn = SampleOptions::drawnByUser(2);
  const ColorSamples samples =
      calibrationSamples(extrapolate(sim.state(), shown), camera, field, patterns, drawn);
  ASSERT_FALSE(samples.at(ColorClass::Orange).empty());
  const auto model = SegmentationModel::fromTable(
      std::make_shared<const ColorTable>(calibrateColorTable({{frame.image, samples}})));
  ASSERT_TRUE(model->streak_classifier);
  const FrameIdentifier identifier(camera, patterns, field);

  int kicks = 0, found_with = 0, found_without = 0, false_with = 0;
  double error_sum = 0;
  for (double x : {-3.6, -2.8, -2.0, -1.2}) {
    for (double y : {-2.2, -1.1, 0.0, 1.1, 2.2}) {
      for (int direction = 0; direction < 8; direction += 3) {
        SceneState scene = sim.state();
        bool clear = true;  // a ball rolling into a robot would be hidden
        for (const RobotState& r : scene.robots) clear = clear && std::hypot(r.x - x, r.y - y) > 0.35;
        if (!clear) continue;
        const double a = direction * M_PI / 4;
        BallState ball;
        ball.x = x;
        ball.y = y;
        ball.vx = 12 * std::cos(a);
        ball.vy = 12 * std::sin(a);
        scene.balls = {ball};
        renderer.render(scene, kicks + 1, frame);
        const Eigen::Vector2d truth(x + ball.vx * shown, y + ball.vy * shown);
        const auto pixel = camera.project({truth.x(), truth.y(), ball.z});
        ASSERT_TRUE(pixel);
        // The tracker's window: 200 px around a prediction some pixels off.
        const cv::Rect window(static_cast<int>(pixel->x()) - 80, static_cast<int>(pixel->y()) - 120, 200,
                              200);
        ++kicks;
        for (bool streaks : {true, false}) {
          Segmenter segmenter;
          SegmentationResult segmented;
          segmenter.process(*model, frame.image, PixelLayout::Bgr, {window}, segmented,
                            streaks ? std::vector<cv::Rect>{window} : std::vector<cv::Rect>{});
          const CameraFrameDetections seen = identifier.identify(segmented.regions, 0, 0, false);
          bool found = false;
          for (const BallDetection& b : seen.balls) {
            const double error = std::hypot(b.x - truth.x(), b.y - truth.y());
            if (error < 0.02 && !found) {
              found = true;
              if (streaks) error_sum += error;
            } else if (streaks) {
              ++false_with;
            }
          }
          (streaks ? found_with : found_without) += found;
        }
      }
    }
  }
  std::printf(
      "kicked balls at 12 m/s: %d, found %d with the streak table (mean error %.1f mm), %d without; "
      "%d other candidates\n",
      kicks, found_with, 1e3 * error_sum / std::max(1, found_with), found_without, false_with);
  ASSERT_GE(kicks, 30);
  EXPECT_GE(found_with, 0.95 * kicks);
  EXPECT_LE(found_without, 0.5 * kicks);  // what the streak table is for
  EXPECT_LT(error_sum / std::max(1, found_with), 0.008);
  EXPECT_EQ(false_with, 0);
}
