// Identification on frames of the synthetic camera (the best test: real anti-aliasing,
// noise, uneven light and perspective): render -> colour table calibrated on the
// simulator's sample polygons -> segmentation -> identification with a camera pose solved
// from the field landmarks -> compared with the ground-truth SceneState.
//
// Per preset: detection rate over the robots the renderer calls visible (all markers in
// the image), false positives (a detection with no true robot of that team and id within
// 50 mm), wrong ids (a detection within 50 mm of a true robot of another team/id), and
// position / heading errors; the ball the same way.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "soccer_vision/calibration_samples.h"
#include "soccer_vision/camera_pose_solver.h"
#include "soccer_vision/color_calibration.h"
#include "soccer_vision/field_renderer.h"
#include "soccer_vision/frame_identification.h"
#include "soccer_vision/game_simulator.h"
#include "soccer_vision/rigid_fit_2d.h"
#include "soccer_vision/segmenter.h"

using namespace soccer_vision;

namespace {

struct Figures {
  int visible = 0, found = 0, false_positives = 0, wrong_ids = 0, detections = 0;
  int balls_visible = 0, balls_found = 0, ball_false = 0;
  std::vector<double> position_mm, heading_deg, ball_mm;

  static double rms(const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x * x;
    return v.empty() ? 0 : std::sqrt(s / v.size());
  }
  static double quantile(std::vector<double> v, double q) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(q * (v.size() - 1))];
  }
  double rate() const { return visible ? static_cast<double>(found) / visible : 0; }
};

// `frames` frames `step_s` apart of `scenario`, both cameras.
Figures measure(const ScenarioConfig& scenario, int frames, double step_s) {
  const FieldGeometry field;
  const PatternSet patterns = patternSetByName(scenario.pattern);
  GameSimulator sim(scenario, field, patterns.maxRobotsPerTeam());
  std::vector<std::unique_ptr<FieldRenderer>> renderers;
  for (int c = 0; c < 2; ++c) {
    renderers.push_back(std::make_unique<FieldRenderer>(
        CameraModel::defaultCamera(field, c, scenario.width, scenario.height), field, patterns, scenario));
  }
  // Calibration as a user would do it: a few frames of each camera, before the test frames.
  std::vector<CalibrationImage> calibration;
  for (int k = 0; k < 3; ++k) {
    for (const auto& r : renderers) {
      RenderedFrame f;
      r->render(sim.state(), k, f);
      calibration.push_back({f.image.clone(), calibrationSamples(sim.state(), r->camera(), field, patterns)});
    }
    sim.step(1.0);
  }
  const auto model = SegmentationModel::fromTable(std::make_shared<const ColorTable>(calibrateColorTable(calibration)));

  // The identification camera: intrinsics as published, pose solved from the landmarks.
  std::vector<FrameIdentifier> identifiers;
  for (const auto& r : renderers) {
    const CameraIntrinsics& k = r->camera().intrinsics();
    identifiers.emplace_back(solveCameraPose(k, fieldCorrespondences(r->camera(), field)).model(), patterns, field);
  }

  Figures fig;
  Segmenter segmenter;
  SegmentationResult seg;
  std::int64_t index = 100;
  for (int f = 0; f < frames; ++f) {
    const int steps = std::max(1, static_cast<int>(std::lround(step_s * scenario.fps)));
    for (int i = 0; i < steps; ++i) sim.step(1.0 / scenario.fps);
    index += steps;
    const SceneState& scene = sim.state();
    for (std::size_t c = 0; c < renderers.size(); ++c) {
      RenderedFrame frame;
      renderers[c]->render(scene, index, frame);
      segmenter.process(*model, frame.image, PixelLayout::Bgr, {}, seg);
      const CameraFrameDetections det = identifiers[c].identify(seg.regions, scene.time, static_cast<int>(c));
      fig.detections += static_cast<int>(det.robots.size());
      for (const RobotState& t : scene.robots) {
        if (!renderers[c]->robotVisible(t)) continue;
        ++fig.visible;
        for (const RobotDetection& d : det.robots) {
          if (d.team != t.team || d.id != t.id) continue;
          ++fig.found;
          fig.position_mm.push_back(1000 * std::hypot(d.x - t.x, d.y - t.y));
          fig.heading_deg.push_back(std::abs(angleDifference(d.theta, t.theta)) * 180 / M_PI);
          break;
        }
      }
      for (const RobotDetection& d : det.robots) {
        bool right = false, wrong = false;
        for (const RobotState& t : scene.robots) {
          if (std::hypot(d.x - t.x, d.y - t.y) > 0.05) continue;
          (d.team == t.team && d.id == t.id ? right : wrong) = true;
        }
        fig.false_positives += !right;
        fig.wrong_ids += wrong && !right;
      }
      for (const BallState& b : scene.balls) {
        if (!renderers[c]->ballVisible(b)) continue;
        ++fig.balls_visible;
        if (!det.balls.empty() && std::hypot(det.balls[0].x - b.x, det.balls[0].y - b.y) < 0.05) {
          ++fig.balls_found;
          fig.ball_mm.push_back(1000 * std::hypot(det.balls[0].x - b.x, det.balls[0].y - b.y));
        }
      }
      for (const BallDetection& d : det.balls) {
        bool near = false;
        for (const BallState& b : scene.balls) near = near || std::hypot(d.x - b.x, d.y - b.y) < 0.05;
        fig.ball_false += !near;
      }
    }
  }
  std::printf("[ %s ] %d frames x 2 cameras: robots found %d / %d (%.2f %%), false positives %d of %d detections, "
              "wrong ids %d\n",
              scenario.name.c_str(), frames, fig.found, fig.visible, 100 * fig.rate(), fig.false_positives,
              fig.detections, fig.wrong_ids);
  std::printf("[ %s ] position error RMS %.2f mm, 95 %% %.2f mm, max %.2f mm; heading error RMS %.3f deg, 95 %% %.3f deg, "
              "max %.3f deg\n",
              scenario.name.c_str(), Figures::rms(fig.position_mm), Figures::quantile(fig.position_mm, 0.95),
              Figures::quantile(fig.position_mm, 1.0), Figures::rms(fig.heading_deg),
              Figures::quantile(fig.heading_deg, 0.95), Figures::quantile(fig.heading_deg, 1.0));
  std::printf("[ %s ] ball found %d / %d, position error RMS %.2f mm, max %.2f mm; %d ball candidates not at a ball\n",
              scenario.name.c_str(), fig.balls_found, fig.balls_visible, Figures::rms(fig.ball_mm),
              Figures::quantile(fig.ball_mm, 1.0), fig.ball_false);
  return fig;
}

void expectTargets(const Figures& f, double max_heading_rms = 1.0) {
  ASSERT_GT(f.visible, 20);
  EXPECT_EQ(f.found, f.visible);
  EXPECT_EQ(f.false_positives, 0);
  EXPECT_EQ(f.wrong_ids, 0);
  EXPECT_LT(Figures::quantile(f.position_mm, 1.0), 5.0);
  EXPECT_LT(Figures::rms(f.heading_deg), max_heading_rms);
  EXPECT_LT(Figures::quantile(f.heading_deg, 1.0), 3.0);
}

ScenarioConfig preset(const std::string& name) {
  return loadScenario(std::string(SOCCER_VISION_SOURCE_DIR) + "/config/scenarios/" + name + ".yaml");
}

}  // namespace

TEST(IdentificationOnRenderedFrames, TwoTagEvenLightStill) {
  const Figures f = measure(preset("even_static"), 4, 0.5);
  expectTargets(f);
  EXPECT_EQ(f.balls_found, f.balls_visible);
}

TEST(IdentificationOnRenderedFrames, TwoTagUnevenDriftingLightMoving) {
  const Figures f = measure(preset("uneven_drift"), 6, 0.7);
  expectTargets(f);
  EXPECT_EQ(f.balls_found, f.balls_visible);
}

TEST(IdentificationOnRenderedFrames, SslPattern) {
  const Figures f = measure(preset("ssl_pattern"), 5, 0.7);
  expectTargets(f);
  EXPECT_EQ(f.balls_found, f.balls_visible);
}

TEST(IdentificationOnRenderedFrames, SslCrowdedTouching) {
  const Figures f = measure(preset("crowded"), 3, 0.7);
  expectTargets(f);
}
