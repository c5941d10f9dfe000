// The floor around a region (floor_surround.h), and the streak table's regions that are not
// on the floor (SegmentationParams::ball_streak_floor_share): a print on a robot's dark top
// that the streak table reads as a blurred ball is refused, the same colours on the carpet
// are the ball, and the colour table's own orange on the top is kept.
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "ball_and_carpet_samples.h"
#include "soccer_vision/segmentation/floor_surround.h"
#include "soccer_vision/segmentation/segmenter.h"

using namespace soccer_vision;

namespace {

const cv::Scalar kTop(28, 28, 30);  // a robot's dark top (BGR)

cv::Scalar scalar(const cv::Vec3d& bgr) { return {bgr[0], bgr[1], bgr[2]}; }

// A 12 m/s streak's middle: 60 % ball, 40 % carpet; the colour table reads it as no marker.
const cv::Vec3d kStreak = 0.6 * test::kSampledBall + 0.4 * test::kSampledCarpet;

// Carpet, a robot's top at (80, 120) and a patch of `patch` on it, and the same patch on
// the carpet at (240, 120).
cv::Mat scene(const cv::Vec3d& patch) {
  cv::Mat image(240, 320, CV_8UC3, scalar(test::kSampledCarpet));
  cv::circle(image, {80, 120}, 40, kTop, cv::FILLED);
  cv::rectangle(image, cv::Rect(72, 115, 16, 10), scalar(patch), cv::FILLED);
  cv::rectangle(image, cv::Rect(232, 115, 16, 10), scalar(patch), cv::FILLED);
  return image;
}

std::shared_ptr<const SegmentationModel> model() {
  return SegmentationModel::fromTable(
      std::make_shared<const ColorTable>(ColorTable::buildFromSamplePixels(test::ballAndCarpetSamples())));
}

std::vector<Region> orange(const SegmentationResult& r) {
  std::vector<Region> out;
  for (const Region& region : r.regions)
    if (region.color == ColorClass::Orange) out.push_back(region);
  return out;
}

}  // namespace

TEST(FloorSurround, IsTheShareOfARingOutsideTheRegionReadAsCarpet) {
  const auto m = model();
  const cv::Mat image = scene(kStreak);
  const FrameClassifier colors(*m->classifier, image, PixelLayout::Bgr, {});
  Region on_carpet;
  on_carpet.cx = 239.5;
  on_carpet.cy = 119.5;
  on_carpet.mu20 = 16.0 * 16 / 12;  // a 16 x 10 rectangle's moments
  on_carpet.mu02 = 10.0 * 10 / 12;
  Region on_top = on_carpet;
  on_top.cx = 79.5;
  EXPECT_DOUBLE_EQ(floorShareAround(colors, on_carpet).value(), 1.0);
  EXPECT_DOUBLE_EQ(floorShareAround(colors, on_top).value(), 0.0);
  // At the image's edge only the points inside count: the carpet there, all of them.
  Region at_edge = on_carpet;
  at_edge.cx = 318;
  EXPECT_DOUBLE_EQ(floorShareAround(colors, at_edge).value(), 1.0);
  Region outside = on_carpet;
  outside.cx = 2000;
  EXPECT_FALSE(floorShareAround(colors, outside));
  outside.cx = NAN;
  EXPECT_FALSE(floorShareAround(colors, outside));
}

TEST(FloorSurround, AStreakOnARobotsTopIsRefusedAndOnTheCarpetKept) {
  const auto m = model();
  ASSERT_TRUE(m->streak_classifier);
  const cv::Mat image = scene(kStreak);
  const std::vector<cv::Rect> whole = {{0, 0, 320, 240}};
  SegmentationParams params;
  Segmenter segmenter(params);
  SegmentationResult out;
  segmenter.process(*m, image, PixelLayout::Bgr, whole, out, whole);
  auto found = orange(out);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_NEAR(found[0].cx, 239.5, 0.5);
  EXPECT_EQ(out.streak_regions, 1u);
  EXPECT_EQ(out.streak_refused, 1u);

  params.ball_streak_floor_share = 0;  // off: both patches read as the ball
  segmenter.setParams(params);
  segmenter.process(*m, image, PixelLayout::Bgr, whole, out, whole);
  EXPECT_EQ(orange(out).size(), 2u);
  EXPECT_EQ(out.streak_refused, 0u);
}

TEST(FloorSurround, TheColourTablesOwnOrangeStaysWhereAStreakIsRefused) {
  const auto m = model();
  const cv::Mat image = scene(test::kSampledBall);  // the ball's own colour, on the top too
  const std::vector<cv::Rect> whole = {{0, 0, 320, 240}};
  Segmenter segmenter;
  SegmentationResult out;
  segmenter.process(*m, image, PixelLayout::Bgr, whole, out, whole);
  EXPECT_EQ(orange(out).size(), 2u);  // the colour table's on the top, the streak table's on the carpet
  EXPECT_EQ(out.streak_regions, 1u);
  EXPECT_EQ(out.streak_refused, 1u);
}
