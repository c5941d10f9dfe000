// The fast_motion and flicker_noise presets (issue 4's accuracy gaps):
//  - a frame with motion blur shows the middle of its exposure, its stamp is the start: the
//    tracker takes the measurements at stamp + measurement_offset and outputs at the stamp
//    without a lag of v x offset;
//  - robots that collide or stop dead change velocity within a frame: the robot filter
//    follows (a manoeuvre) instead of coasting on the old velocity;
//  - the synthetic calibration samples where the blurred frame shows the objects and
//    enough frames: the fast ball's streak and the noisy Bayer role markers are classified;
//  - the whole offline pipeline (render -> segment -> identify -> track -> windows) on both
//    presets, scored against the simulator's truth (scoring.h).
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "soccer_vision/evaluation/scoring.h"
#include "soccer_vision/identification/frame_identification.h"
#include "soccer_vision/pipeline/vision_pipeline.h"
#include "soccer_vision/segmentation/segmenter.h"
#include "soccer_vision/simulation/field_renderer.h"
#include "soccer_vision/simulation/game_simulator.h"
#include "soccer_vision/simulation/synthetic_calibration.h"
#include "soccer_vision/tracking/result_recording.h"
#include "soccer_vision/tracking/tracker.h"

using namespace soccer_vision;

namespace {

constexpr double kDt = 1.0 / 60;
constexpr double kT0 = 1700000000.0;
constexpr double kExposure = 0.004;

ScenarioConfig preset(const std::string& name) {
  return loadScenario(std::string(SOCCER_VISION_SOURCE_DIR) + "/config/scenarios/" + name + ".yaml");
}

// One default camera over a preset: renderer, colour table calibrated like the demo's,
// identification and the game, as the tests of rendered frames below need them.
struct PresetRig {
  explicit PresetRig(const std::string& name)
      : scenario(preset(name)),
        patterns(patternSetByName(scenario.pattern)),
        camera(CameraModel::defaultCamera(field, 0, scenario.width, scenario.height)),
        renderer(camera, field, patterns, scenario),
        model(SegmentationModel::fromTable(
            std::make_shared<const ColorTable>(calibrateSyntheticCamera(scenario, 0)))),
        identifier(camera, patterns, field),
        sim(scenario, field, patterns.maxRobotsPerTeam()) {}

  // Renders the simulator's current state as frame k and segments it whole.
  CameraFrameDetections detectWhole(int k) {
    RenderedFrame frame;
    renderer.render(sim.state(), k, frame);
    segmenter.process(*model, frame.image, PixelLayout::Bgr, {}, segmented);
    return identifier.identify(segmented.regions, k * kDt);
  }

  const ScenarioConfig scenario;
  const FieldGeometry field;
  const PatternSet patterns;
  const CameraModel camera;
  const FieldRenderer renderer;
  const std::shared_ptr<const SegmentationModel> model;
  const FrameIdentifier identifier;
  Segmenter segmenter;
  SegmentationResult segmented;
  GameSimulator sim;
};

RobotDetection robotAt(double x, double y) {
  RobotDetection d;
  d.team = Team::Yellow;
  d.id = 2;
  d.x = x;
  d.y = y;
  d.theta = 0;
  d.heading_valid = true;
  d.confidence = 0.9;
  return d;
}

struct LagFigures {
  double robot_mean_error = 0, ball_mean_error = 0;  // [m] along the motion, signed
};

// A robot at 5 m/s and a ball at 15 m/s along +x, each frame measured exactly where they
// are in the middle of a 4 ms exposure; tracked outputs at the capture stamps.
LagFigures constantVelocityLag(double measurement_offset) {
  TrackerParams params;
  params.measurement_offset = measurement_offset;
  Tracker tracker(params);
  const double v_robot = 5.0, v_ball = 15.0;
  LagFigures f;
  int samples = 0;
  for (int k = 0; k < 120; ++k) {
    const double t = k * kDt, shown = t + kExposure / 2;
    CameraFrameDetections frame;
    frame.stamp = kT0 + t;
    frame.robots.push_back(robotAt(-3.0 + v_robot * shown, 0.5));
    BallDetection b;
    b.x = -3.5 + v_ball * shown;
    b.y = -0.5;
    b.confidence = 0.8;
    frame.balls.push_back(b);
    tracker.update(frame);
    const TrackerOutput out = tracker.output(frame.stamp);
    if (k < 60) continue;  // converged
    EXPECT_EQ(out.robots.size(), 1u);
    EXPECT_NE(out.primaryBall(), nullptr);
    if (out.robots.empty() || !out.primaryBall()) continue;
    f.robot_mean_error += out.robots.front().x - (-3.0 + v_robot * t);
    f.ball_mean_error += out.primaryBall()->x - (-3.5 + v_ball * t);
    ++samples;
  }
  f.robot_mean_error /= std::max(samples, 1);
  f.ball_mean_error /= std::max(samples, 1);
  return f;
}

}  // namespace

TEST(MeasurementOffset, RemovesTheLagBiasOfAConstantVelocityTarget) {
  // Taken at the stamp, a mid-exposure measurement is ahead by v x exposure / 2.
  const LagFigures without = constantVelocityLag(0.0);
  EXPECT_NEAR(without.robot_mean_error, 5.0 * kExposure / 2, 0.001);  // 10 mm
  EXPECT_NEAR(without.ball_mean_error, 15.0 * kExposure / 2, 0.002);  // 30 mm
  const LagFigures with = constantVelocityLag(kExposure / 2);
  EXPECT_LT(std::abs(with.robot_mean_error), 0.0002);
  EXPECT_LT(std::abs(with.ball_mean_error), 0.0005);
}

TEST(MeasurementOffset, PerCameraOffsetsReplaceTheDefault) {
  TrackerParams p;
  p.measurement_offset = 0.002;
  p.camera_measurement_offsets[1] = 0.005;
  EXPECT_DOUBLE_EQ(p.measurementOffset(0), 0.002);
  EXPECT_DOUBLE_EQ(p.measurementOffset(1), 0.005);
  Tracker tracker(p);
  CameraFrameDetections f;
  f.stamp = kT0;
  f.camera_id = 1;
  f.robots.push_back(robotAt(0, 0));
  tracker.update(f);
  EXPECT_DOUBLE_EQ(tracker.time(), kT0 + 0.005);  // the filters run on measurement times
  const TrackerOutput out = tracker.output(kT0);
  ASSERT_EQ(out.robots.size(), 1u);
  EXPECT_TRUE(out.robots.front().visible);                  // measured in the frame of this stamp
  EXPECT_DOUBLE_EQ(out.robots.front().last_measured, kT0);  // capture stamps outside
}

TEST(MeasurementOffset, OutOfRangeOffsetsAreRejectedWithTheirName) {
  TrackerParams p;
  p.measurement_offset = 0.5;
  try {
    Tracker t(p);
    FAIL() << "an offset of 0.5 s was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("measurement_offset"), std::string::npos) << e.what();
  }
  p.measurement_offset = 0;
  p.camera_measurement_offsets[3] = std::nan("");
  EXPECT_THROW(Tracker{p}, std::invalid_argument);
}

TEST(Maneuver, RobotStoppingDeadStaysWithinTheMatchDistance) {
  // 5 m/s, then a collision stops it within one frame: 83 mm off the constant-velocity
  // prediction at the next frame, 167 mm at the one after.
  Tracker tracker;
  double x = -2.0, worst_after_stop = 0, final_error = 0;
  for (int k = 0; k < 100; ++k) {
    const double v = k < 60 ? 5.0 : 0.0;
    if (k > 0) x += v * kDt;
    CameraFrameDetections f;
    f.stamp = kT0 + k * kDt;
    f.robots.push_back(robotAt(x, 1.0));
    tracker.update(f);
    const TrackerOutput out = tracker.output(f.stamp);
    ASSERT_EQ(out.robots.size(), 1u) << "frame " << k;
    const double error = std::hypot(out.robots.front().x - x, out.robots.front().y - 1.0);
    if (k >= 60) worst_after_stop = std::max(worst_after_stop, error);
    final_error = error;
  }
  std::printf("dead stop from 5 m/s: worst error %.1f mm, after 40 frames %.2f mm, %ld manoeuvre(s)\n",
              1e3 * worst_after_stop, 1e3 * final_error, tracker.stats().robot_maneuvers);
  EXPECT_LT(worst_after_stop, 0.010);  // the measurement is used at once
  EXPECT_LT(final_error, 0.001);
  EXPECT_GE(tracker.stats().robot_maneuvers, 1);
  EXPECT_EQ(tracker.stats().robot_outliers, 0);
}

TEST(Maneuver, JumpsBeyondAVelocityChangesReachAreStillRejected) {
  RobotFilterParams p;  // maneuver_speed_change 8 m/s: 183 mm reach at 60 Hz
  RobotFilter f(p, {0, 0, 0, true});
  for (int k = 0; k < 30; ++k) {
    f.predict(kDt);
    f.update({0, 0, 0, true});
  }
  f.predict(kDt);
  EXPECT_EQ(f.update({0.25, 0, 0, true}), GateResult::Rejected);
  f.predict(kDt);
  // 0.15 m two frames after the last accepted position: within 8 m/s x 33 ms + 50 mm
  const GateResult g = f.update({0.15, 0, 0, true});
  EXPECT_EQ(g, GateResult::Maneuver);
  EXPECT_NEAR(f.state()(0), 0.15, 0.005);
  EXPECT_GT(f.state()(3), 3.0);  // the velocity follows the jump at once
}

TEST(BlurredCalibration, FastBallStreakIsFoundAtItsMidExposurePosition) {
  // fast_motion: kicked up to 15 m/s, a 4 ms exposure: a 43 mm ball smeared over 60 mm.
  PresetRig rig("fast_motion");
  GameSimulator& sim = rig.sim;
  int fast = 0, found = 0;
  double sq = 0;
  for (int k = 0; k < 600; ++k, sim.step(kDt)) {
    if (k % 3) continue;
    const BallState& truth = sim.state().balls.front();
    const double speed = std::hypot(truth.vx, truth.vy);
    if (speed < 8.0 || !rig.renderer.ballVisible(truth, sim.state().robots)) continue;
    const CameraFrameDetections d = rig.detectWhole(k);
    const BallState mid = extrapolate(sim.state(), shownTimeAfterStamp(rig.scenario.sensor)).balls.front();
    ++fast;
    for (const BallDetection& b : d.balls) {
      const double e = std::hypot(b.x - mid.x, b.y - mid.y);
      if (e < 0.05) {
        ++found;
        sq += e * e;
        break;
      }
    }
  }
  std::printf("ball at >= 8 m/s: found in %d of %d frames, RMSE %.1f mm against the mid-exposure position\n",
              found, fast, 1e3 * std::sqrt(sq / std::max(found, 1)));
  ASSERT_GT(fast, 30);
  EXPECT_GE(found, 0.9 * fast);  // polygons at the exposure start (before): 7 % of all frames
  EXPECT_LT(std::sqrt(sq / std::max(found, 1)), 0.010);
}

// Robots at 3-5 m/s under a 4 ms exposure: their 40 mm role discs are smeared by 12-20 mm,
// only the fully covered core keeps the role colour (a fraction of the expected area).
TEST(BlurredIdentification, FastRobotsAreIdentifiedAtTheirMidExposurePose) {
  PresetRig rig("fast_motion");
  GameSimulator& sim = rig.sim;
  int fast = 0, found = 0;
  double sq = 0, sq_at_stamp = 0;
  for (int k = 0; k < 600; ++k, sim.step(kDt)) {
    if (k % 2) continue;
    const CameraFrameDetections d = rig.detectWhole(k);
    const SceneState mid = extrapolate(sim.state(), shownTimeAfterStamp(rig.scenario.sensor));
    for (std::size_t i = 0; i < mid.robots.size(); ++i) {
      const RobotState& r = mid.robots[i];
      if (std::hypot(r.vx, r.vy) < 3.0 || !rig.renderer.robotVisible(sim.state().robots[i])) continue;
      ++fast;
      for (const RobotDetection& det : d.robots) {
        if (det.team != r.team || det.id != r.id) continue;
        const double e = std::hypot(det.x - r.x, det.y - r.y);
        if (e > 0.05) continue;
        ++found;
        sq += e * e;
        sq_at_stamp +=
            std::pow(det.x - sim.state().robots[i].x, 2) + std::pow(det.y - sim.state().robots[i].y, 2);
        break;
      }
    }
  }
  const double rmse = std::sqrt(sq / std::max(found, 1)),
               rmse_at_stamp = std::sqrt(sq_at_stamp / std::max(found, 1));
  std::printf(
      "robots at >= 3 m/s: identified in %d of %d cases; RMSE %.2f mm against the mid-exposure pose, %.1f mm "
      "against the pose at the stamp\n",
      found, fast, 1e3 * rmse, 1e3 * rmse_at_stamp);
  ASSERT_GT(fast, 300);
  EXPECT_GE(found, 0.985 * fast);
  EXPECT_LT(rmse, 0.001);           // the centroids are where the robots were mid-exposure ...
  EXPECT_GT(rmse_at_stamp, 0.006);  // ... 8-10 mm ahead of where they were at the stamp
}

namespace {

// The in-process pipeline of one camera over a preset (VisionPipeline: windows fed back,
// as in the nodelets), scored against the simulator's truth at every capture stamp after
// the first 30 frames.
Score runPipeline(const std::string& name, int frames) {
  PresetRig rig(name);
  const ScenarioConfig& scenario = rig.scenario;
  PipelineCamera camera;
  camera.model = rig.camera;
  camera.segmentation = rig.model;
  camera.layout = scenario.sensor.bayer.empty()
                      ? PixelLayout::Bgr
                      : *pixelLayoutForEncoding("bayer_" + scenario.sensor.bayer + "8");
  VisionPipelineParams params;
  params.tracker.measurement_offset = shownTimeAfterStamp(scenario.sensor);
  VisionPipeline pipeline({camera}, rig.patterns, rig.field, params);
  const double interval = 1.0 / scenario.fps;
  Score total;
  for (int i = 0; i < frames; ++i, rig.sim.step(interval)) {
    const SceneState& s = rig.sim.state();
    RenderedFrame f;
    rig.renderer.render(s, i, f);
    const PipelineFrame out = pipeline.process(0, f.image, s.time);
    if (i < 30) continue;
    FrameRecord truth;
    truth.stamp = s.time;
    for (const RobotState& r : s.robots)
      truth.robots.push_back({r.team, r.id, r.x, r.y, r.theta, rig.renderer.robotVisible(r), {}});
    for (const BallState& b : s.balls)
      truth.balls.push_back({b.x, b.y, rig.renderer.ballVisible(b, s.robots), {}});
    total.add(scoreFrame(truth, toFrameRecord(out.output)));
  }
  std::printf(
      "%s, %d frames: robots %.2f %% found, %.2f %% precise, %ld identity errors, RMSE %.2f mm, heading "
      "%.2f deg; ball %.2f %% / %.2f %%, RMSE %.1f mm\n",
      scenario.name.c_str(), frames, 100 * total.robotDetectionRate(), 100 * total.robotPrecision(),
      static_cast<long>(total.identity_errors), 1e3 * total.robotPositionRmse(),
      total.robotHeadingRmse() * 180 / M_PI, 100 * total.ballDetectionRate(), 100 * total.ballPrecision(),
      1e3 * total.ballPositionRmse());
  return total;
}

}  // namespace

// Issue 4's targets for these presets: >= 99.7 % found, >= 99.9 % precise, no identity
// error. Before: fast_motion 99.45 % / 99.45 %, 6.1 mm, ball 20 % (collisions coasted
// through, stamps taken as measurement times, ball calibrated on its streak's tail);
// flicker_noise 97.2 % / 97.9 % (6 calibration frames).
TEST(PresetPipeline, FastMotion) {
  const Score s = runPipeline("fast_motion", 600);
  EXPECT_GE(s.robotDetectionRate(), 0.997);
  EXPECT_GE(s.robotPrecision(), 0.999);
  EXPECT_EQ(s.identity_errors, 0);
  EXPECT_LT(s.robotPositionRmse(), 0.003);  // 6 mm with the stamp taken as the measurement time
  EXPECT_GE(s.ballDetectionRate(), 0.97);
  EXPECT_LT(s.ballPositionRmse(), 0.008);
  // Issue 4's heading target: 1.05° before heading manoeuvres (turn starts lost for frames).
  EXPECT_LT(s.robotHeadingRmse(), 1.0 * M_PI / 180);
}

// The markers' brightness variants (ColorTableParams::brightness_spread, 2026-12-04) cost
// this preset 99.88 -> 99.78 % found and 0 -> 1 identity error in 600 frames (blue's variants
// reach towards sky blue under its flicker and noise); leaving blue and sky blue out of them
// removes it but misses 75 more robots on the randomised tuning recordings, which is the
// trade docs/segmentation.md records.
TEST(PresetPipeline, FlickerNoise) {
  const Score s = runPipeline("flicker_noise", 600);
  EXPECT_GE(s.robotDetectionRate(), 0.997);
  EXPECT_GE(s.robotPrecision(), 0.999);
  EXPECT_LE(s.identity_errors, 1);
  EXPECT_LT(s.robotPositionRmse(), 0.005);
  EXPECT_GE(s.ballDetectionRate(), 0.97);
  // Issue 4's heading target is 1°: 1.55° when a Bayer quad's coverage was placed at its
  // centre, 0.92° with a larger team-tag axis weight for it, 0.44° since each of its sensor
  // sites weighs its own coverage at its own position (region_moments.cpp).
  EXPECT_LT(s.robotHeadingRmse(), 0.7 * M_PI / 180);
}
