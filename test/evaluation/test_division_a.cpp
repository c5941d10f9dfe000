// Division A (12 x 9 m) under the layouts of CameraModel::defaultCamera: every camera of a
// preset renders the same game, each calibrated from its own synthetic start-up frames, one
// VisionPipeline tracks them all. Every robot in view of some camera must be reported, and
// reported once: a robot in the overlap of two or four cameras is one track, not several.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/evaluation/evaluation.h"
#include "soccer_vision/pipeline/vision_pipeline.h"
#include "soccer_vision/simulation/field_renderer.h"
#include "soccer_vision/simulation/game_simulator.h"
#include "soccer_vision/simulation/scenario_camera.h"
#include "soccer_vision/simulation/synthetic_calibration.h"
#include "soccer_vision/tracking/result_recording.h"
#include "support/scene_objects.h"

using namespace soccer_vision;
using soccer_vision::test::robotRecord;

namespace {

struct LayoutRun {
  RunEvaluation evaluation;
  int frames = 0;
  int duplicate_robots = 0;    // a (team, id) reported twice in one output
  int robots_close_twice = 0;  // two reports of one team within a robot's radius
  int overlap_samples = 0;     // truth robots seen whole by two or more cameras
  int ball_frames = 0, ball_tracked = 0;
};

LayoutRun runLayout(const std::string& preset, int frames) {
  const ScenarioConfig scenario =
      loadScenario(std::string(SOCCER_VISION_SOURCE_DIR) + "/config/scenarios/" + preset + ".yaml");
  const FieldGeometry field = fieldGeometryByName(scenario.field);
  const PatternSet patterns = patternSetByName(scenario.pattern);
  std::vector<std::unique_ptr<FieldRenderer>> renderers;
  std::vector<PipelineCamera> cameras;
  for (int i = 0; i < scenario.cameras; ++i) {
    const CameraModel camera = scenarioCamera(field, i, scenario);
    renderers.push_back(std::make_unique<FieldRenderer>(camera, field, patterns, scenario));
    PipelineCamera c;
    c.id = i;
    c.model = camera;
    c.layout = *pixelLayoutForEncoding(renderers.back()->encoding());  // as the preset renders it
    c.segmentation = SegmentationModel::fromTable(
        std::make_shared<const ColorTable>(calibrateSyntheticCamera(scenario, i)));
    cameras.push_back(c);
  }
  VisionPipeline pipeline(cameras, patterns, field);
  GameSimulator sim(scenario, field, patterns.maxRobotsPerTeam());
  const double dt = 1.0 / scenario.fps;
  LayoutRun run;
  RenderedFrame rendered;
  for (int k = 0; k < frames; ++k) {
    const double stamp = 1000.0 + k * dt;
    PipelineFrame last;
    // The cameras are not synchronised: camera i captures i ms after camera 0.
    for (int i = 0; i < scenario.cameras; ++i) {
      renderers[i]->render(sim.state(), k, rendered);
      last = pipeline.process(i, rendered.image, stamp + 0.001 * i);
    }
    FrameRecord truth;
    truth.stamp = stamp;
    for (const RobotState& s : sim.state().robots) {
      int seen_by = 0;
      for (const auto& r : renderers) seen_by += r->robotVisible(s);
      run.overlap_samples += seen_by >= 2;
      RobotRecord rec = robotRecord(s.team, s.id, s.x, s.y, seen_by > 0);
      rec.theta = s.theta;
      truth.robots.push_back(rec);
    }
    for (const BallState& s : sim.state().balls) {
      BallRecord b;
      b.x = s.x;
      b.y = s.y;
      b.visible = std::any_of(renderers.begin(), renderers.end(),
                              [&](const auto& r) { return r->ballVisible(s, sim.state().robots); });
      truth.balls.push_back(b);
    }
    const FrameRecord record = toFrameRecord(last.output);
    run.evaluation.add(truth, record);
    ++run.frames;
    for (std::size_t a = 0; a < record.robots.size(); ++a) {
      for (std::size_t b = a + 1; b < record.robots.size(); ++b) {
        const RobotRecord &p = record.robots[a], &q = record.robots[b];
        if (p.team != q.team) continue;
        run.duplicate_robots += p.id == q.id && p.id >= 0;
        run.robots_close_twice += std::hypot(p.x - q.x, p.y - q.y) < patterns.robot_radius;
      }
    }
    const bool ball_in_view = !truth.balls.empty() && truth.balls.front().visible;
    run.ball_frames += ball_in_view;
    run.ball_tracked += ball_in_view && !record.balls.empty() && record.balls.front().visible;
    sim.step(dt);
  }
  return run;
}

void expectEveryRobotOnce(const char* preset, const LayoutRun& run) {
  const Score& s = run.evaluation.total();
  std::printf(
      "%s: %d instants, robots %.3f %% / %.3f %%, %.2f mm, %d robot samples in overlaps; duplicates %d, "
      "two reports within a radius %d; ball %d of %d frames\n",
      preset, run.frames, 100 * s.robotDetectionRate(), 100 * s.robotPrecision(), 1e3 * s.robotPositionRmse(),
      run.overlap_samples, run.duplicate_robots, run.robots_close_twice, run.ball_tracked, run.ball_frames);
  EXPECT_GT(run.overlap_samples, run.frames) << preset << ": the game should cross the overlaps";
  EXPECT_EQ(run.duplicate_robots, 0) << preset;
  EXPECT_EQ(run.robots_close_twice, 0) << preset;
  EXPECT_GE(s.robotDetectionRate(), 0.995) << preset;
  EXPECT_GE(s.robotPrecision(), 0.999) << preset;
  EXPECT_LE(s.robotPositionRmse(), 0.006) << preset;
  EXPECT_EQ(run.evaluation.identitySwitches(), 0) << preset;
}

}  // namespace

TEST(DivisionA, FourCamerasReportEveryRobotOnce) {
  expectEveryRobotOnce("div_a_four_cameras", runLayout("div_a_four_cameras", 150));
}

TEST(DivisionA, TwoLeagueCamerasReportEveryRobotOnce) {
  expectEveryRobotOnce("div_a_two_cameras", runLayout("div_a_two_cameras", 90));
}

TEST(DivisionA, LayoutsCoverTheFieldAndKeepDivisionB) {
  // Division B's two cameras are the ones every earlier figure was measured with.
  const FieldGeometry div_b = fieldGeometryByName("div_b");
  for (int i = 0; i < 2; ++i) {
    const CameraModel c = CameraModel::defaultCamera(div_b, i);
    EXPECT_EQ(c.intrinsics().fx, 800.0);
    EXPECT_NEAR(c.fieldTCamera().translation().x(), (i == 0 ? -2.26 : 2.26), 1e-12);
    EXPECT_NEAR(c.fieldTCamera().translation().y(), 0.02, 1e-12);
  }
  // Every point of the playing area and of its boundary (but its outer 5 cm) is in the image
  // of some camera of each layout.
  const FieldGeometry div_a = fieldGeometryByName("div_a");
  for (int count : {1, 2, 3, 4, 6, 8}) {
    std::vector<CameraModel> cameras;
    for (int i = 0; i < count; ++i)
      cameras.push_back(CameraModel::defaultCamera(div_a, i, 1280, 1024, count));
    int unseen = 0;
    const double margin = div_a.boundary - 0.05;
    for (double x = -div_a.halfLength() - margin; x <= div_a.halfLength() + margin; x += 0.1) {
      for (double y = -div_a.halfWidth() - margin; y <= div_a.halfWidth() + margin; y += 0.1) {
        bool seen = false;
        for (const auto& c : cameras) {
          const auto px = c.project({x, y, 0.0});
          seen = seen || (px && px->x() >= 0 && px->y() >= 0 && px->x() <= c.width() - 1 &&
                          px->y() <= c.height() - 1);
        }
        unseen += !seen;
      }
    }
    EXPECT_EQ(unseen, 0) << count << " cameras";
  }
  EXPECT_THROW(CameraModel::defaultCamera(div_a, 4, 1280, 1024, 4), std::invalid_argument);
  EXPECT_THROW(CameraModel::defaultCamera(div_a, 0, 1280, 1024, 9), std::invalid_argument);
  EXPECT_THROW(CameraModel::defaultCamera(div_a, -1), std::invalid_argument);
}
