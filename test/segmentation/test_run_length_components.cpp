// Run-length connected components against cv::connectedComponentsWithStats
// (connectivity 8) on random masks, in whole masks and in sub-rectangles: the component of
// every pixel, area, bbox, moment sums, the runs of each component, the numbering.
#include <algorithm>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "soccer_vision/segmentation/run_length_components.h"

using namespace soccer_vision;

namespace {

cv::Mat randomMask(std::mt19937& rng, cv::Size size) {
  cv::Mat mask(size, CV_8UC1, cv::Scalar(0));
  std::uniform_int_distribution<int> px(-5, size.width + 5), py(-5, size.height + 5), extent(1, 25),
      thickness(1, 3), coin(0, 14);
  for (int i = 0; i < 15; ++i) {
    cv::rectangle(mask, cv::Rect(px(rng), py(rng), extent(rng), extent(rng)), cv::Scalar(255), cv::FILLED);
    cv::line(mask, {px(rng), py(rng)}, {px(rng), py(rng)}, cv::Scalar(255), thickness(rng));
  }
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) {
      if (coin(rng) == 0) mask.at<std::uint8_t>(y, x) ^= 255;  // single pixels and diagonal contacts
    }
  }
  return mask;
}

}  // namespace

TEST(RunLengthComponents, EqualConnectedComponentsWithStatsOnRandomMasks) {
  std::mt19937 rng(9);
  std::uniform_int_distribution<int> width(1, 190), height(1, 80);
  RunLengthComponents rl;
  BitMask bits;
  int components = 0;
  for (int i = 0; i < 200; ++i) {
    const cv::Mat mask = randomMask(rng, {width(rng), height(rng)});
    std::uniform_int_distribution<int> x0(0, mask.cols - 1), y0(0, mask.rows - 1);
    const int x = i % 2 ? x0(rng) : 0, y = i % 2 ? y0(rng) : 0;
    std::uniform_int_distribution<int> w(1, mask.cols - x), h(1, mask.rows - y);
    const cv::Rect rect = i % 2 ? cv::Rect(x, y, w(rng), h(rng)) : cv::Rect(0, 0, mask.cols, mask.rows);

    bits.setFromLabels(mask, 255);
    rl.compute(bits, rect);
    cv::Mat labels, stats, centroids;
    const int n = cv::connectedComponentsWithStats(mask(rect), labels, stats, centroids, 8, CV_32S);
    ASSERT_EQ(static_cast<int>(rl.components().size()), n - 1) << "mask " << i;
    // OpenCV labels 2 x 2 blocks, so its numbering may differ: pixels give the mapping,
    // which must be one to one.
    std::vector<int> ours(static_cast<std::size_t>(n), -2);
    std::vector<std::int64_t> xx(static_cast<std::size_t>(n), 0), xy(xx), yy(xx);
    for (int py = 0; py < rect.height; ++py) {
      for (int px = 0; px < rect.width; ++px) {
        const int label = labels.at<int>(py, px);
        const int component = rl.componentAt(px, py);
        ASSERT_EQ(component < 0, label == 0) << "mask " << i << " pixel " << px << "," << py;
        int& mapped = ours[static_cast<std::size_t>(label)];
        if (label > 0 && mapped == -2) mapped = component;
        ASSERT_EQ(label == 0 ? -1 : mapped, component) << "mask " << i << " pixel " << px << "," << py;
        xx[static_cast<std::size_t>(label)] += px * px;
        xy[static_cast<std::size_t>(label)] += px * py;
        yy[static_cast<std::size_t>(label)] += py * py;
      }
    }
    std::vector<int> sorted(ours.begin() + 1, ours.end());
    std::sort(sorted.begin(), sorted.end());
    for (int c = 0; c < n - 1; ++c) ASSERT_EQ(sorted[static_cast<std::size_t>(c)], c) << "mask " << i;

    for (int l = 1; l < n; ++l) {
      const int c = ours[static_cast<std::size_t>(l)];
      const ComponentStats& component = rl.components()[static_cast<std::size_t>(c)];
      const int* s = stats.ptr<int>(l);
      EXPECT_EQ(component.area, static_cast<std::uint32_t>(s[cv::CC_STAT_AREA]))
          << "mask " << i << " label " << l;
      EXPECT_EQ(component.bbox, cv::Rect(s[cv::CC_STAT_LEFT], s[cv::CC_STAT_TOP], s[cv::CC_STAT_WIDTH],
                                         s[cv::CC_STAT_HEIGHT]));
      EXPECT_NEAR(static_cast<double>(component.sum_x) / component.area, centroids.at<double>(l, 0), 1e-9);
      EXPECT_NEAR(static_cast<double>(component.sum_y) / component.area, centroids.at<double>(l, 1), 1e-9);
      EXPECT_EQ(component.sum_xx, xx[static_cast<std::size_t>(l)]);
      EXPECT_EQ(component.sum_xy, xy[static_cast<std::size_t>(l)]);
      EXPECT_EQ(component.sum_yy, yy[static_cast<std::size_t>(l)]);
      std::uint32_t pixels = 0;
      for (const PixelRun* run = rl.runsBegin(c); run != rl.runsEnd(c); ++run) {
        EXPECT_EQ(run->component, c);
        for (int px = run->x_begin; px < run->x_end; ++px) EXPECT_EQ(labels.at<int>(run->y, px), l);
        pixels += static_cast<std::uint32_t>(run->x_end - run->x_begin);
      }
      EXPECT_EQ(pixels, component.area);
    }
    // Raster order of the first pixels.
    for (int c = 1; c < n - 1; ++c) {
      const PixelRun& previous = *rl.runsBegin(c - 1);
      const PixelRun& first = *rl.runsBegin(c);
      EXPECT_TRUE(previous.y < first.y || (previous.y == first.y && previous.x_begin < first.x_begin))
          << "mask " << i;
    }
    components += n - 1;
  }
  std::printf("[ components ] 200 random masks, %d components, all equal to OpenCV's\n", components);
  EXPECT_GT(components, 2000);
}
