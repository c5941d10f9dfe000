// Online self-calibration's rules on hand-made frames: a hole cell inside a confirmed marker
// is learned, one the background also shows is vetoed, one far from the class's calibrated
// colour is not, the rate bound holds, and reset() returns to the calibrated table.
#include <cstdint>
#include <memory>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "soccer_vision/segmentation/online_calibration.h"

using namespace soccer_vision;

namespace {

const cv::Scalar kCarpet(60, 110, 60);
const cv::Vec3b kBlue(200, 80, 20);        // the calibrated blue (V 200)
const cv::Vec3b kBrightBlue(230, 92, 23);  // the same hue and saturation at V 230: a hole

// A table of blue and carpet (and the ball) from exact pixels: its blue body is V 200 only
// (no margin, no generalisation), so V 230 is a hole.
std::shared_ptr<const SegmentationModel> tightModel(bool with_ball = false) {
  ColorTableParams p;
  p.v_margin = 0;
  p.generalize_sigmas = 0;
  ClassPixels samples;
  samples[ColorClass::Blue].assign(50, kBlue);
  samples[ColorClass::Carpet].assign(50, cv::Vec3b(60, 110, 60));
  if (with_ball) samples[ColorClass::Orange].assign(50, cv::Vec3b(8, 95, 215));
  return SegmentationModel::fromTable(std::make_shared<const ColorTable>(ColorTable::build(samples, p)));
}

Region disc(ColorClass c, double cx, double cy, double r) {
  Region region;
  region.color = c;
  region.cx = cx;
  region.cy = cy;
  region.area = static_cast<std::uint32_t>(3.14159 * r * r);
  region.mu20 = region.mu02 = r * r / 4;  // a disc's second moments
  return region;
}

cv::Mat frameWith(const std::vector<std::pair<cv::Point, cv::Vec3b>>& discs, int radius) {
  cv::Mat image(256, 256, CV_8UC3, kCarpet);
  for (const auto& [centre, color] : discs) cv::circle(image, centre, radius, cv::Scalar(color), cv::FILLED);
  return image;
}

OnlineCalibrationParams enabled() {
  OnlineCalibrationParams p;
  p.enabled = true;
  return p;
}

// Observes `frames` frames at 60 Hz from stamp 100 s, updating after each; the last model returned.
std::shared_ptr<const SegmentationModel> run(OnlineCalibration& learning, const cv::Mat& image,
                                             const std::vector<Region>& regions,
                                             const std::vector<int>& confirmed, int frames,
                                             double t0 = 100.0) {
  std::shared_ptr<const SegmentationModel> last;
  for (int k = 0; k < frames; ++k) {
    const double stamp = t0 + k / 60.0;
    learning.observe(image, PixelLayout::Bgr, BlockOffsets{}, 0.0, regions, confirmed, stamp);
    if (auto m = learning.update(stamp)) last = m;
  }
  return last;
}

}  // namespace

TEST(OnlineCalibration, LearnsAHoleInsideConfirmedMarkers) {
  const auto base = tightModel();
  ASSERT_EQ(base->classifier->classify(kBrightBlue[0], kBrightBlue[1], kBrightBlue[2], 0), ColorClass::None);
  OnlineCalibration learning(base, enabled());
  const cv::Mat image = frameWith({{{128, 128}, kBrightBlue}}, 10);
  const auto learned = run(learning, image, {disc(ColorClass::Blue, 128, 128, 10)}, {0}, 90);
  ASSERT_NE(learned, nullptr);
  EXPECT_EQ(learned->classifier->classify(kBrightBlue[0], kBrightBlue[1], kBrightBlue[2], 0),
            ColorClass::Blue);
  EXPECT_EQ(learning.status().learned_cells[static_cast<int>(ColorClass::Blue)], 1u);
  // The carpet is untouched, and the calibrated table itself never changes.
  EXPECT_EQ(learned->classifier->classify(60, 110, 60, 0), ColorClass::Carpet);
  EXPECT_EQ(base->classifier->classify(kBrightBlue[0], kBrightBlue[1], kBrightBlue[2], 0), ColorClass::None);

  learning.reset();
  EXPECT_EQ(learning.model(), base);
  EXPECT_EQ(learning.status().learnedTotal(), 0u);
}

TEST(OnlineCalibration, ALearnedModelKeepsTheBallsStreakTable) {
  // What is learned is the robots' markers and the carpet: the ball's streak table
  // (ball_streak_table.h) stays the calibrated one's, not lost with the first update.
  const auto base = tightModel(true);
  ASSERT_TRUE(base->streak_classifier);
  OnlineCalibration learning(base, enabled());
  const cv::Mat image = frameWith({{{128, 128}, kBrightBlue}}, 10);
  const auto learned = run(learning, image, {disc(ColorClass::Blue, 128, 128, 10)}, {0}, 90);
  ASSERT_NE(learned, nullptr);
  EXPECT_NE(learned->classifier, base->classifier);
  EXPECT_EQ(learned->streak_classifier, base->streak_classifier);
}

TEST(OnlineCalibration, RegionsNotConfirmedTeachNothing) {
  OnlineCalibration learning(tightModel(), enabled());
  const cv::Mat image = frameWith({{{128, 128}, kBrightBlue}}, 10);
  EXPECT_EQ(run(learning, image, {disc(ColorClass::Blue, 128, 128, 10)}, {}, 150), nullptr);
  EXPECT_EQ(learning.status().learnedTotal(), 0u);
}

TEST(OnlineCalibration, IsOffUnlessEnabled) {
  OnlineCalibration learning(tightModel(), OnlineCalibrationParams{});
  const cv::Mat image = frameWith({{{128, 128}, kBrightBlue}}, 10);
  EXPECT_EQ(run(learning, image, {disc(ColorClass::Blue, 128, 128, 10)}, {0}, 150), nullptr);
  EXPECT_EQ(learning.status().frames, 0u);
}

TEST(OnlineCalibration, ACellTheBackgroundShowsIsVetoed) {
  OnlineCalibration learning(tightModel(), enabled());
  // The same colour on something no robot confirmed (a shirt beyond the lines, say).
  const cv::Mat image = frameWith({{{128, 128}, kBrightBlue}, {{40, 40}, kBrightBlue}}, 14);
  EXPECT_EQ(run(learning, image, {disc(ColorClass::Blue, 128, 128, 14)}, {0}, 150), nullptr);
  EXPECT_EQ(learning.status().learnedTotal(), 0u);
  EXPECT_GE(learning.status().vetoed_cells, 1u);
}

TEST(OnlineCalibration, AColourFarFromTheCalibratedOneIsNotLearned) {
  OnlineCalibration learning(tightModel(), enabled());
  const cv::Vec3b green(30, 200, 40);  // confirmed as blue, but 100° of hue away
  const cv::Mat image = frameWith({{{128, 128}, green}}, 10);
  EXPECT_EQ(run(learning, image, {disc(ColorClass::Blue, 128, 128, 10)}, {0}, 150), nullptr);
  EXPECT_EQ(learning.status().learnedTotal(), 0u);
  EXPECT_GE(learning.status().outside_envelope, 1u);
}

TEST(OnlineCalibration, ChangesAtMostMaxCellsPerUpdate) {
  OnlineCalibrationParams p = enabled();
  p.max_cells_per_update = 1;
  OnlineCalibration learning(tightModel(), p);
  // A marker whose halves show V 215 and 245: two hole cells.
  cv::Mat image = frameWith({}, 0);
  cv::circle(image, {128, 128}, 12, cv::Scalar(215, 86, 21), cv::FILLED);
  cv::rectangle(image, cv::Rect(128, 110, 20, 40), cv::Scalar(kCarpet), cv::FILLED);
  cv::Mat right(256, 256, CV_8UC3, kCarpet);
  cv::circle(right, {128, 128}, 12, cv::Scalar(245, 98, 24), cv::FILLED);
  right(cv::Rect(128, 0, 128, 256)).copyTo(image(cv::Rect(128, 0, 128, 256)));
  const std::vector<Region> regions{disc(ColorClass::Blue, 128, 128, 12)};
  ASSERT_NE(run(learning, image, regions, {0}, 61), nullptr);  // the first update: 1 s after the first frame
  EXPECT_EQ(learning.status().cells_added, 1u);
  ASSERT_NE(run(learning, image, regions, {0}, 61, 101.1), nullptr);
  EXPECT_EQ(learning.status().cells_added, 2u);
}

TEST(OnlineCalibration, UpdatesFollowTheStampsNotTheFrames) {
  OnlineCalibration learning(tightModel(), enabled());
  const cv::Mat image = frameWith({{{128, 128}, kBrightBlue}}, 10);
  const std::vector<Region> regions{disc(ColorClass::Blue, 128, 128, 10)};
  // Half a second of frames: no update is due yet.
  EXPECT_EQ(run(learning, image, regions, {0}, 30), nullptr);
  // Time jumped back: the period starts again from there.
  EXPECT_EQ(run(learning, image, regions, {0}, 30, 50.0), nullptr);
  EXPECT_EQ(learning.status().updates, 0u);
  EXPECT_EQ(learning.status().models, 0u);
  EXPECT_NE(run(learning, image, regions, {0}, 40, 50.5), nullptr);
}

TEST(OnlineCalibration, RefusesBadParameters) {
  OnlineCalibrationParams p = enabled();
  p.purity = 0.2;
  EXPECT_THROW(OnlineCalibration(tightModel(), p), std::invalid_argument);
  p = enabled();
  p.update_period = std::nan("");
  EXPECT_THROW(p.validate(), std::invalid_argument);
  p = enabled();
  p.background_stride = 0;
  EXPECT_THROW(p.validate(), std::invalid_argument);
  EXPECT_THROW(OnlineCalibration(nullptr, enabled()), std::invalid_argument);
}
