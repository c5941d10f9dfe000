// Bit-packed morphology against OpenCV (cv::erode, cv::dilate with a k x k MORPH_RECT,
// the default and the reflected anchor, the default border; the centred open + close) on random masks,
// including widths that are not multiples of 64 and masks narrower than the kernel.
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "soccer_vision/segmentation/binary_morphology.h"

using namespace soccer_vision;

namespace {

// Random blobs on sparse noise: both large structures and single pixels.
cv::Mat randomMask(std::mt19937& rng, cv::Size size) {
  cv::Mat labels(size, CV_8UC1, cv::Scalar(0));
  std::uniform_int_distribution<int> px(-5, size.width + 5), py(-5, size.height + 5), extent(1, 30),
      coin(0, 9);
  for (int i = 0; i < 12; ++i) {
    cv::rectangle(labels, cv::Rect(px(rng), py(rng), extent(rng), extent(rng)), cv::Scalar(1), cv::FILLED);
    cv::circle(labels, {px(rng), py(rng)}, extent(rng) / 3, cv::Scalar(1), cv::FILLED);
  }
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) {
      if (coin(rng) == 0) labels.at<std::uint8_t>(y, x) ^= 1;
    }
  }
  return labels;
}

::testing::AssertionResult sameMask(const BitMask& got, const cv::Mat& want) {
  const cv::Mat got_mat = got.toMat();
  if (got_mat.size() != want.size()) return ::testing::AssertionFailure() << "size differs";
  const int differing = cv::countNonZero(got_mat != want);
  if (differing == 0) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << differing << " pixels differ";
}

}  // namespace

TEST(BinaryMorphology, PacksLabelsAndKeepsBitsBeyondTheWidthClear) {
  std::mt19937 rng(1);
  const cv::Mat labels = randomMask(rng, {70, 9});
  BitMask mask;
  mask.setFromLabels(labels, 1);
  EXPECT_EQ(mask.wordsPerRow(), 2);
  EXPECT_TRUE(sameMask(mask, labels == 1));
  for (int y = 0; y < mask.height(); ++y) EXPECT_EQ(mask.row(y)[1] & ~mask.validBits(1), 0u);
}

TEST(BinaryMorphology, EqualsOpenCvOnRandomMasks) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> width(1, 200), height(1, 90);
  MorphologyScratch scratch;
  BitMask mask, out;
  int cases = 0;
  for (const int k : {1, 2, 3, 4, 5, 6, 7, 9, 15, 31}) {
    const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k));
    for (int i = 0; i < 30; ++i) {
      // Every width class: inside one word, exactly 64 and 128, and across words.
      const cv::Size size(i == 0 ? 64 : i == 1 ? 128 : width(rng), height(rng));
      const cv::Mat binary = randomMask(rng, size) == 1;
      mask.setFromLabels(binary, 255);
      const std::string where =
          "k " + std::to_string(k) + ", " + std::to_string(size.width) + "x" + std::to_string(size.height);

      cv::Mat want;
      cv::erode(binary, want, kernel);
      erode(mask, k, out, scratch);
      ASSERT_TRUE(sameMask(out, want)) << "erode, " << where;
      cv::dilate(binary, want, kernel);
      dilate(mask, k, out, scratch);
      ASSERT_TRUE(sameMask(out, want)) << "dilate, " << where;

      // Anchored passes, and the centred opening + closing: the second pass of each with
      // the reflected anchor (for odd k that is cv::morphologyEx).
      const int a = k / 2, reflected = k - 1 - k / 2;
      cv::erode(binary, want, kernel, cv::Point(reflected, reflected));
      erode(mask, k, out, scratch, reflected);
      ASSERT_TRUE(sameMask(out, want)) << "erode, reflected anchor, " << where;
      cv::dilate(binary, want, kernel, cv::Point(reflected, reflected));
      dilate(mask, k, out, scratch, reflected);
      ASSERT_TRUE(sameMask(out, want)) << "dilate, reflected anchor, " << where;
      cv::erode(binary, want, kernel, cv::Point(a, a));
      cv::dilate(want, want, kernel, cv::Point(reflected, reflected));
      cv::dilate(want, want, kernel, cv::Point(a, a));
      cv::erode(want, want, kernel, cv::Point(reflected, reflected));
      if (k % 2 == 1) {
        cv::Mat opencv;
        cv::morphologyEx(binary, opencv, cv::MORPH_OPEN, kernel);
        cv::morphologyEx(opencv, opencv, cv::MORPH_CLOSE, kernel);
        ASSERT_EQ(cv::countNonZero(opencv != want), 0) << where;
      }
      openThenClose(mask, k, scratch);
      ASSERT_TRUE(sameMask(mask, want)) << "open + close, " << where;
      ++cases;
    }
  }
  EXPECT_EQ(cases, 300);
}

// openThenClose computes only the rows near the foreground: blobs in a band of a tall
// mask (at the top and bottom borders too, where rows beyond the mask count as
// foreground for erosion) must still give OpenCV's result everywhere.
TEST(BinaryMorphology, OpenThenCloseOfABandOfRowsEqualsOpenCv) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> width(1, 150), band(1, 12);
  MorphologyScratch scratch;
  BitMask mask;
  int cases = 0, changed = 0;
  for (const int k : {2, 3, 4, 5, 7}) {
    const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k));
    const int a = k / 2, reflected = k - 1 - k / 2;
    for (int i = 0; i < 40; ++i) {
      const int height = 60, rows = band(rng);
      const int offset = i % 4 == 0   ? 0
                         : i % 4 == 1 ? height - rows
                                      : std::uniform_int_distribution<int>(1, height - rows - 1)(rng);
      cv::Mat binary(height, width(rng), CV_8UC1, cv::Scalar(0));
      const cv::Mat blobs = randomMask(rng, {binary.cols, rows}) == 1;
      blobs.copyTo(binary.rowRange(offset, offset + rows));
      mask.setFromLabels(binary, 255);
      cv::Mat want;
      cv::erode(binary, want, kernel, cv::Point(a, a));
      cv::dilate(want, want, kernel, cv::Point(reflected, reflected));
      cv::dilate(want, want, kernel, cv::Point(a, a));
      cv::erode(want, want, kernel, cv::Point(reflected, reflected));
      openThenClose(mask, k, scratch);
      ASSERT_TRUE(sameMask(mask, want))
          << "k " << k << ", band of " << rows << " rows at " << offset << ", width " << binary.cols;
      changed += cv::countNonZero(want != binary) > 0;
      ++cases;
    }
  }
  EXPECT_EQ(cases, 200);
  EXPECT_GT(changed, 150);  // the passes did change most masks: the comparison is not of idle inputs
}
