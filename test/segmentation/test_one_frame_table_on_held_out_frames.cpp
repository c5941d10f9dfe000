// A colour table calibrated from ONE frame must generalise: marker pixels of frames it
// never saw must not fall into holes of the table.
//
// Presets: one frame of camera 0, the calibrationSamples polygons (60 % of each visible
// marker, plus carpet, lines and robot tops); held out: frames of 2 other seeds (other
// robots in other places) at brightness 0.7, 1.0 and 1.3 of the calibration's.
// Randomised scenes (config/scenarios/rand_*.yaml, their tuning seeds): calibrated as a user
// does, polygons 2 px inside each marker on one frame, where it shows them (mid-exposure when
// blurred, as the label images); held out: the same hall (the seed
// draws its prints, carpet, white balance and lens) 1 s and 2 s later, the robots
// elsewhere, at 0.85, 1.0 and 1.15 of the light. Only marker colours the calibration frame shows are counted
// (a colour it lacks cannot be learnt from it: make_scenario --calibration-frame auto picks a frame).
//
// Marker interior: a pixel whose label is a marker colour and whose 8 neighbours share it.
// Background: a non-marker pixel with no marker pixel among its 8 neighbours; a false
// positive is one given a marker colour.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
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
using soccer_vision::test::openedMarkers;

namespace {

ScenarioConfig preset(const std::string& name) {
  return loadScenario(std::string(SOCCER_VISION_SOURCE_DIR) + "/config/scenarios/" + name + ".yaml");
}

// Per table variant: accuracy on the held-out frames of `scenario` (2 other seeds x 3
// light levels, one frame each, 1 s into the run).
std::vector<Accuracy> heldOut(const ScenarioConfig& scenario, const std::vector<ColorTableParams>& variants) {
  const FieldGeometry field;
  const PatternSet patterns = patternSetByName(scenario.pattern);
  const CameraModel camera = CameraModel::defaultCamera(field, 0, scenario.width, scenario.height);
  std::vector<std::shared_ptr<const SegmentationModel>> models;
  {
    GameSimulator sim(scenario, field, patterns.maxRobotsPerTeam());
    const FieldRenderer renderer(camera, field, patterns, scenario);
    RenderedFrame frame;
    renderer.render(sim.state(), 0, frame);
    const ColorSamples samples = calibrationSamples(sim.state(), camera, field, patterns);
    for (const ColorTableParams& p : variants) {
      models.push_back(SegmentationModel::fromTable(
          std::make_shared<const ColorTable>(calibrateColorTable({{frame.image, samples}}, p))));
    }
  }
  std::vector<Accuracy> out(variants.size());
  for (std::uint64_t seed_offset : {101u, 202u}) {
    for (double light : {0.7, 1.0, 1.3}) {
      ScenarioConfig held = scenario;
      held.seed = scenario.seed + seed_offset;
      held.lighting.brightness = scenario.lighting.brightness * light;
      GameSimulator sim(held, field, patterns.maxRobotsPerTeam());
      const FieldRenderer renderer(camera, field, patterns, held);
      const int steps = static_cast<int>(held.fps);
      for (int i = 0; i < steps; ++i) sim.step(1.0 / held.fps);
      RenderedFrame frame;
      renderer.render(sim.state(), steps, frame);
      const cv::Mat1b truth = renderer.renderLabels(sim.state());
      for (std::size_t v = 0; v < variants.size(); ++v) {
        countMarkerInteriors(
            truth, classifyAll(*models[v], frame.image, PixelLayout::Bgr, SegmentationParams{}), out[v]);
      }
    }
  }
  return out;
}

// A user's few strokes instead of the renderer's exact polygons, as the calibration UI sends
// them: per class the 3 largest polygons (markers, ball, carpet squares, line strips, robot
// tops), each replaced by one short stroke through its middle, 2 px wide and half the
// polygon's width long.
ColorSamples strokesOf(const ColorSamples& exact) {
  ColorSamples strokes;
  for (const auto& [c, polygons] : exact) {
    std::vector<cv::Rect2d> boxes;
    for (const Polygon& p : polygons) {
      double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
      for (const Eigen::Vector2d& v : p) {
        x0 = std::min(x0, v.x()), y0 = std::min(y0, v.y()), x1 = std::max(x1, v.x()),
        y1 = std::max(y1, v.y());
      }
      boxes.emplace_back(x0, y0, x1 - x0, y1 - y0);
    }
    std::sort(boxes.begin(), boxes.end(),
              [](const cv::Rect2d& a, const cv::Rect2d& b) { return a.area() > b.area(); });
    if (boxes.size() > 3) boxes.resize(3);
    for (const cv::Rect2d& b : boxes) {
      const double cx = b.x + b.width / 2, cy = b.y + b.height / 2, half = std::max(1.0, b.width / 4);
      strokes[c].push_back(
          Polygon{{cx - half, cy - 1}, {cx + half, cy - 1}, {cx + half, cy + 1}, {cx - half, cy + 1}});
    }
  }
  return strokes;
}

// A sloppy user's polygons: each of `exact` moved by `px` in a direction of its own
// (seeded: the same directions every run), so a 2 px inset keeps 2 - px px off the edge.
ColorSamples movedBy(const ColorSamples& exact, double px) {
  std::mt19937 rng(2026);
  std::uniform_real_distribution<double> angle(0, 2 * M_PI);
  ColorSamples moved = exact;
  for (auto& [c, polygons] : moved) {
    for (Polygon& p : polygons) {
      const double a = angle(rng);
      for (Eigen::Vector2d& v : p) v += px * Eigen::Vector2d(std::cos(a), std::sin(a));
    }
  }
  return moved;
}

// A table variant: its parameters, and whether it is calibrated from strokesOf the samples
// or from them moved by `moved_px` (movedBy).
struct Variant {
  Variant(const ColorTableParams& p, bool s = false, double m = 0)  // NOLINT: lists of params
      : params(p), strokes(s), moved_px(m) {}
  ColorTableParams params;
  bool strokes;
  double moved_px;
};

// Per table variant: accuracy on held-out frames of a randomised scene (1 s and 2 s into the
// run: the robots elsewhere, at light 0.85, 1.0 and 1.15 of the calibration's), calibrated
// from frame 0 with polygons 2 px inside (or strokes through them).
// `opened`, when given: the same counts on the labels as the regions see them
// (openedMarkers with the segmentation's opening kernel, smallest region and scan grid for
// the label image's width).
std::vector<Accuracy> heldOutRandomised(const ScenarioConfig& scenario, const std::vector<Variant>& variants,
                                        std::vector<Accuracy>* opened = nullptr) {
  const FieldGeometry field;
  const PatternSet patterns = patternSetByName(scenario.pattern);
  const CameraModel camera = scenarioCamera(field, 0, scenario);
  std::vector<std::shared_ptr<const SegmentationModel>> models;
  std::set<ColorClass> sampled;
  PixelLayout layout = PixelLayout::Bgr;
  {
    GameSimulator sim(scenario, field, patterns.maxRobotsPerTeam());
    const FieldRenderer renderer(camera, field, patterns, scenario);
    layout = *pixelLayoutForEncoding(renderer.encoding());
    RenderedFrame frame;
    renderer.render(sim.state(), 0, frame);
    const SampleOptions drawn = SampleOptions::drawnByUser(2);
    // Drawn where the frame shows the objects (mid-exposure when blurred), as a user draws them.
    const double shown = shownTimeAfterStamp(scenario.sensor);
    const ColorSamples samples =
        calibrationSamples(extrapolate(sim.state(), shown), camera, field, patterns, drawn);
    for (const auto& [c, polygons] : samples) {
      if (!polygons.empty()) sampled.insert(c);
    }
    const cv::Mat colors = classifiedColors(frame.image, layout);
    for (const Variant& v : variants) {
      const ColorSamples drawn_samples = v.strokes        ? strokesOf(samples)
                                         : v.moved_px > 0 ? movedBy(samples, v.moved_px)
                                                          : samples;
      models.push_back(SegmentationModel::fromTable(
          std::make_shared<const ColorTable>(calibrateColorTable({{colors, drawn_samples}}, v.params))));
    }
  }
  std::vector<Accuracy> out(variants.size());
  if (opened) opened->assign(variants.size(), Accuracy{});
  for (double light : {0.85, 1.0, 1.15}) {
    ScenarioConfig held = scenario;
    held.lighting.brightness = scenario.lighting.brightness * light;
    GameSimulator sim(held, field, patterns.maxRobotsPerTeam());
    const FieldRenderer renderer(camera, field, patterns, held);
    for (int second = 1; second <= 2; ++second) {
      const int steps = static_cast<int>(held.fps);
      for (int i = 0; i < steps; ++i) sim.step(1.0 / held.fps);
      RenderedFrame frame;
      renderer.render(sim.state(), second * steps, frame);
      // Where the frame shows the objects: mid-exposure when blurred.
      cv::Mat1b truth = renderer.renderLabels(extrapolate(sim.state(), shownTimeAfterStamp(held.sensor)));
      for (std::size_t v = 0; v < variants.size(); ++v) {
        cv::Mat1b labels = classifyAll(*models[v], frame.image, layout, SegmentationParams{});
        // A Bayer frame is classified per 2x2 quad: compare on the quad grid.
        cv::Mat1b scored = truth;
        if (labels.size() != truth.size()) cv::resize(truth, scored, labels.size(), 0, 0, cv::INTER_NEAREST);
        countMarkerInteriors(scored, labels, out[v], sampled);
        if (opened) {
          const RegionParams q = labelParams(RegionParams{}, labels.cols);
          countMarkerInteriors(scored, openedMarkers(labels, q.morph_kernel, q.min_area, scanGridStride(q)),
                               (*opened)[v], sampled);
        }
      }
    }
  }
  return out;
}

ColorTableParams bodyAlone() {
  ColorTableParams p;
  p.generalize_sigmas = 0;
  p.hs_closing = 0;
  return p;
}

}  // namespace

// Before: the body of the samples alone (the paper's, with the V margin); after: the
// default, generalised through each class's L*a*b* Gaussian. Also printed: the body closed
// in HS by 1 cell (hs_closing), the step tried before.
TEST(OneFrameTable, MarkerInteriorsOfHeldOutFramesAreClassified) {
  ColorTableParams closed = bodyAlone();
  closed.hs_closing = 1;
  Accuracy total[3];
  for (const char* name : {"even_static", "uneven_drift", "crowded", "ssl_pattern"}) {
    const std::vector<Accuracy> a = heldOut(preset(name), {bodyAlone(), ColorTableParams{}, closed});
    std::printf(
        "[ %-12s ] marker interiors %.3f %% -> %.3f %% (closing 1: %.3f %%) of %ld, background -> marker "
        "%.5f %% -> %.5f %% (%.5f %%) of %ld\n",
        name, 100 * a[0].markers(), 100 * a[1].markers(), 100 * a[2].markers(),
        static_cast<long>(a[1].interior), 100 * a[0].falsePositives(), 100 * a[1].falsePositives(),
        100 * a[2].falsePositives(), static_cast<long>(a[1].background));
    for (int v = 0; v < 3; ++v) total[v].add(a[v]);
    EXPECT_LE(a[1].falsePositives(), 1e-4) << name;
  }
  std::printf(
      "[ all          ] marker interiors %.3f %% -> %.3f %% (closing 1: %.3f %%), background -> marker "
      "%.5f %% -> %.5f %% (%.5f %%)\n",
      100 * total[0].markers(), 100 * total[1].markers(), 100 * total[2].markers(),
      100 * total[0].falsePositives(), 100 * total[1].falsePositives(), 100 * total[2].falsePositives());
  EXPECT_GT(total[1].interior, 20000);
  // Measured 2026-12-04: 94.995 % (body) -> 99.338 % (generalised), 0 background pixels of
  // 31.2 M given a marker colour. The misses are even_static's markers at 0.7 and 1.3 of the
  // calibration's light: V the V margin and the Gaussian's L* spread do not reach.
  EXPECT_GE(total[1].markers(), total[0].markers() + 0.03);
  EXPECT_GE(total[1].markers(), 0.985);
  EXPECT_LE(total[1].falsePositives(), 1e-4);
}

// Scenes the system was not developed on. The bar is >= 99.5 % of marker interiors
// and <= 0.01 % of the background given a marker colour per kind; measured 2026-12-04
// (docs/segmentation.md): 99.72 % over all kinds (body alone 80.84 %), 98.91 % the lowest
// (rand_fast: blur mixes the markers with the robot tops), background 0.35 % (the floor
// beyond the field, 0.88 % on rand_ssl; rand_people's clothes in team colours are
// background in the labels: 0.74 %). The markers' brightness variants
// (ColorTableParams::brightness_spread) and the ball's carpet mixture raised the interiors
// from 97.62 % and the background from 0.16 %; polygons and labels where a blurred frame
// shows the robots (mid-exposure), rand_fast from 91.3 %. After the segmentation's 3x3
// opening: interiors 99.24 %, background 0 on 6 kinds, 0.00008 % on rand_flicker_jpeg; after
// the 2x2 opening, its stride-3 scan and the smallest region (2026-12-05): interiors 99.6 %,
// background 0 on 6 kinds, 0.05 % on rand_flicker_jpeg. rand_bayer_ssl, added 2026-12-05:
// interiors 100 % (all kinds 99.78 %). These bounds keep what is reached.
TEST(OneFrameTable, MarkerInteriorsOfRandomisedScenesAreClassified) {
  Accuracy total[2], total_opened;
  for (const char* name :
       {"rand_even_static", "rand_uneven_lamps", "rand_fast", "rand_packed", "rand_people",
        "rand_flicker_jpeg", "rand_bayer", "rand_ssl", "rand_wide_angle", "rand_bayer_ssl"}) {
    std::vector<Accuracy> opened;
    const std::vector<Accuracy> a =
        heldOutRandomised(preset(name), {bodyAlone(), ColorTableParams{}}, &opened);
    std::printf(
        "[ %-17s ] marker interiors %.3f %% -> %.3f %% of %ld, background -> marker %.5f %% -> %.5f %% of "
        "%ld; after the opening: interiors %.3f %%, background -> marker %.5f %%\n",
        name, 100 * a[0].markers(), 100 * a[1].markers(), static_cast<long>(a[1].interior),
        100 * a[0].falsePositives(), 100 * a[1].falsePositives(), static_cast<long>(a[1].background),
        100 * opened[1].markers(), 100 * opened[1].falsePositives());
    for (int v = 0; v < 2; ++v) total[v].add(a[v]);
    total_opened.add(opened[1]);
    EXPECT_GE(a[1].markers(), std::max(a[0].markers(), 0.985)) << name;
    EXPECT_LE(a[1].falsePositives(), 1e-2) << name;
    // The 0.01 % as the regions see the labels: the background's marker-coloured
    // pixels are single noisy carpet pixels, which the opening removes. Not with people
    // beside the field (team-coloured clothes, background in the labels) nor on Bayer quads
    // (no opening, regions need a pair of adjacent pixels instead).
    // rand_flicker_jpeg: 0.05 % since the opening is 2x2 (2026-12-05; 0.00008 % with 3x3):
    // 2-3 px wide stretches of the field lines that JPEG tints sky blue, an id colour only.
    const ScenarioConfig kind = preset(name);
    if (std::string(name) == "rand_flicker_jpeg") {
      EXPECT_LE(opened[1].falsePositives(), 1e-3) << name;
    } else if (kind.appearance.distractors == 0 && kind.sensor.bayer.empty()) {
      EXPECT_LE(opened[1].falsePositives(), 1e-4) << name;
    }
  }
  EXPECT_GE(total[1].markers(), 0.995);
  EXPECT_LE(total[1].falsePositives(), 4.5e-3);
  std::printf(
      "[ all randomised  ] marker interiors %.3f %% -> %.3f %%, background -> marker %.5f %% -> %.5f %%; "
      "after "
      "the opening: %.3f %%, %.5f %%\n",
      100 * total[0].markers(), 100 * total[1].markers(), 100 * total[0].falsePositives(),
      100 * total[1].falsePositives(), 100 * total_opened.markers(), 100 * total_opened.falsePositives());
}

// The calibration UI's target: a table from about 3 strokes per class classifies the marker
// interiors of other frames within 0.5 % of one from the renderer's exact samples (both
// generalised, both from the same one frame), asserted per kind. Measured 2026-12-06
// (docs/calibration.md): 99.766 % against 99.784 % over all kinds, the largest gap 0.19 %
// (rand_flicker_jpeg); on 2026-12-04 rand_uneven_lamps and rand_bayer were 1.4 and 2.9 %
// short. On held-out seeds 9100-9104: 49 of 50 kinds x seeds within 0.5 %.
// The same bound for a sloppy hand: every polygon 1 px off where it belongs (the 2 px
// inset half used up), the third variant below.
TEST(OneFrameTable, AFewStrokesPerClassDoAsWellAsExactSamples) {
  Accuracy total[3];
  for (const char* name :
       {"rand_even_static", "rand_uneven_lamps", "rand_fast", "rand_packed", "rand_people",
        "rand_flicker_jpeg", "rand_bayer", "rand_ssl", "rand_wide_angle", "rand_bayer_ssl"}) {
    const std::vector<Accuracy> a = heldOutRandomised(
        preset(name),
        {ColorTableParams{}, Variant(ColorTableParams{}, true), Variant(ColorTableParams{}, false, 1.0)});
    std::printf(
        "[ %-17s ] marker interiors: exact samples %.3f %%, 3 strokes per class %.3f %%, polygons moved 1 px "
        "%.3f %%; background -> marker %.5f %%, %.5f %%, %.5f %%\n",
        name, 100 * a[0].markers(), 100 * a[1].markers(), 100 * a[2].markers(), 100 * a[0].falsePositives(),
        100 * a[1].falsePositives(), 100 * a[2].falsePositives());
    for (int v = 0; v < 3; ++v) total[v].add(a[v]);
    EXPECT_GE(a[1].markers(), a[0].markers() - 0.005) << name << ": strokes";
    EXPECT_GE(a[2].markers(), a[0].markers() - 0.005) << name << ": polygons moved 1 px";
  }
  EXPECT_GE(total[1].markers(), total[0].markers() - 0.002);
  EXPECT_GE(total[2].markers(), total[0].markers() - 0.002);
  std::printf("[ all randomised  ] marker interiors: exact %.3f %%, strokes %.3f %%, moved 1 px %.3f %%\n",
              100 * total[0].markers(), 100 * total[1].markers(), 100 * total[2].markers());
}

namespace {

struct ClippedOutcome {
  Accuracy colour, opened;  // `colour`'s interiors; every sampled colour's after the opening
};

// rand_uneven_lamps at `seed`, its table calibrated on frame `calibration_frame` as
// make_scenario samples it (2 px inside each object), `colour` sampled clipped twice there;
// classified on every `every`-th frame after it up to `last`.
ClippedOutcome clippedColourAfter(int seed, int calibration_frame, ColorClass colour, int last, int every) {
  ScenarioConfig scenario = preset("rand_uneven_lamps");
  scenario.seed = seed;
  const FieldGeometry field;
  const PatternSet patterns = patternSetByName(scenario.pattern);
  const CameraModel camera = scenarioCamera(field, 0, scenario);
  GameSimulator sim(scenario, field, patterns.maxRobotsPerTeam());
  const FieldRenderer renderer(camera, field, patterns, scenario);
  for (int i = 0; i < calibration_frame; ++i) sim.step(1.0 / scenario.fps);
  RenderedFrame frame;
  renderer.render(sim.state(), calibration_frame, frame);
  const ColorSamples samples =
      calibrationSamples(extrapolate(sim.state(), shownTimeAfterStamp(scenario.sensor)), camera, field,
                         patterns, SampleOptions::drawnByUser(2));
  const std::vector<CalibrationImage> images{{frame.image, samples}};
  EXPECT_EQ(classesSampledClipped(images), std::vector<ColorClass>{colour});
  const auto model =
      SegmentationModel::fromTable(std::make_shared<const ColorTable>(calibrateColorTable(images)));
  std::set<ColorClass> sampled;
  for (const auto& [c, polygons] : samples) {
    if (!polygons.empty()) sampled.insert(c);
  }
  ClippedOutcome out;
  for (int i = calibration_frame + 1; i <= last; ++i) {
    sim.step(1.0 / scenario.fps);
    if (i % every) continue;
    renderer.render(sim.state(), i, frame);
    const cv::Mat1b truth =
        renderer.renderLabels(extrapolate(sim.state(), shownTimeAfterStamp(scenario.sensor)));
    const cv::Mat1b labels = classifyAll(*model, frame.image, PixelLayout::Bgr, SegmentationParams{});
    countMarkerInteriors(truth, labels, out.colour, {colour});
    const RegionParams q = labelParams(RegionParams{}, labels.cols);
    countMarkerInteriors(truth, openedMarkers(labels, q.morph_kernel, q.min_area, scanGridStride(q)),
                         out.opened, sampled);
  }
  std::printf(
      "[ rand_uneven_lamps %d ] %s interiors %.3f %% of %ld; after the opening: interiors %.3f %%, "
      "background -> marker %.5f %%\n",
      seed, std::string(colorClassName(colour)).c_str(), 100 * out.colour.markers(),
      static_cast<long>(out.colour.interior), 100 * out.opened.markers(), 100 * out.opened.falsePositives());
  return out;
}

}  // namespace

// Held-out seed 9053 of rand_uneven_lamps (spent): the calibration frame (71, the first
// showing every colour) had its yellow tags under the brightest lamp only, clipped in two
// channels; under the dimmer lamps the print reads 42-44°, and the yellow robots there went
// unseen (measured 89.1 %). The clipped tags' rims lend the class their hue
// (calibrateColorTable, docs/calibration.md): the yellow interiors of the frames after are
// classified (without the rims: 88.2 %, 93.0 % after the opening). What the wider yellow
// also claims, single noisy pixels of the floor beyond the carpet (0.36 -> 0.62 % of the
// background), the opening removes, as the regions see the labels.
TEST(OneFrameTable, AColourSampledOnlyClippedIsSeenUnderDimmerLamps) {
  const ClippedOutcome o = clippedColourAfter(9053, 71, ColorClass::Yellow, 220, 15);
  EXPECT_GE(o.colour.markers(), 0.98);
  EXPECT_GE(o.opened.markers(), 0.99);
  EXPECT_LE(o.opened.falsePositives(), 1e-4);
}

// Held-out seed 9074 of rand_uneven_lamps (spent): the calibration frame's yellow tags
// clipped twice under the brightest lamp, their rims lent the class its hue at the clipped
// samples' brightness; the print is at least that bright, and its rim's colours claim their
// cells at the ceiling too (calibrateColorTable). Yellow 3, under a lamp between, went
// unidentified in 4 of the first 20 frames before (measured 99.70 %; 100 % with them).
TEST(OneFrameTable, AClippedPrintsRimClaimsItsCellsAtTheCeiling) {
  const ClippedOutcome o = clippedColourAfter(9074, 0, ColorClass::Yellow, 40, 2);
  EXPECT_GE(o.colour.markers(), 0.99);  // 78.1 % without the ceiling
  EXPECT_LE(o.opened.falsePositives(), 1e-4);
}

namespace {

// Every sixth of the first 240 frames of preset `name` at `seed`, before and after the
// calibration frame, as `evaluate` sees the recording: the true labels (renderLabels) and the
// classification by the table calibrated from frame `calibration_frame` as make_scenario
// samples it (2 px inside each object). BGR presets only.
template <typename Visit>
void classifyHeldOutRecording(const std::string& name, int seed, int calibration_frame, Visit visit) {
  ScenarioConfig scenario = preset(name);
  scenario.seed = seed;
  const FieldGeometry field;
  const PatternSet patterns = patternSetByName(scenario.pattern);
  const CameraModel camera = scenarioCamera(field, 0, scenario);
  GameSimulator sim(scenario, field, patterns.maxRobotsPerTeam());
  const FieldRenderer renderer(camera, field, patterns, scenario);
  std::vector<SceneState> states{sim.state()};
  for (int i = 1; i < 240; ++i) {
    sim.step(1.0 / scenario.fps);
    states.push_back(sim.state());
  }
  const auto shown = [&](int i) { return extrapolate(states[i], shownTimeAfterStamp(scenario.sensor)); };
  RenderedFrame frame;
  renderer.render(states[calibration_frame], calibration_frame, frame);
  const ColorSamples samples =
      calibrationSamples(shown(calibration_frame), camera, field, patterns, SampleOptions::drawnByUser(2));
  const auto model = SegmentationModel::fromTable(
      std::make_shared<const ColorTable>(calibrateColorTable({{frame.image, samples}})));
  for (int i = 0; i < 240; i += 6) {
    renderer.render(states[i], i, frame);
    visit(renderer.renderLabels(shown(i)),
          classifyAll(*model, frame.image, PixelLayout::Bgr, SegmentationParams{}));
  }
}

// Pixels of colour `truth_class` (renderLabels) read as `read`.
std::int64_t countReadAs(const cv::Mat1b& truth, const cv::Mat1b& labels, ColorClass truth_class,
                         ColorClass read) {
  std::int64_t n = 0;
  for (int y = 0; y < truth.rows; ++y) {
    for (int x = 0; x < truth.cols; ++x)
      n += truth(y, x) == static_cast<std::uint8_t>(truth_class) &&
           labels(y, x) == static_cast<std::uint8_t>(read);
  }
  return n;
}

}  // namespace

// Held-out seed 9063 of rand_fast (spent): of the calibration frame's (76) three yellow
// tags one, yellow 3's, is another print, hue 36-46° where the others read 54°. Most of
// its pixels were valid, so it was no print of its own, and the class's Gaussian, centred
// between the prints, left the colours around it to the ball's orange: blurred or under
// another lamp its tag read orange, its robot was lost for 2 s (measured 97.1 %) and parts
// of the tag became balls. The table confused it with the ball when first built, so it is
// built again with that tag as a print of its own (ColorTable::buildFromSamplePixels).
TEST(OneFrameTable, ATagPrintedCloseToTheBallsOrangeKeepsItsColour) {
  Accuracy yellow;
  std::int64_t yellow_as_orange = 0;
  classifyHeldOutRecording("rand_fast", 9063, 76, [&](const cv::Mat1b& truth, const cv::Mat1b& labels) {
    countMarkerInteriors(truth, labels, yellow, {ColorClass::Yellow});
    yellow_as_orange += countReadAs(truth, labels, ColorClass::Yellow, ColorClass::Orange);
  });
  std::printf("[ rand_fast 9063 ] yellow interiors %.3f %% of %ld; yellow pixels read orange %ld\n",
              100 * yellow.markers(), static_cast<long>(yellow.interior),
              static_cast<long>(yellow_as_orange));
  // Without the second build: 94.74 % and 2183 (the tag's rims, blurred with the robot's
  // top, read orange either way).
  EXPECT_GE(yellow.markers(), 0.97);
  EXPECT_LE(yellow_as_orange, 2000);
}
