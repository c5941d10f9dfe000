// Online self-calibration through the whole pipeline, calibrated as a user does (one frame,
// polygons 2 px inside each marker) on randomised scenes (config/scenarios/rand_*.yaml):
//  - after the light falls by 30 %, or a lamp goes out over part of the field, the robots
//    are measured again within seconds, and the marker interiors are classified at least as
//    well as by the calibrated table alone; when it rises by 30 % (the camera clipping bright
//    markers) learning adds no false colour;
//  - on a static scene, 10 000 frames do not make it drift: the learned cells stop growing,
//    the background never takes a marker colour, no robot is lost.
// "Measured": a visible robot detected in its own frame with its team and id within 50 mm.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "segmentation/marker_interior_accuracy.h"
#include "soccer_vision/calibration/color_calibration.h"
#include "soccer_vision/pipeline/vision_pipeline.h"
#include "soccer_vision/simulation/calibration_samples.h"
#include "soccer_vision/simulation/field_renderer.h"
#include "soccer_vision/simulation/game_simulator.h"
#include "soccer_vision/simulation/scenario_camera.h"

using namespace soccer_vision;
using soccer_vision::test::Accuracy;
using soccer_vision::test::countMarkerInteriors;

namespace {

constexpr double kT0 = 1700000000.0;
constexpr double kGate = 0.05;  // [m]

ScenarioConfig preset(const std::string& name) {
  return loadScenario(std::string(SOCCER_VISION_SOURCE_DIR) + "/config/scenarios/" + name + ".yaml");
}

// A lamp going out: the light falls to `remaining` at `centre` (image pixels), smoothly
// over `radius`.
struct LampOut {
  cv::Point2d centre;
  double radius = 300;
  double remaining = 0.5;
  void apply(cv::Mat& image) const {
    cv::Mat1f gain(image.size());
    for (int y = 0; y < gain.rows; ++y) {
      for (int x = 0; x < gain.cols; ++x) {
        const double d2 = (x - centre.x) * (x - centre.x) + (y - centre.y) * (y - centre.y);
        gain(y, x) = static_cast<float>(1.0 - (1.0 - remaining) * std::exp(-0.5 * d2 / (radius * radius)));
      }
    }
    cv::Mat f;
    image.convertTo(f, CV_32F);
    std::vector<cv::Mat> channels;
    cv::split(f, channels);
    for (cv::Mat& c : channels) c = c.mul(gain);
    cv::merge(channels, f);
    f.convertTo(image, image.type());
  }
};

struct Phase {
  int visible = 0, measured = 0;
  Accuracy accuracy;
  double rate() const { return visible ? static_cast<double>(measured) / visible : 1.0; }
};

struct Outcome {
  Phase first, last;  // the first and the last second shown
  std::uint32_t learned = 0;
  double level_deviation = 0;
  OnlineCalibrationStatus status;
};

class Hall {
 public:
  // Calibrated as the held-out protocol does: on the first frame (60 Hz, within `horizon`
  // s) that shows every marker colour the camera shows meanwhile, polygons 2 px inside.
  Hall(const ScenarioConfig& scenario, double horizon)
      : scenario_(scenario),
        patterns_(patternSetByName(scenario.pattern)),
        camera_(scenarioCamera(field_, 0, scenario)) {
    const FieldRenderer renderer(camera_, field_, patterns_, scenario_);
    layout_ = *pixelLayoutForEncoding(renderer.encoding());
    const SampleOptions drawn = SampleOptions::drawnByUser(2);
    std::set<ColorClass> in_view;
    std::vector<SceneState> states;
    {
      GameSimulator sim(scenario_, field_, patterns_.maxRobotsPerTeam());
      for (int k = 0; k <= horizon * scenario_.fps; ++k) {
        if (k > 0) sim.step(1.0 / scenario_.fps);
        states.push_back(sim.state());
        for (const RobotState& r : sim.state().robots) {
          if (!renderer.robotVisible(r)) continue;
          for (const auto& m : patterns_.markers(r.team, r.id)) in_view.insert(m.color);
        }
      }
    }
    std::size_t best = 0, best_shown = 0;
    ColorSamples samples;
    for (std::size_t k = 0; k < states.size(); ++k) {
      ColorSamples s = calibrationSamples(states[k], camera_, field_, patterns_, drawn);
      std::size_t shown = 0;
      for (const ColorClass c : in_view) shown += s.count(c) && !s.at(c).empty();
      if (shown > best_shown || samples.empty()) best = k, best_shown = shown, samples = std::move(s);
      if (best_shown == in_view.size()) break;
    }
    for (const auto& [c, polygons] : samples) {
      if (!polygons.empty()) sampled_.insert(c);
    }
    RenderedFrame frame;
    renderer.render(states[best], static_cast<std::int64_t>(best), frame);
    model_ = SegmentationModel::fromTable(std::make_shared<const ColorTable>(
        calibrateColorTable({{classifiedColors(frame.image, layout_), samples}})));
    std::printf("[ %s: calibrated on frame %zu, %zu of %zu marker colours ]\n", scenario_.name.c_str(), best,
                best_shown, in_view.size());
  }

  // `seconds` of the recording at `fps` through the pipeline, learning or not: the light of
  // `before` until `step_at` s, then that of `after` (the same hall, robots moving as in
  // the calibration's run). Accuracy and measured rate of the second after the step and
  // of the last second.
  Outcome run(const ScenarioConfig& before, const ScenarioConfig& after, double step_at, bool learning,
              double seconds, double fps, const LampOut* lamp = nullptr) const {
    VisionPipelineParams params;
    params.online_calibration.enabled = learning;
    VisionPipeline pipeline({PipelineCamera{0, camera_, model_, layout_}}, patterns_, field_, params);
    GameSimulator sim(before, field_, patterns_.maxRobotsPerTeam());
    const FieldRenderer renderer_before(camera_, field_, patterns_, before);
    const FieldRenderer renderer_after(camera_, field_, patterns_, after);
    const int steps_per_frame = static_cast<int>(std::lround(before.fps / fps));
    const int frames = static_cast<int>(seconds * fps), step_frame = static_cast<int>(step_at * fps);
    Outcome out;
    for (int k = 0; k < frames; ++k) {
      for (int i = 0; i < steps_per_frame; ++i) sim.step(1.0 / before.fps);
      const bool stepped = k >= step_frame;
      const FieldRenderer& renderer = stepped ? renderer_after : renderer_before;
      RenderedFrame frame;
      renderer.render(sim.state(), static_cast<std::int64_t>(k) * steps_per_frame, frame);
      if (lamp && stepped) lamp->apply(frame.image);
      const double stamp = kT0 + k / fps;
      const PipelineFrame f = pipeline.process(0, frame.image, stamp);
      Phase* phase = stepped && k < step_frame + fps ? &out.first : k >= frames - fps ? &out.last : nullptr;
      if (!phase) continue;
      for (const RobotState& r : sim.state().robots) {
        if (!renderer.robotVisible(r)) continue;
        ++phase->visible;
        for (const RobotDetection& d : f.detections.robots) {
          if (d.team == r.team && d.id == r.id && std::hypot(d.x - r.x, d.y - r.y) < kGate) {
            ++phase->measured;
            break;
          }
        }
      }
      // Every 4th frame: the classification of the model now in use against the renderer's labels.
      if (k % 4 != 0) continue;
      const cv::Mat1b truth = renderer.renderLabels(sim.state());
      const cv::Mat1b labels = classifyAll(*pipeline.camera(0)->segmentation, frame.image, layout_);
      if (labels.size() != truth.size()) {
        cv::Mat1b quads;
        cv::resize(truth, quads, labels.size(), 0, 0, cv::INTER_NEAREST);
        countMarkerInteriors(quads, labels, phase->accuracy, sampled_);
      } else {
        countMarkerInteriors(truth, labels, phase->accuracy, sampled_);
      }
    }
    out.status = pipeline.onlineCalibration(0)->status();
    out.learned = out.status.learnedTotal();
    out.level_deviation = out.status.level_deviation;
    return out;
  }

  const ScenarioConfig& scenario() const { return scenario_; }
  const CameraModel& camera() const { return camera_; }
  const std::shared_ptr<const SegmentationModel>& model() const { return model_; }

 private:
  ScenarioConfig scenario_;
  FieldGeometry field_;
  PatternSet patterns_;
  CameraModel camera_;
  PixelLayout layout_ = PixelLayout::Bgr;
  std::set<ColorClass> sampled_;
  std::shared_ptr<const SegmentationModel> model_;
};

void print(const char* what, const Outcome& o) {
  std::printf(
      "[ %-34s ] measured %.2f %% -> %.2f %%, marker interiors %.3f %% -> %.3f %%, background -> marker "
      "%.5f %%, %u cells learned, light moved %.0f %% (%lu markers, %lu marker pixels, %u cells vetoed, %u "
      "beyond "
      "the colours at the last update)\n",
      what, 100 * o.first.rate(), 100 * o.last.rate(), 100 * o.first.accuracy.markers(),
      100 * o.last.accuracy.markers(), 100 * o.last.accuracy.falsePositives(), o.learned,
      100 * o.level_deviation, static_cast<unsigned long>(o.status.markers),
      static_cast<unsigned long>(o.status.marker_votes), o.status.vetoed_cells, o.status.outside_envelope);
}

struct Compared {
  Outcome fixed, learned;
};

// 5 s of rand_uneven_lamps at 15 fps, the light times `factor` after the first second, with
// the calibrated table and with learning.
Compared lightStep(double factor) {
  const Hall hall(preset("rand_uneven_lamps"), 5.0);
  ScenarioConfig after = hall.scenario();
  after.lighting.brightness *= factor;
  Compared c{hall.run(hall.scenario(), after, 1.0, false, 5.0, 15.0),
             hall.run(hall.scenario(), after, 1.0, true, 5.0, 15.0)};
  const std::string what = "light x" + std::to_string(factor).substr(0, 3);
  print((what + ", calibrated table").c_str(), c.fixed);
  print((what + ", learning").c_str(), c.learned);
  return c;
}

}  // namespace

// The light falls by 30 % one second into the recording (the calibration frame is of the
// light before). Learned: the cells the darker markers fall into and the light's shape.
TEST(OnlineCalibration, RecoversFromALightStep) {
  const Compared c = lightStep(0.7);
  EXPECT_GE(c.learned.last.rate(), 0.99);
  EXPECT_GE(c.learned.last.rate(), c.fixed.last.rate());
  // Learning recovers the interiors the step took and loses none of the calibrated table's
  // beyond a pixel in a thousand (of the ~1200 counted: since 2026-12-07's calibration
  // samples, one yellow pixel more wrong than the calibrated table's, 340 of 346).
  EXPECT_GT(c.learned.last.accuracy.markers(), c.learned.first.accuracy.markers());
  EXPECT_GE(c.learned.last.accuracy.markers(), c.fixed.last.accuracy.markers() - 1e-3);
  EXPECT_LE(c.learned.last.accuracy.falsePositives(), std::max(1e-4, c.fixed.last.accuracy.falsePositives()));
}

// 30 % more light: the camera clips the bright markers, which no table learnt from the
// markers still seen brings back (docs/segmentation.md); what is checked is that learning
// adds no false colour. The figures are printed.
TEST(OnlineCalibration, AddsNoFalseColourWhenTheLightRises) {
  const Compared c = lightStep(1.3);
  EXPECT_LE(c.learned.last.accuracy.falsePositives(), std::max(1e-4, c.fixed.last.accuracy.falsePositives()));
  EXPECT_EQ(c.learned.status.cells_removed, 0u);
}

TEST(OnlineCalibration, RecoversWhenALampGoesOut) {
  const Hall hall(preset("rand_even_static"), 1.0);
  LampOut lamp;
  lamp.centre = {hall.camera().width() * 0.3, hall.camera().height() * 0.5};
  lamp.radius = hall.camera().width() * 0.2;
  lamp.remaining = 0.45;
  const Outcome fixed = hall.run(hall.scenario(), hall.scenario(), 1.0, false, 5.0, 15.0, &lamp);
  const Outcome learned = hall.run(hall.scenario(), hall.scenario(), 1.0, true, 5.0, 15.0, &lamp);
  print("lamp out, calibrated table", fixed);
  print("lamp out, learning", learned);
  EXPECT_GE(learned.last.rate(), 0.99);
  EXPECT_GE(learned.last.rate(), fixed.last.rate());
  EXPECT_GT(learned.level_deviation, 0.2);  // the expected light followed the lamp
  EXPECT_LE(learned.last.accuracy.falsePositives(), 1e-4);
}

TEST(OnlineCalibration, DoesNotDriftOnAStaticSceneOver10000Frames) {
  const ScenarioConfig scenario = preset("rand_even_static");
  const Hall hall(scenario, 0.0);
  // 16 renderings of the still scene (their noise differs), shown in turn at 60 Hz.
  const FieldGeometry field;
  const PatternSet patterns = patternSetByName(scenario.pattern);
  GameSimulator sim(scenario, field, patterns.maxRobotsPerTeam());
  const FieldRenderer renderer(hall.camera(), field, patterns, scenario);
  const PixelLayout layout = *pixelLayoutForEncoding(renderer.encoding());
  std::vector<cv::Mat> frames;
  for (int k = 1; k <= 16; ++k) {
    RenderedFrame frame;
    renderer.render(sim.state(), k, frame);
    frames.push_back(frame.image.clone());
  }
  const cv::Mat1b truth = renderer.renderLabels(sim.state());
  int visible = 0;
  for (const RobotState& r : sim.state().robots) visible += renderer.robotVisible(r);

  VisionPipelineParams params;
  params.online_calibration.enabled = true;
  // The Hall's table, calibrated on frame 0.
  VisionPipeline pipeline({PipelineCamera{0, hall.camera(), hall.model(), layout}}, patterns, field, params);
  auto accuracy = [&] {
    Accuracy a;
    for (const cv::Mat& image : frames) {
      countMarkerInteriors(truth, classifyAll(*pipeline.camera(0)->segmentation, image, layout), a);
    }
    return a;
  };
  const Accuracy before = accuracy();
  std::uint32_t learned_half = 0;
  int measured_last = 0, frames_last = 0;
  constexpr int kFrames = 10000;
  for (int k = 0; k < kFrames; ++k) {
    const PipelineFrame f = pipeline.process(0, frames[k % frames.size()], kT0 + k / 60.0);
    if (k == kFrames / 2) learned_half = pipeline.onlineCalibration(0)->status().learnedTotal();
    if (k < kFrames - 600) continue;
    ++frames_last;
    for (const RobotState& r : sim.state().robots) {
      if (!renderer.robotVisible(r)) continue;
      for (const RobotDetection& d : f.detections.robots) {
        if (d.team == r.team && d.id == r.id && std::hypot(d.x - r.x, d.y - r.y) < kGate) {
          ++measured_last;
          break;
        }
      }
    }
  }
  const OnlineCalibrationStatus& status = pipeline.onlineCalibration(0)->status();
  const Accuracy after = accuracy();
  std::printf(
      "[ static, 10 000 frames ] marker interiors %.3f %% -> %.3f %%, background -> marker %.5f %% -> %.5f "
      "%%; "
      "cells learned %u at frame 5000, %u at 10 000 (%lu added, %lu given back in %lu updates); light moved "
      "%.1f %%; measured in the last 10 s %.2f %%\n",
      100 * before.markers(), 100 * after.markers(), 100 * before.falsePositives(),
      100 * after.falsePositives(), learned_half, status.learnedTotal(),
      static_cast<unsigned long>(status.cells_added), static_cast<unsigned long>(status.cells_removed),
      static_cast<unsigned long>(status.updates), 100 * status.level_deviation,
      100.0 * measured_last / std::max(1, frames_last * visible));
  // Converged in the first half: the second adds at most 2 % more cells.
  EXPECT_LE(status.learnedTotal(), learned_half + std::max<std::uint32_t>(2, learned_half / 50));
  EXPECT_GE(after.markers(), before.markers());
  EXPECT_LE(after.falsePositives(), std::max(1e-4, before.falsePositives()));
  EXPECT_LT(status.level_deviation, 0.1);  // the light did not change: its band barely moves
  EXPECT_EQ(measured_last, frames_last * visible);
}
