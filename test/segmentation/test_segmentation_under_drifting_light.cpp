// Segmentation accuracy against the synthetic camera's per-pixel labels (the issue's
// acceptance test): a table calibrated on ONE frame (camera 0, frame 0, the
// calibrationSamples polygons incl. background classes), then frames over 20 s of the
// uneven-drifting-light preset, with illumination adaptation off (the table of V as
// captured, no adaptation), the paper's (k = 0.3) and on (normalised V, the default).
//
// Marker interior: a pixel whose label is a marker colour and whose 8 neighbours share it
// (edge pixels are mixtures). Background: a non-marker pixel with no marker pixel among its
// 8 neighbours; a false positive is one classified as a marker colour.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "marker_interior_accuracy.h"
#include "soccer_vision/calibration/color_calibration.h"
#include "soccer_vision/segmentation/segmenter.h"
#include "soccer_vision/simulation/calibration_samples.h"
#include "soccer_vision/simulation/field_renderer.h"
#include "soccer_vision/simulation/game_simulator.h"

using namespace soccer_vision;
using soccer_vision::test::Accuracy;
using soccer_vision::test::countMarkerInteriors;

namespace {

struct Mode {
  const char* name;
  CalibrationLight light;
  double k;
  double sharpen = 0.0;
};
constexpr Mode kOff{"off", CalibrationLight::AsCaptured, 0.0};
constexpr Mode kPaper{"paper k=0.3", CalibrationLight::AsCaptured, 0.3};
constexpr Mode kOn{"on (normalised)", CalibrationLight::Normalized, 0.3};
constexpr Mode kOnSharpened{"on + sharpen 0.5", CalibrationLight::Normalized, 0.3, 0.5};

// Accuracy of each mode on `frames` frames spread over `seconds` after the calibration.
std::vector<Accuracy> measure(const ScenarioConfig& scenario, const std::vector<Mode>& modes, int frames,
                              double seconds) {
  const FieldGeometry field;
  const PatternSet patterns = patternSetByName(scenario.pattern);
  GameSimulator sim(scenario, field, patterns.maxRobotsPerTeam());
  const FieldRenderer renderer(CameraModel::defaultCamera(field, 0, scenario.width, scenario.height), field,
                               patterns, scenario);
  RenderedFrame calibration;
  renderer.render(sim.state(), 0, calibration);
  const ColorSamples samples = calibrationSamples(sim.state(), renderer.camera(), field, patterns);
  std::vector<std::shared_ptr<const SegmentationModel>> models;
  for (const Mode& m : modes) {
    models.push_back(SegmentationModel::fromTable(std::make_shared<const ColorTable>(
        calibrateColorTable({{calibration.image, samples}}, {}, m.light))));
  }
  std::vector<Accuracy> out(modes.size());
  const int steps_between = static_cast<int>(seconds * scenario.fps / frames);
  std::int64_t index = 0;
  for (int f = 0; f < frames; ++f) {
    for (int i = 0; i < steps_between; ++i, ++index) sim.step(1.0 / scenario.fps);
    RenderedFrame frame;
    renderer.render(sim.state(), index, frame);
    const cv::Mat1b truth = renderer.renderLabels(sim.state());
    for (std::size_t m = 0; m < modes.size(); ++m) {
      SegmentationParams params;
      params.illumination_k = modes[m].k;
      params.sharpen = modes[m].sharpen;
      countMarkerInteriors(truth, classifyAll(*models[m], frame.image, PixelLayout::Bgr, params), out[m]);
    }
  }
  for (std::size_t m = 0; m < modes.size(); ++m) {
    std::printf("[ %s ] %-16s marker interiors %.3f %% of %ld, background -> marker %.5f %% of %ld\n",
                scenario.name.c_str(), modes[m].name, 100 * out[m].markers(),
                static_cast<long>(out[m].interior), 100 * out[m].falsePositives(),
                static_cast<long>(out[m].background));
  }
  return out;
}

}  // namespace

// The bar. Measured (10 frames over 20 s, v_margin 8 in all modes): off 62.0 %,
// paper 57.3 %, on 99.41 % (the misses are mostly purple, ~96 %: its one calibration
// marker leaves HS cells other purple pixels fall into), no false positive in any mode.
// Sharpening (paper §IV, 0.5) on top: 97.79 %: in flat marker interiors the Laplacian is
// sensor noise, which it amplifies; it is off by default.
TEST(SegmentationAccuracy, UnevenDriftingLightCalibratedOnOneFrame) {
  const ScenarioConfig scenario =
      loadScenario(std::string(SOCCER_VISION_SOURCE_DIR) + "/config/scenarios/uneven_drift.yaml");
  const std::vector<Accuracy> a = measure(scenario, {kOff, kPaper, kOn, kOnSharpened}, 10, 20.0);
  ASSERT_GT(a[2].interior, 2000);
  EXPECT_GE(a[2].markers(), 0.99);
  EXPECT_LE(a[2].falsePositives(), 1e-4);
  EXPECT_GE(a[2].markers(), a[0].markers());
  EXPECT_LE(a[2].falsePositives(), a[0].falsePositives() + 1e-5);
}

// Even light: adaptation has nothing to correct and must not make things worse. The
// misses (~6 %) are HS cells one frame of samples did not reach (and the ball, not in
// camera 0's first frame), the same with and without adaptation up to the noise of the
// measured levels: one pixel of 1695 (a bright marker pixel at its cell's V border).
TEST(SegmentationAccuracy, EvenLightAdaptationDoesNotMakeThingsWorse) {
  ScenarioConfig scenario;
  scenario.name = "even";
  const std::vector<Accuracy> a = measure(scenario, {kOff, kOn}, 4, 8.0);
  EXPECT_GE(a[1].markers(), a[0].markers() - 0.002);
  EXPECT_LE(a[1].falsePositives(), 1e-4);
}

// Bayer input is segmented at quad resolution with quadLabelParams: the markers come out
// where the bgr8 frame puts them (OpenCV's off-centre even kernel shifted them by ~5 px,
// the 3x3 one of bgr8 would erase the 3-quad-wide team tags).
TEST(SegmentationBayer, QuadRegionsLieWhereTheColourFramePutsThem) {
  ScenarioConfig colour;
  ScenarioConfig mosaic = colour;
  mosaic.sensor.bayer = "rggb";
  const FieldGeometry field;
  const PatternSet patterns = patternSetByName(colour.pattern);
  const CameraModel camera = CameraModel::defaultCamera(field, 0, colour.width, colour.height);
  GameSimulator sim(colour, field, patterns.maxRobotsPerTeam());
  const FieldRenderer bgr_renderer(camera, field, patterns, colour),
      bayer_renderer(camera, field, patterns, mosaic);
  RenderedFrame bgr, bayer;
  bgr_renderer.render(sim.state(), 0, bgr);
  bayer_renderer.render(sim.state(), 0, bayer);
  const auto model = SegmentationModel::fromTable(std::make_shared<const ColorTable>(
      calibrateColorTable({{bgr.image, calibrationSamples(sim.state(), camera, field, patterns)}})));
  Segmenter segmenter;
  SegmentationResult from_bgr, from_bayer;
  segmenter.process(*model, bgr.image, PixelLayout::Bgr, {}, from_bgr);
  segmenter.process(*model, bayer.image, PixelLayout::BayerRggb, {}, from_bayer);
  ASSERT_GE(from_bgr.regions.size(), 8u);
  std::vector<double> distances;
  for (const Region& r : from_bgr.regions) {
    double best = 1e9;
    for (const Region& q : from_bayer.regions) {
      if (q.color == r.color) best = std::min(best, std::hypot(q.cx - r.cx, q.cy - r.cy));
    }
    distances.push_back(best);
  }
  std::sort(distances.begin(), distances.end());
  const auto within = std::count_if(distances.begin(), distances.end(), [](double d) { return d < 1.5; });
  std::printf("  %zu bgr8 regions, %zu Bayer regions, median centroid distance %.2f px, %ld within 1.5 px\n",
              from_bgr.regions.size(), from_bayer.regions.size(), distances[distances.size() / 2],
              static_cast<long>(within));
  // Measured: 13 of 14 within 0.9 px; one robot's tags (top left of the image) are not
  // segmented from the quads, a table hole of the quad colours left for later.
  EXPECT_LT(distances[distances.size() / 2], 1.0);
  EXPECT_GE(within, static_cast<long>(distances.size()) * 85 / 100);
  const RegionParams q = quadLabelParams(RegionParams{});
  EXPECT_EQ(q.morph_kernel, 1);
  EXPECT_EQ(quadLabelParams([] {
              RegionParams p;
              p.morph_kernel = 7;
              return p;
            }())
                .morph_kernel,
            3);
  EXPECT_EQ(q.min_area, 1);
}

// Lower resolutions scale the region parameters given for 1280 px: the 2x2 opening is kept
// down to 960 px and halved below (a 3x3 one found 71 % of the robots at 780 px, at 640 px
// none; the pipeline tests at 780x580 in test_evaluation), areas go with the pixel count.
TEST(LabelParams, ScaleTheRegionParametersToTheLabelWidth) {
  const RegionParams p;  // kernel 2, min_area 5, max_area 20000, tile 16
  const RegionParams same = labelParams(p, 2448);
  EXPECT_EQ(same.morph_kernel, 2);
  EXPECT_EQ(same.min_area, p.min_area);
  EXPECT_EQ(same.max_area, p.max_area);
  EXPECT_EQ(labelParams(p, 1280).tile_size, p.tile_size);
  EXPECT_EQ(labelParams(p, 960).morph_kernel, 2);
  const RegionParams low = labelParams(p, 780);
  EXPECT_EQ(low.morph_kernel, 1);
  EXPECT_TRUE(low.require_pair);
  EXPECT_EQ(low.min_area, 2);     // 5 x (780 / 1280)^2 = 1.86
  EXPECT_EQ(low.max_area, 7427);  // 20000 x 0.371
  EXPECT_EQ(low.tile_size, 10);
  const RegionParams quads = quadLabelParams(p);  // = labelParams(p, 640)
  EXPECT_EQ(quads.max_area, labelParams(p, 640).max_area);
  EXPECT_EQ(quads.tile_size, 8);
  RegionParams off = p;
  off.morph_kernel = 0;
  EXPECT_EQ(labelParams(off, 640).morph_kernel, 0);
}

// classifiedColors: the colours the classifier reads, on the image's own grid.
TEST(ClassifiedColors, QuadColoursFillTheirQuadsAndBgrStaysAsItIs) {
  cv::Mat3b bgr(4, 6);
  for (int y = 0; y < bgr.rows; ++y) {
    for (int x = 0; x < bgr.cols; ++x) bgr(y, x) = cv::Vec3b(10 * x, 20 * y, 7 * x + 3 * y);
  }
  EXPECT_EQ(cv::norm(classifiedColors(bgr, PixelLayout::Bgr), bgr, cv::NORM_INF), 0.0);
  cv::Mat3b rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  EXPECT_EQ(cv::norm(classifiedColors(rgb, PixelLayout::Rgb), bgr, cv::NORM_INF), 0.0);
  // RGGB: R at (0, 0), G at (1, 0) and (0, 1), B at (1, 1) of each quad.
  cv::Mat1b raw(4, 6);
  for (int y = 0; y < raw.rows; ++y) {
    for (int x = 0; x < raw.cols; ++x)
      raw(y, x) =
          static_cast<std::uint8_t>(y % 2 == 0 ? (x % 2 == 0 ? 200 : 100 + x) : (x % 2 == 0 ? 101 + y : 50));
  }
  const cv::Mat3b quads = classifiedColors(raw, PixelLayout::BayerRggb);
  ASSERT_EQ(quads.size(), raw.size());
  for (int y = 0; y < raw.rows; ++y) {
    for (int x = 0; x < raw.cols; ++x) {
      const int qx = x / 2 * 2, qy = y / 2 * 2;
      const cv::Vec3b want(raw(qy + 1, qx + 1),
                           static_cast<std::uint8_t>((raw(qy, qx + 1) + raw(qy + 1, qx) + 1) >> 1),
                           raw(qy, qx));
      ASSERT_EQ(quads(y, x), want) << x << ", " << y;
    }
  }
  EXPECT_THROW(classifiedColors(cv::Mat1b(3, 4), PixelLayout::BayerRggb), std::invalid_argument);
}
