// Evaluation figures (plot_canvas.h, evaluation_plots.h, sample_statistics.h): tick values,
// where data land in the rendered image (read back pixel by pixel), gaps at NaN, and that
// each figure writes a PNG of the expected size with its series' colours in it.
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "evaluation_plots.h"
#include "plot_canvas.h"
#include "soccer_vision/common/statistics.h"

using namespace soccer_vision;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const cv::Scalar kRed(0, 0, 220), kGreen(0, 160, 0), kBlue(200, 60, 0);

void expectTicks(const std::vector<double>& got, const std::vector<double>& expected) {
  ASSERT_EQ(got.size(), expected.size());
  for (size_t i = 0; i < got.size(); ++i)
    EXPECT_NEAR(got[i], expected[i], 1e-12 * (1 + std::abs(expected[i]))) << i;
}

bool near(const cv::Vec3b& px, const cv::Scalar& c, int tolerance) {
  for (int k = 0; k < 3; ++k)
    if (std::abs(px[k] - static_cast<int>(std::lround(c[k]))) > tolerance) return false;
  return true;
}

// Pixels of img (inside rect) within tolerance of colour c in every channel.
int countColor(const cv::Mat& img, const cv::Scalar& c, int tolerance = 8, cv::Rect rect = cv::Rect()) {
  if (rect.empty()) rect = cv::Rect(0, 0, img.cols, img.rows);
  int n = 0;
  for (int y = rect.y; y < rect.y + rect.height; ++y)
    for (int x = rect.x; x < rect.x + rect.width; ++x) n += near(img.at<cv::Vec3b>(y, x), c, tolerance);
  return n;
}

cv::Vec3b pixelAt(const cv::Mat& img, cv::Point2d p) {
  return img.at<cv::Vec3b>(static_cast<int>(std::lround(p.y)), static_cast<int>(std::lround(p.x)));
}

// Mean column of the pixels of colour c (NaN if none).
double meanColumn(const cv::Mat& img, const cv::Scalar& c) {
  double sum = 0;
  int n = 0;
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x)
      if (near(img.at<cv::Vec3b>(y, x), c, 4)) sum += x, ++n;
  return n ? sum / n : kNaN;
}

std::string tempDir() {
  const auto dir =
      std::filesystem::temp_directory_path() /
      ("test_evaluation_plots_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
       std::to_string(std::random_device{}()));
  std::filesystem::create_directories(dir);
  return dir.string();
}

}  // namespace

// ---------------------------------------------------------------------------------------
TEST(NiceTicks, KnownRanges) {
  expectTicks(niceTicks(0, 9), {0, 2, 4, 6, 8});
  expectTicks(niceTicks(9, 0), {0, 2, 4, 6, 8});  // ends swapped
  expectTicks(niceTicks(-3, 3), {-3, -2, -1, 0, 1, 2, 3});
  expectTicks(niceTicks(-7.5, -1.2), {-7, -6, -5, -4, -3, -2});
  expectTicks(niceTicks(-4.8, 4.8, 10), {-4, -3, -2, -1, 0, 1, 2, 3, 4});
  expectTicks(niceTicks(0, 1000, 6), {0, 200, 400, 600, 800, 1000});
  expectTicks(niceTicks(0.001, 0.0013), {0.001, 0.00105, 0.0011, 0.00115, 0.0012, 0.00125, 0.0013});
  expectTicks(niceTicks(0, 1e-6), {0, 2e-7, 4e-7, 6e-7, 8e-7, 1e-6});
  EXPECT_DOUBLE_EQ(niceTickStep(0, 9), 2);
  EXPECT_DOUBLE_EQ(niceTickStep(1e9, 1e9 + 3), 0.5);  // far from zero, small span
}

TEST(NiceTicks, ZeroWidthRangeIsWidenedAroundTheValue) {
  expectTicks(niceTicks(5, 5), {4.6, 4.8, 5.0, 5.2, 5.4});  // 5 ± 0.5
  expectTicks(niceTicks(0, 0), {-0.4, -0.2, 0, 0.2, 0.4});
  EXPECT_EQ(niceTicks(0, 0)[2], 0.0);                     // exactly zero, not 1e-17
  const std::vector<double> big = niceTicks(2000, 2000);  // ± 5 %
  EXPECT_GE(big.size(), 2u);
  EXPECT_GE(big.front(), 1900);
  EXPECT_LE(big.back(), 2100);
}

TEST(NiceTicks, StepsAreOneTwoFiveAndTicksStayInsideTheRange) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> exponent(-6, 6), unit(-1, 1);
  for (int i = 0; i < 2000; ++i) {
    const double scale = std::pow(10.0, exponent(rng));
    const double a = unit(rng) * scale, b = unit(rng) * scale;
    if (a == b) continue;
    const int max_ticks = 2 + i % 10;
    const double step = niceTickStep(a, b, max_ticks);
    const double mantissa = step / std::pow(10.0, std::floor(std::log10(step) + 1e-9));
    EXPECT_TRUE(std::abs(mantissa - 1) < 1e-9 || std::abs(mantissa - 2) < 1e-9 ||
                std::abs(mantissa - 5) < 1e-9)
        << a << " .. " << b << ": step " << step;
    const std::vector<double> ticks = niceTicks(a, b, max_ticks);
    ASSERT_GE(ticks.size(), 1u) << a << " .. " << b;
    EXPECT_LE(static_cast<int>(ticks.size()), max_ticks) << a << " .. " << b;
    const double tol = 1e-9 * step;
    EXPECT_GE(ticks.front(), std::min(a, b) - tol);
    EXPECT_LE(ticks.back(), std::max(a, b) + tol);
    for (size_t k = 1; k < ticks.size(); ++k) EXPECT_NEAR(ticks[k] - ticks[k - 1], step, tol * 10);
    // The smallest such step: the next smaller nice step (1 -> 0.5, 2 -> 1, 5 -> 2) gives
    // more than max_ticks ticks.
    const double smaller = std::abs(mantissa - 5) < 1e-9 ? step * 0.4 : step * 0.5;
    const double lo = std::min(a, b), hi = std::max(a, b);
    const double more = std::floor(hi / smaller + 1e-9) - std::ceil(lo / smaller - 1e-9) + 1;
    EXPECT_GT(more, max_ticks) << a << " .. " << b << ": step " << step;
  }
}

TEST(NiceTicks, BadArgumentsThrow) {
  EXPECT_THROW(niceTicks(kNaN, 1), std::invalid_argument);
  EXPECT_THROW(niceTicks(0, std::numeric_limits<double>::infinity()), std::invalid_argument);
  EXPECT_THROW(niceTicks(0, 1, 1), std::invalid_argument);
}

TEST(NiceTicks, Labels) {
  EXPECT_EQ(formatTick(1.4000000000000001, 0.2), "1.4");
  EXPECT_EQ(formatTick(4, 2), "4");
  EXPECT_EQ(formatTick(-1e-17, 0.2), "0");  // never "-0"
  EXPECT_EQ(formatTick(0.00105, 5e-5), "0.00105");
  EXPECT_EQ(formatTick(-2.5, 0.5), "-2.5");
  EXPECT_EQ(formatTick(2e6, 1e6), "2e+06");
  EXPECT_EQ(formatTick(4e-7, 2e-7), "4e-07");
}

TEST(SampleStatistics, PercentilesAndRmsSkipMissingValues) {
  EXPECT_DOUBLE_EQ(percentile({4, 1, 3, 2}, 50), 2.5);
  EXPECT_DOUBLE_EQ(percentile({4, 1, kNaN, 3, 2}, 0), 1);
  EXPECT_DOUBLE_EQ(percentile({4, 1, 3, 2, std::numeric_limits<double>::infinity()}, 100), 4);
  std::vector<double> hundred;
  for (int i = 1; i <= 100; ++i) hundred.push_back(i);
  EXPECT_NEAR(percentile(hundred, 99), 99.01, 1e-12);
  EXPECT_TRUE(std::isnan(percentile({kNaN}, 50)));
  EXPECT_THROW(percentile(hundred, 101), std::invalid_argument);
  EXPECT_DOUBLE_EQ(rootMeanSquare({3, 4, kNaN}), std::sqrt(12.5));
  EXPECT_TRUE(std::isnan(rootMeanSquare({})));
}

// ---------------------------------------------------------------------------------------
TEST(PlotCanvas, DataPointsLandOnTheirPixels) {
  PlotCanvas c(1000, 700);
  c.setTitle("mapping");
  c.setXLabel("x");
  c.setYLabel("y");
  c.setXRange(0, 10);
  c.setYRange(0, 5);
  c.setLegendPosition(LegendPosition::None);
  c.addScatter({2.5}, {1.0}, kRed, "", 5);
  c.addScatter({7.5}, {4.0}, kBlue, "", 5);
  const cv::Mat img = c.render();
  ASSERT_EQ(img.size(), cv::Size(1000, 700));

  const cv::Rect area = c.plotArea();
  EXPECT_GT(area.width, 800);
  EXPECT_GT(area.height, 550);
  const cv::Point2d origin = c.toPixel(0, 0), corner = c.toPixel(10, 5);
  EXPECT_NEAR(origin.x, area.x, 1e-9);
  EXPECT_NEAR(origin.y, area.y + area.height - 1, 1e-9);
  EXPECT_NEAR(corner.x, area.x + area.width - 1, 1e-9);
  EXPECT_NEAR(corner.y, area.y, 1e-9);

  const cv::Point2d red = c.toPixel(2.5, 1.0), blue = c.toPixel(7.5, 4.0);
  EXPECT_NEAR(red.x, area.x + 0.25 * (area.width - 1), 1e-9);
  EXPECT_TRUE(near(pixelAt(img, red), kRed, 2)) << pixelAt(img, red);
  EXPECT_TRUE(near(pixelAt(img, blue), kBlue, 2)) << pixelAt(img, blue);
  // A radius-5 dot: filled 3 px from its centre, nothing 9 px away.
  EXPECT_TRUE(near(pixelAt(img, red + cv::Point2d(3, 0)), kRed, 2));
  EXPECT_FALSE(near(pixelAt(img, red + cv::Point2d(9, 0)), kRed, 60));
  EXPECT_FALSE(near(pixelAt(img, red + cv::Point2d(0, -9)), kRed, 60));
  EXPECT_EQ(countColor(img, kRed, 2, cv::Rect(area.x + area.width / 2, 0, area.width / 2, img.rows)), 0);
}

TEST(PlotCanvas, EqualAspectKeepsMetresSquare) {
  PlotCanvas c(1000, 700);  // plot area much wider than tall
  c.setXRange(-1, 1);
  c.setYRange(-3, 3);
  c.setEqualAspect(true);
  c.setLegendPosition(LegendPosition::None);
  // A 1 m × 1 m square outline.
  c.addPolyline({0, 1, 1, 0, 0}, {0, 0, 1, 1, 0}, kGreen, "", LineStyle::Solid, 1);
  const double px_per_m_x = c.toPixel(1, 0).x - c.toPixel(0, 0).x;
  const double px_per_m_y = c.toPixel(0, 0).y - c.toPixel(0, 1).y;
  EXPECT_NEAR(px_per_m_x, px_per_m_y, 1e-9);
  EXPECT_GT(px_per_m_x, 50);
  // The requested ranges are still inside the (widened) axes.
  EXPECT_LE(c.xRange()[0], -1);
  EXPECT_GE(c.xRange()[1], 1);
  EXPECT_NEAR(c.yRange()[0], -3, 1e-9);  // the limiting axis keeps its range
  EXPECT_NEAR(c.yRange()[1], 3, 1e-9);

  const cv::Mat img = c.render();
  int x0 = img.cols, x1 = -1, y0 = img.rows, y1 = -1;
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x)
      if (near(img.at<cv::Vec3b>(y, x), kGreen, 40))
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  ASSERT_GE(x1, 0);
  EXPECT_NEAR(x1 - x0, y1 - y0, 1.0);  // drawn square, in pixels
  EXPECT_NEAR(x1 - x0, px_per_m_x, 2.0);
}

TEST(PlotCanvas, NaNBreaksAPolyline) {
  PlotCanvas c(1000, 700);
  c.setXRange(0, 10);
  c.setYRange(0, 5);
  c.setLegendPosition(LegendPosition::None);
  std::vector<double> xs, ys;
  for (int i = 0; i <= 10; ++i) xs.push_back(i), ys.push_back(2.5);
  ys[4] = ys[5] = kNaN;
  ys[6] = std::numeric_limits<double>::infinity();
  c.addPolyline(xs, ys, kGreen, "", LineStyle::Solid, 2);
  const cv::Mat img = c.render();
  const int row = static_cast<int>(std::lround(c.toPixel(0, 2.5).y));
  const cv::Rect band_before(static_cast<int>(c.toPixel(0.5, 0).x), row - 3,
                             static_cast<int>(c.toPixel(2.5, 0).x - c.toPixel(0.5, 0).x), 7);
  const cv::Rect gap(static_cast<int>(c.toPixel(3, 0).x) + 4, row - 3,
                     static_cast<int>(c.toPixel(7, 0).x - c.toPixel(3, 0).x) - 8, 7);
  const cv::Rect band_after(static_cast<int>(c.toPixel(7.5, 0).x), row - 3,
                            static_cast<int>(c.toPixel(9.5, 0).x - c.toPixel(7.5, 0).x), 7);
  EXPECT_GE(countColor(img, kGreen, 10, band_before), band_before.width);  // every column has it
  EXPECT_GE(countColor(img, kGreen, 10, band_after), band_after.width);
  EXPECT_EQ(countColor(img, kGreen, 80, gap), 0);
}

TEST(PlotCanvas, DashedLinesHaveGapsAndSolidOnesNone) {
  PlotCanvas c(1000, 700);
  c.setXRange(0, 10);
  c.setYRange(0, 4);
  c.setLegendPosition(LegendPosition::None);
  c.setGrid(false);
  c.addPolyline({0, 10}, {1, 1}, kGreen, "", LineStyle::Solid, 2);
  c.addPolyline({0, 10}, {3, 3}, kRed, "", LineStyle::Dashed, 2);
  const cv::Mat img = c.render();
  const cv::Rect area = c.plotArea();
  auto columnsWith = [&](double y, const cv::Scalar& color) {
    const int row = static_cast<int>(std::lround(c.toPixel(0, y).y));
    int n = 0;
    for (int x = area.x + 10; x < area.x + area.width - 10; ++x) {
      bool hit = false;
      for (int dy = -2; dy <= 2; ++dy) hit = hit || near(img.at<cv::Vec3b>(row + dy, x), color, 10);
      n += hit;
    }
    return n;
  };
  const int span = area.width - 20;
  EXPECT_EQ(columnsWith(1, kGreen), span);
  const int dashed = columnsWith(3, kRed);
  // 10 px on, 7 px off, plus the round caps: about 70 % of the columns.
  EXPECT_GT(dashed, span * 0.5);
  EXPECT_LT(dashed, span * 0.82);
}

TEST(PlotCanvas, HistogramBarsReachTheirCounts) {
  PlotCanvas c(1000, 700);
  c.setYRange(0, 5);
  c.setLegendPosition(LegendPosition::None);
  c.addBars({0, 1, 2, 3}, {2, 4, 1}, kBlue, "frames");
  const cv::Mat img = c.render();
  EXPECT_TRUE(near(pixelAt(img, c.toPixel(0.5, 1.9)), kBlue, 2));
  EXPECT_FALSE(near(pixelAt(img, c.toPixel(0.5, 2.1)), kBlue, 60));
  EXPECT_TRUE(near(pixelAt(img, c.toPixel(1.5, 3.9)), kBlue, 2));
  EXPECT_FALSE(near(pixelAt(img, c.toPixel(1.5, 4.1)), kBlue, 60));
  EXPECT_TRUE(near(pixelAt(img, c.toPixel(2.5, 0.9)), kBlue, 2));
  EXPECT_FALSE(near(pixelAt(img, c.toPixel(2.5, 1.1)), kBlue, 60));
  EXPECT_LE(c.xRange()[0], 0);  // autoscaled x covers the edges
  EXPECT_GE(c.xRange()[1], 3);
}

TEST(PlotCanvas, NoDataStillRendersAndSaysSo) {
  PlotCanvas empty(600, 400);
  empty.setTitle("nothing");
  EXPECT_FALSE(empty.hasData());
  const cv::Mat a = empty.render();
  PlotCanvas all_nan(600, 400);
  all_nan.setTitle("nothing");
  all_nan.addPolyline({kNaN, 1}, {0, kNaN}, kGreen, "series");
  all_nan.setLegendPosition(LegendPosition::None);
  EXPECT_FALSE(all_nan.hasData());
  const cv::Mat b = all_nan.render();
  for (const cv::Mat* img : {&a, &b}) {
    ASSERT_EQ(img->size(), cv::Size(600, 400));
    // the grey note in the middle of the plot area
    const cv::Rect area = empty.plotArea();
    const cv::Rect middle(area.x + area.width / 4, area.y + area.height / 3, area.width / 2, area.height / 3);
    EXPECT_GT(countColor(*img, cv::Scalar(150, 150, 150), 60, middle), 100);
  }
}

TEST(PlotCanvas, BadInputGivesClearErrors) {
  PlotCanvas c(600, 400);
  EXPECT_THROW(c.addPolyline({1, 2}, {1}, kGreen), std::invalid_argument);
  EXPECT_THROW(c.addBars({0, 1}, {1, 2}, kGreen), std::invalid_argument);
  EXPECT_THROW(c.setXRange(2, 1), std::invalid_argument);
  EXPECT_THROW(c.setYRange(0, std::numeric_limits<double>::infinity()), std::invalid_argument);
  EXPECT_THROW(PlotCanvas(100, 100), std::invalid_argument);
  cv::Mat wrong(100, 100, CV_8UC3);
  EXPECT_THROW(c.renderInto(wrong), std::invalid_argument);
}

TEST(PlotCanvas, AbsurdCoordinatesAreClippedNotCrashed) {
  PlotCanvas c(600, 400);
  c.setXRange(0, 1);
  c.setYRange(0, 1);
  c.addPolyline({0, 0.5, 1e300}, {0, 0.5, -1e300}, kGreen, "", LineStyle::Dashed);
  c.addScatter({1e200}, {5}, kRed);
  c.addFilledPolygon({-1e250, 1e250, 0}, {0, 0, 1e250}, kBlue);
  EXPECT_NO_THROW(c.render());
}

// ---------------------------------------------------------------------------------------
namespace {

std::vector<TrajectorySeries> twoRobots() {
  TrajectorySeries blue{"blue 0", "blue", {}, {}, {}, {}, {}};
  TrajectorySeries yellow{"yellow 0", "yellow", {}, {}, {}, {}, {}};
  for (int i = 0; i < 120; ++i) {
    const double t = 1.7e9 + i / 60.0, a = i / 120.0 * 3.0;
    blue.t.push_back(t);
    blue.truth_x.push_back(-2.0 - std::cos(a));
    blue.truth_y.push_back(std::sin(a));
    blue.tracked_x.push_back(i >= 50 && i < 60 ? kNaN : blue.truth_x.back() + 0.02);
    blue.tracked_y.push_back(i >= 50 && i < 60 ? kNaN : blue.truth_y.back());
    yellow.t.push_back(t);
    yellow.truth_x.push_back(2.0 + 0.01 * i);
    yellow.truth_y.push_back(-1.0 + 0.015 * i);
    yellow.tracked_x.push_back(yellow.truth_x.back());
    yellow.tracked_y.push_back(yellow.truth_y.back() - 0.03);
  }
  return {blue, yellow};
}

}  // namespace

TEST(EvaluationPlots, TrajectoriesShowEachRobotInItsTeamColourWhereItDrove) {
  const cv::Mat img = renderTrajectories(twoRobots(), FieldGeometry{});
  ASSERT_EQ(img.size(), cv::Size(1300, 800));
  const cv::Scalar blue = trajectoryColor("blue", 0), yellow = trajectoryColor("yellow", 0);
  EXPECT_NE(blue, yellow);
  EXPECT_NE(trajectoryColor("blue", 0), trajectoryColor("blue", 1));
  EXPECT_GT(countColor(img, blue, 6), 150);
  EXPECT_GT(countColor(img, yellow, 6), 150);
  EXPECT_GT(countColor(img, truthShade(blue), 6), 300);
  EXPECT_GT(countColor(img, truthShade(yellow), 6), 300);
  // Blue drove at x < -1 m, yellow at x > 2 m: their pale truth lines lie left and right.
  EXPECT_LT(meanColumn(img, truthShade(blue)), img.cols * 0.4);
  EXPECT_GT(meanColumn(img, truthShade(yellow)), meanColumn(img, truthShade(blue)) + 200);
}

TEST(EvaluationPlots, AWildPositionDoesNotShrinkTheField) {
  auto robots = twoRobots();
  const cv::Mat normal = renderTrajectories(robots, FieldGeometry{});
  robots[1].tracked_x[3] = 1e300;  // a broken track
  robots[1].tracked_y[4] = -40.0;
  const cv::Mat wild = renderTrajectories(robots, FieldGeometry{});
  const cv::Scalar carpet = cv::Scalar(normal.at<cv::Vec3b>(normal.rows / 2, normal.cols / 3));
  const int carpet_px = countColor(normal, carpet, 2);
  EXPECT_GT(carpet_px, normal.total() / 3);  // the field fills the figure
  EXPECT_NEAR(countColor(wild, carpet, 2), carpet_px, carpet_px * 0.01);
}

TEST(EvaluationPlots, PositionErrorHasBothSeries) {
  ErrorSeries e;
  for (int i = 0; i < 300; ++i) {
    e.t.push_back(100 + i / 60.0);
    e.robot_error_mm.push_back(8 + 4 * std::sin(i * 0.1));
    e.ball_error_mm.push_back(i % 50 < 5 ? kNaN : 5 + 3 * std::cos(i * 0.07));
  }
  const cv::Mat img = renderPositionError(e);
  ASSERT_EQ(img.size(), cv::Size(1000, 700));
  EXPECT_GT(countColor(img, robotErrorColor(), 20), 200);
  EXPECT_GT(countColor(img, ballErrorColor(), 20), 200);
  e.ball_error_mm.pop_back();
  EXPECT_THROW(renderPositionError(e), std::invalid_argument);
}

TEST(EvaluationPlots, StageTimingHasOneHistogramPerStage) {
  StageTimes s;
  s.stage = {"segmentation", "identification", "tracking"};
  std::mt19937 rng(3);
  std::gamma_distribution<double> g(9.0, 0.2);
  s.ms.resize(3);
  for (int i = 0; i < 2000; ++i) {
    s.ms[0].push_back(3.0 + g(rng));
    s.ms[1].push_back(0.4 + 0.1 * g(rng));
    s.ms[2].push_back(i == 7 ? 50.0 : 0.05 + 0.01 * g(rng));  // one hiccup: a cut tail
  }
  const cv::Mat img = renderStageTimingHistogram(s);
  ASSERT_EQ(img.size(), cv::Size(1000, 44 + 2 * 330));  // 2 × 2 panels under the title
  for (int i = 0; i < 3; ++i)
    EXPECT_GT(countColor(img, stageColor(i), 6), 2000) << s.stage[static_cast<size_t>(i)];
  EXPECT_EQ(countColor(img, stageColor(3), 6), 0);  // the fourth panel is empty
  s.ms.pop_back();
  EXPECT_THROW(renderStageTimingHistogram(s), std::invalid_argument);
}

TEST(EvaluationPlots, PredictionErrorPanelsShareTheirScale) {
  std::vector<PredictionErrorSeries> series;
  for (int step : {2, 1}) {  // out of order on purpose
    PredictionErrorSeries p;
    p.frame_step = step;
    for (int i = 0; i < 200; ++i) {
      p.t.push_back(50 + i / 30.0);
      p.error_mm.push_back(10.0 * step);
    }
    series.push_back(p);
  }
  const cv::Mat img = renderPredictionError(series);
  ASSERT_EQ(img.size(), cv::Size(1000, 44 + 656));
  const cv::Scalar red = predictionErrorColor();
  // Step 1 (left panel, after sorting) sits at half the height of step 2 (right panel).
  auto topRow = [&](int x0) {
    for (int y = 0; y < img.rows; ++y)
      for (int x = x0 + 100; x < x0 + 250; ++x)
        if (near(img.at<cv::Vec3b>(y, x), red, 50)) return y;
    return -1;
  };
  const int step1 = topRow(0), step2 = topRow(500);
  ASSERT_GT(step1, 0);
  ASSERT_GT(step2, 0);
  const int bottom = 44 + 656 - 62;  // plot bottom: figure bottom minus tick labels and x title
  EXPECT_NEAR(bottom - step1, (bottom - step2) / 2.0, 6.0);
  EXPECT_THROW(renderPredictionError({{0, {1}, {1}}}), std::invalid_argument);
}

TEST(EvaluationPlots, EmptyInputsGiveNoDataFigures) {
  EXPECT_EQ(renderTrajectories({}, FieldGeometry{}).size(), cv::Size(1300, 800));
  EXPECT_EQ(renderPositionError({}).size(), cv::Size(1000, 700));
  EXPECT_EQ(renderStageTimingHistogram({}).size(), cv::Size(1000, 700));
  EXPECT_EQ(renderPredictionError({}).size(), cv::Size(1000, 700));
}

TEST(EvaluationPlots, FiguresWriteReadablePngs) {
  const std::string dir = tempDir();
  const auto robots = twoRobots();
  ErrorSeries e{{0, 1, 2}, {5, 6, 7}, {}};
  StageTimes s{{"segmentation"}, {{1.0, 1.2, 1.1, 1.4}}};
  std::vector<PredictionErrorSeries> p{{1, {0, 1, 2}, {3, 4, 5}}};

  plotTrajectories(robots, FieldGeometry{}, dir + "/trajectories.png");
  plotPositionError(e, dir + "/position_error.png");
  plotStageTimingHistogram(s, dir + "/stage_timing.png");
  plotPredictionError(p, dir + "/prediction_error.png");

  const std::vector<std::pair<std::string, cv::Mat>> expected = {
      {"trajectories.png", renderTrajectories(robots, FieldGeometry{})},
      {"position_error.png", renderPositionError(e)},
      {"stage_timing.png", renderStageTimingHistogram(s)},
      {"prediction_error.png", renderPredictionError(p)}};
  for (const auto& [name, render] : expected) {
    const cv::Mat read = cv::imread(dir + "/" + name, cv::IMREAD_COLOR);
    ASSERT_FALSE(read.empty()) << name;
    EXPECT_EQ(read.size(), render.size()) << name;
    EXPECT_EQ(cv::norm(read, render, cv::NORM_INF), 0) << name;  // PNG is lossless
  }
  std::filesystem::remove_all(dir);
}

TEST(EvaluationPlots, UnwritablePathThrowsNamingIt) {
  const std::string missing = "/nonexistent_soccer_vision_dir/position_error.png";
  try {
    plotPositionError({{0, 1}, {1, 2}, {}}, missing);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  EXPECT_THROW(plotPredictionError({}, "/tmp/prediction_error.jpg"), std::runtime_error);
  EXPECT_THROW(plotStageTimingHistogram({}, ""), std::runtime_error);
}
