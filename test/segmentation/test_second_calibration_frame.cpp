// When the calibration frame does not show every colour, a user samples the missing ones on a
// second frame (the calibration UI's second freeze, evaluate --more-samples), and the table
// is calibrated on both frames together (~calibrate's merge).
//
// Randomised scenes (their tuning seeds): frame 0 sampled as a user does (polygons 2 px
// inside) without pink and the ball; the first frame from 1 s on that shows them: pink, the
// ball and the carpet only; held out: 6 frames 0.5 s apart after it. Compared: the frames
// calibrated together; the second frame's table with the first's classes filled in
// (keepUnsampledClasses, the merge before); and, with the background model on, the second
// frame's unsampled pixels not background (CalibrationImage::unsampled_is_background) or
// background.
#include <cstdio>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "marker_interior_accuracy.h"
#include "soccer_vision/calibration/color_calibration.h"
#include "soccer_vision/segmentation/segmenter.h"
#include "soccer_vision/simulation/calibration_samples.h"
#include "soccer_vision/simulation/field_renderer.h"
#include "soccer_vision/simulation/game_simulator.h"
#include "soccer_vision/simulation/scenario_camera.h"

using namespace soccer_vision;
using soccer_vision::test::Accuracy;
using soccer_vision::test::countMarkerInteriors;

namespace {

// `samples` with only the classes in `keep` (keep_them) or without them.
ColorSamples filtered(const ColorSamples& samples, const std::set<ColorClass>& classes, bool keep_them) {
  ColorSamples out;
  for (const auto& [c, polygons] : samples) {
    if (classes.count(c) == static_cast<std::size_t>(keep_them) && !polygons.empty()) out[c] = polygons;
  }
  return out;
}

// Per table (together, keepUnsampledClasses, with the background model: together, the second
// frame's markers as background): all sampled colours' interiors and the first frame's colours'.
struct Outcome {
  std::vector<Accuracy> all, first_colours;
};

Outcome compare(const std::string& kind) {
  Outcome out;
  const ScenarioConfig scenario =
      loadScenario(std::string(SOCCER_VISION_SOURCE_DIR) + "/config/scenarios/" + kind + ".yaml");
  const FieldGeometry field;
  const PatternSet patterns = patternSetByName(scenario.pattern);
  const CameraModel camera = scenarioCamera(field, 0, scenario);
  GameSimulator sim(scenario, field, patterns.maxRobotsPerTeam());
  const FieldRenderer renderer(camera, field, patterns, scenario);
  EXPECT_EQ(renderer.encoding(), "bgr8");
  const SampleOptions drawn = SampleOptions::drawnByUser(2);
  const int per_second = static_cast<int>(scenario.fps);
  int step = 0;
  auto frameAt = [&](int at_step) {
    for (; step < at_step; ++step) sim.step(1.0 / scenario.fps);
    RenderedFrame frame;
    renderer.render(sim.state(), step, frame);
    return frame.image.clone();
  };

  const std::set<ColorClass> added{ColorClass::Pink, ColorClass::Orange};
  CalibrationImage first{frameAt(0), {}};
  first.samples = filtered(calibrationSamples(sim.state(), camera, field, patterns, drawn), added, false);
  // The second frame: the first from 1 s on that shows pink and the ball.
  std::set<ColorClass> with_carpet = added;
  with_carpet.insert(ColorClass::Carpet);
  CalibrationImage second;
  for (int at = per_second; at < 4 * per_second && second.samples.size() < 3; at += per_second / 10) {
    second.bgr = frameAt(at);
    second.samples =
        filtered(calibrationSamples(sim.state(), camera, field, patterns, drawn), with_carpet, true);
  }
  EXPECT_EQ(second.samples.size(), 3u) << kind << ": pink, the ball and the carpet in a second frame";
  std::set<ColorClass> sampled;
  for (const auto* image : {&first, &second}) {
    for (const auto& entry : image->samples) sampled.insert(entry.first);
  }

  ColorTableParams
      with_background;  // the background model on, as for a hall whose floor is near a marker colour
  with_background.background_share = 1e-5;
  second.unsampled_is_background = false;
  const ColorTable together = calibrateColorTable({first, second});
  const ColorTable together_bg = calibrateColorTable({first, second}, with_background);
  second.unsampled_is_background = true;
  const ColorTable as_background = calibrateColorTable({first, second}, with_background);
  const ColorTable filled_in =
      keepUnsampledClasses(calibrateColorTable({second}), calibrateColorTable({first}), second.samples);

  const std::vector<std::string> names = {"together", "keepUnsampledClasses", "background model: together",
                                          "background model: its markers background"};
  std::vector<std::shared_ptr<const SegmentationModel>> models;
  for (const ColorTable* t : {&together, &filled_in, &together_bg, &as_background})
    models.push_back(SegmentationModel::fromTable(std::make_shared<const ColorTable>(*t)));
  std::vector<Accuracy>&all = out.all, &first_colours = out.first_colours;
  all.resize(models.size());
  first_colours.resize(models.size());
  std::set<ColorClass> first_only;
  for (const auto& entry : first.samples) {
    if (isRobotMarkerColor(entry.first)) first_only.insert(entry.first);
  }
  for (int later = 0; later < 6; ++later) {
    const cv::Mat image = frameAt(step + per_second / 2);
    const cv::Mat1b truth = renderer.renderLabels(sim.state());
    for (std::size_t v = 0; v < models.size(); ++v) {
      const cv::Mat1b labels = classifyAll(*models[v], image, PixelLayout::Bgr, SegmentationParams{});
      countMarkerInteriors(truth, labels, all[v], sampled);
      countMarkerInteriors(truth, labels, first_colours[v], first_only);
    }
  }
  for (std::size_t v = 0; v < models.size(); ++v) {
    std::printf(
        "[ %s: %-42s ] marker interiors %.3f %% of %ld (the first frame's colours %.3f %%), "
        "background -> marker %.4f %%\n",
        kind.c_str(), names[v].c_str(), 100 * all[v].markers(), static_cast<long>(all[v].interior),
        100 * first_colours[v].markers(), 100 * all[v].falsePositives());
  }
  return out;
}

}  // namespace

TEST(SecondCalibrationFrame, AddsItsColoursWithoutTakingTheFirstFramesAway) {
  for (const char* kind : {"rand_flicker_jpeg", "rand_uneven_lamps"}) {
    const Outcome o = compare(kind);
    // Calibrated together, the first frame's colours keep what the second frame's table alone
    // (filled in by keepUnsampledClasses) gave to the carpet and the ball: measured
    // 2026-12-04 99.80 vs 98.73 % (flicker) and 96.85 vs 96.61 % (uneven lamps).
    EXPECT_GE(o.first_colours[0].markers(), o.first_colours[1].markers()) << kind;
    if (std::string(kind) == "rand_flicker_jpeg") {
      EXPECT_GE(o.first_colours[0].markers(), o.first_colours[1].markers() + 0.01) << kind;
    }
    EXPECT_GE(o.all[0].markers(), 0.97) << kind;
    // With the background model, the second frame's unsampled markers are not background.
    EXPECT_GE(o.first_colours[2].markers(), o.first_colours[3].markers()) << kind;
  }
}
