// Identification on frames of the synthetic camera (the best test: real anti-aliasing,
// noise, uneven light and perspective): render -> colour table calibrated on the
// simulator's sample polygons -> segmentation -> identification with a camera pose solved
// from the field landmarks -> compared with the ground-truth SceneState.
//
// Per preset: detection rate over the robots the renderer calls visible (all markers in
// the image), false positives (a detection with no true robot of that team and id within
// 50 mm), wrong ids (a detection within 50 mm of a true robot of another team/id), and
// position / heading errors; the ball the same way.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "soccer_vision/calibration/camera_pose_solver.h"
#include "soccer_vision/calibration/color_calibration.h"
#include "soccer_vision/common/angle.h"
#include "soccer_vision/identification/frame_identification.h"
#include "soccer_vision/identification/image_footprint.h"
#include "soccer_vision/identification/rigid_fit_2d.h"
#include "soccer_vision/segmentation/segmenter.h"
#include "soccer_vision/simulation/calibration_samples.h"
#include "soccer_vision/simulation/field_renderer.h"
#include "soccer_vision/simulation/game_simulator.h"

using namespace soccer_vision;

namespace {

struct Figures {
  int segmentable = 0, found_segmentable = 0;  // robots whose every marker segmentation delivered
  int visible = 0, found = 0, false_positives = 0, wrong_ids = 0, detections = 0;
  std::size_t regions = 0;
  int balls_visible = 0, balls_found = 0, ball_false = 0;
  std::vector<double> position_mm, heading_deg, ball_mm, identify_ms;
  std::array<std::vector<double>, 2> team_position_mm;  // per Team

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

// Whether segmentation delivered every marker of the robot: a region of the marker's
// colour within 1.5 px of its projected centre with at least half its expected area.
bool segmentable(const RobotState& t, const CameraModel& camera, const PatternSet& patterns,
                 const std::vector<Region>& regions) {
  const double c = std::cos(t.theta), s = std::sin(t.theta);
  for (const ColoredMarker& m : patterns.markers(t.team, t.id)) {
    const Eigen::Vector3d centre(t.x + c * m.shape.x - s * m.shape.y, t.y + s * m.shape.x + c * m.shape.y,
                                 patterns.height(t.team));
    const Eigen::Vector2d px = *camera.project(centre);
    const double expected = expectedMarkerArea(camera, m.shape, t.x, t.y, t.theta, patterns.height(t.team));
    bool delivered = false;
    for (const Region& r : regions) {
      delivered = delivered || (r.color == m.color && std::hypot(r.cx - px.x(), r.cy - px.y()) < 1.5 &&
                                r.area >= 0.5 * expected);
    }
    if (!delivered) return false;
  }
  return true;
}

// `frames` frames `step_s` apart of `scenario`, both cameras; the robots rendered (and the
// colour table's samples taken) with `patterns`, identified with `identified` (a pattern
// that may differ from the robots', e.g. in the teams' heights).
Figures measure(const ScenarioConfig& scenario, int frames, double step_s, const PatternSet& patterns,
                const PatternSet& identified) {
  const FieldGeometry field;
  GameSimulator sim(scenario, field, patterns.maxRobotsPerTeam());
  std::vector<std::unique_ptr<FieldRenderer>> renderers;
  for (int c = 0; c < 2; ++c) {
    renderers.push_back(std::make_unique<FieldRenderer>(
        CameraModel::defaultCamera(field, c, scenario.width, scenario.height), field, patterns, scenario));
  }
  // The colour table: calibrated on the simulator's sample polygons (the markers' inner
  // 85 %) of the 6 frames before each evaluated frame, one table per camera (each with its
  // own illumination reference, as each camera's segmentation has),
  // i.e. a table made for the light of the test. These figures measure identification on
  // realistic regions; how well a table made once generalises to other light is the
  // segmentation tests' business.
  const int steps = std::max(8, static_cast<int>(std::lround(step_s * scenario.fps)));
  const int lead = 1, calibration_frames = 6;
  std::vector<std::vector<CalibrationImage>> calibration(renderers.size());
  {
    SampleOptions options;
    options.shrink = 0.85;
    GameSimulator preview(scenario, field, patterns.maxRobotsPerTeam());
    std::int64_t index = 0;
    for (int f = 0; f < frames; ++f) {
      const std::int64_t evaluated = index + steps;
      for (; index < evaluated; ++index) {
        preview.step(1.0 / scenario.fps);
        const std::int64_t before = evaluated - (index + 1);
        if (before == 0 || before % lead != 0 || before > calibration_frames * lead) continue;
        for (std::size_t c = 0; c < renderers.size(); ++c) {
          RenderedFrame frame;
          renderers[c]->render(preview.state(), index + 1, frame);
          calibration[c].push_back(
              {frame.image.clone(),
               calibrationSamples(preview.state(), renderers[c]->camera(), field, patterns, options)});
        }
      }
    }
  }
  // Coarser S and V cells than the default (1/8, 32 levels): fewer cells a few dozen
  // samples per marker leave unclaimed.
  ColorTableParams table_params;
  table_params.s_bins = 8;
  table_params.v_bins = 8;
  std::vector<std::shared_ptr<const SegmentationModel>> models;
  for (const auto& images : calibration) {
    models.push_back(SegmentationModel::fromTable(
        std::make_shared<const ColorTable>(calibrateColorTable(images, table_params))));
  }

  // The identification camera: intrinsics as published, pose solved from the landmarks.
  std::vector<FrameIdentifier> identifiers;
  for (const auto& r : renderers) {
    const CameraIntrinsics& k = r->camera().intrinsics();
    identifiers.emplace_back(solveCameraPose(k, fieldCorrespondences(r->camera(), field)).model(), identified,
                             field);
  }

  Figures fig;
  Segmenter segmenter;
  SegmentationResult seg;
  std::int64_t index = 0;
  for (int f = 0; f < frames; ++f) {
    for (int i = 0; i < steps; ++i, ++index) sim.step(1.0 / scenario.fps);
    // With motion blur the picture shows the exposure's middle: compare with that instant.
    const SceneState scene = scenario.sensor.blur_samples > 1
                                 ? extrapolate(sim.state(), scenario.sensor.exposure / 2)
                                 : sim.state();
    for (std::size_t c = 0; c < renderers.size(); ++c) {
      RenderedFrame frame;
      renderers[c]->render(sim.state(), index, frame);
      segmenter.process(*models[c], frame.image, PixelLayout::Bgr, {}, seg);
      fig.regions += seg.regions.size();
      const auto start = std::chrono::steady_clock::now();
      const CameraFrameDetections det = identifiers[c].identify(seg.regions, scene.time, static_cast<int>(c));
      fig.identify_ms.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
      fig.detections += static_cast<int>(det.robots.size());
      for (const RobotState& t : scene.robots) {
        if (!renderers[c]->robotVisible(t)) continue;
        ++fig.visible;
        const int found_before = fig.found;
        for (const RobotDetection& d : det.robots) {
          if (d.team != t.team || d.id != t.id) continue;
          ++fig.found;
          fig.position_mm.push_back(1000 * std::hypot(d.x - t.x, d.y - t.y));
          fig.team_position_mm[static_cast<std::size_t>(t.team)].push_back(fig.position_mm.back());
          fig.heading_deg.push_back(std::abs(angleDifference(d.theta, t.theta)) * 180 / M_PI);
          break;
        }
        if (segmentable(t, renderers[c]->camera(), patterns, seg.regions)) {
          ++fig.segmentable;
          fig.found_segmentable += fig.found > found_before;
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
        if (!renderers[c]->ballVisible(b, scene.robots)) continue;
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
  std::printf(
      "[ %s ] %d frames x 2 cameras: robots found %d / %d visible (%.2f %%); of those segmentation delivered "
      "whole: %d / %d; false positives %d of %d detections, wrong ids %d\n",
      scenario.name.c_str(), frames, fig.found, fig.visible, 100 * fig.rate(), fig.found_segmentable,
      fig.segmentable, fig.false_positives, fig.detections, fig.wrong_ids);
  std::printf(
      "[ %s ] position error RMS %.2f mm, 95 %% %.2f mm, max %.2f mm; heading error RMS %.3f deg, 95 %% %.3f "
      "deg, "
      "max %.3f deg\n",
      scenario.name.c_str(), Figures::rms(fig.position_mm), Figures::quantile(fig.position_mm, 0.95),
      Figures::quantile(fig.position_mm, 1.0), Figures::rms(fig.heading_deg),
      Figures::quantile(fig.heading_deg, 0.95), Figures::quantile(fig.heading_deg, 1.0));
  std::printf(
      "[ %s ] ball found %d / %d, position error RMS %.2f mm, max %.2f mm; %d ball candidates not at a "
      "ball\n",
      scenario.name.c_str(), fig.balls_found, fig.balls_visible, Figures::rms(fig.ball_mm),
      Figures::quantile(fig.ball_mm, 1.0), fig.ball_false);
  std::printf(
      "[ %s ] identification %.3f ms per frame (median, %.1f regions per frame; for information only)\n",
      scenario.name.c_str(), Figures::quantile(fig.identify_ms, 0.5),
      static_cast<double>(fig.regions) / fig.identify_ms.size());
  return fig;
}

Figures measure(const ScenarioConfig& scenario, int frames, double step_s) {
  const PatternSet patterns = patternSetByName(scenario.pattern);
  return measure(scenario, frames, step_s, patterns, patterns);
}

// Identification's part: every robot whose markers segmentation delivered is found with
// its id; nothing else is reported; errors within the targets. `min_rate`: the
// whole chain's detection rate, segmentation misses included (the committed colour table
// leaves holes under uneven light).
void expectTargets(const Figures& f, double min_rate, double max_heading_rms = 1.0) {
  ASSERT_GT(f.visible, 20);
  EXPECT_GE(f.segmentable, 0.8 * f.visible);
  EXPECT_EQ(f.found_segmentable, f.segmentable);
  EXPECT_GE(f.rate(), min_rate);
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
  expectTargets(f, 1.0);
  EXPECT_EQ(f.balls_found, f.balls_visible);
}

TEST(IdentificationOnRenderedFrames, TwoTagUnevenDriftingLightMoving) {
  const Figures f = measure(preset("uneven_drift"), 8, 0.7);
  expectTargets(f, 0.8);
  EXPECT_EQ(f.balls_found, f.balls_visible);
}

TEST(IdentificationOnRenderedFrames, SslPattern) {
  const Figures f = measure(preset("ssl_pattern"), 6, 0.7);
  expectTargets(f, 0.9);
  EXPECT_EQ(f.balls_found, f.balls_visible);
}

// Robots up to 5 m/s, 4 ms exposure with motion blur (compared with the exposure's
// middle). The ball at up to 15 m/s is a streak longer than itself; segmentation often
// loses it altogether (not asserted here; the figures are printed).
TEST(IdentificationOnRenderedFrames, TwoTagFastMotionBlur) {
  const Figures f = measure(preset("fast_motion"), 8, 0.7);
  expectTargets(f, 0.9);
}

TEST(IdentificationOnRenderedFrames, SslCrowdedTouching) {
  const Figures f = measure(preset("crowded"), 3, 0.7);
  expectTargets(f, 0.95);
}

// The teams' robots rendered at their own heights (blue 0.15 m, yellow 0.13 m): with the
// pattern's per-team heights every robot is found where it is; with one height for both
// (0.15 m) the yellow ones are off by the parallax of 2 cm (the renderer draws each team
// on its plane: otherwise the two runs would agree).
TEST(IdentificationOnRenderedFrames, TwoTagTeamsOfDifferentHeights) {
  PatternSet heights = PatternSet::twoTag();
  heights.team_height = {0.15, 0.13};
  const Figures f = measure(preset("even_static"), 4, 0.5, heights, heights);
  expectTargets(f, 1.0);
  EXPECT_LT(Figures::quantile(f.position_mm, 1.0), 2.0);
  const PatternSet one = PatternSet::twoTag();  // 0.15 m for both
  const Figures g = measure(preset("even_static"), 4, 0.5, heights, one);
  const auto& yellow = g.team_position_mm[static_cast<std::size_t>(Team::Yellow)];
  const auto& blue = g.team_position_mm[static_cast<std::size_t>(Team::Blue)];
  std::printf(
      "[ blue 0.15 m, yellow 0.13 m ] per-team heights: position RMS %.2f mm, max %.2f mm; one height 0.15 "
      "m: "
      "yellow RMS %.2f mm, max %.2f mm (%zu found), blue max %.2f mm\n",
      Figures::rms(f.position_mm), Figures::quantile(f.position_mm, 1.0), Figures::rms(yellow),
      Figures::quantile(yellow, 1.0), yellow.size(), Figures::quantile(blue, 1.0));
  ASSERT_GT(yellow.size(), 10u);
  EXPECT_GT(Figures::rms(yellow), 3 * std::max(Figures::rms(f.position_mm), 1.0));
  EXPECT_LT(Figures::quantile(blue, 1.0), 2.0);
}
