// RegionParams::require_pair (morphology off, e.g. Bayer quads): the checkerboard scan
// returns exactly the 8-connected components that hold two 4-adjacent pixels of their
// class, checked against OpenCV's components on random label images with isolated pixels
// and diagonal chains, full frame and in windows; and labelParams turns it on where it
// turns the opening off.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <random>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "label_colors.h"
#include "soccer_vision/segmentation/color_table.h"
#include "soccer_vision/segmentation/pixel_classifier.h"
#include "soccer_vision/segmentation/region_extractor.h"
#include "soccer_vision/segmentation/segmenter.h"

using namespace soccer_vision;

namespace {

const std::vector<std::pair<ColorClass, cv::Vec3b>> kPalette = {{ColorClass::Blue, {200, 80, 20}},
                                                                {ColorClass::Yellow, {30, 220, 240}},
                                                                {ColorClass::Pink, {180, 80, 255}}};
const cv::Vec3b kNoneColor(128, 128, 128);

const PixelClassifier& paletteClassifier() {
  static const PixelClassifier classifier = [] {
    ClassPixels samples;
    for (const auto& [c, color] : kPalette) samples[c].assign(4, color);
    return PixelClassifier(std::make_shared<const ColorTable>(ColorTable::build(samples)));
  }();
  return classifier;
}

// Blobs, single pixels and diagonal chains of single pixels (no two 4-adjacent).
cv::Mat1b randomLabels(std::mt19937& rng, cv::Size size) {
  cv::Mat1b labels(size, static_cast<std::uint8_t>(ColorClass::None));
  std::uniform_int_distribution<int> klass(0, static_cast<int>(kPalette.size()) - 1), px(0, size.width - 1),
      py(0, size.height - 1), extent(1, 12), shape(0, 2);
  auto value = [&] {
    return static_cast<std::uint8_t>(kPalette[static_cast<std::size_t>(klass(rng))].first);
  };
  for (int i = 0; i < 60; ++i) {
    const cv::Point p(px(rng), py(rng));
    const std::uint8_t v = value();
    switch (shape(rng)) {
      case 0:
        cv::rectangle(labels, cv::Rect(p, cv::Size(extent(rng), extent(rng))), cv::Scalar(v), cv::FILLED);
        break;
      case 1:
        labels(p) = v;
        break;
      default:
        for (int d = 0, n = extent(rng); d < n; ++d) {
          const cv::Point q = p + cv::Point(d, d);
          if (q.x < size.width && q.y < size.height) labels(q) = v;
        }
    }
  }
  return labels;
}

cv::Mat colorsOf(const cv::Mat1b& labels) { return test::paintLabels(labels, kPalette, kNoneColor); }

using Blob = std::tuple<int, int, int, int, int, int>;  // class, area, bbox x, y, width, height

// OpenCV's 8-connected components of each class within the area filter, kept when one of
// their pixels has a 4-neighbour of the class; `dropped` counts the others.
std::vector<Blob> reference(const cv::Mat1b& labels, const RegionParams& p, int& dropped) {
  std::vector<Blob> blobs;
  for (const auto& [c, color] : kPalette) {
    const cv::Mat1b mask = labels == static_cast<int>(c);
    cv::Mat1i cc;
    cv::Mat stats, centroids;
    const int n = cv::connectedComponentsWithStats(mask, cc, stats, centroids, 8, CV_32S);
    std::vector<char> paired(static_cast<std::size_t>(n), 0);
    for (int y = 0; y < cc.rows; ++y) {
      for (int x = 0; x < cc.cols; ++x) {
        const int l = cc(y, x);
        if (l == 0) continue;
        if ((x + 1 < cc.cols && cc(y, x + 1) == l) || (y + 1 < cc.rows && cc(y + 1, x) == l)) paired[l] = 1;
      }
    }
    for (int l = 1; l < n; ++l) {
      const int area = stats.at<int>(l, cv::CC_STAT_AREA);
      if (area < p.min_area || area > p.max_area) continue;
      if (!paired[l]) {
        ++dropped;
        continue;
      }
      blobs.emplace_back(static_cast<int>(c), area, stats.at<int>(l, cv::CC_STAT_LEFT),
                         stats.at<int>(l, cv::CC_STAT_TOP), stats.at<int>(l, cv::CC_STAT_WIDTH),
                         stats.at<int>(l, cv::CC_STAT_HEIGHT));
    }
  }
  std::sort(blobs.begin(), blobs.end());
  return blobs;
}

std::vector<Blob> blobsOf(const std::vector<Region>& regions) {
  std::vector<Blob> blobs;
  for (const Region& r : regions) {
    blobs.emplace_back(static_cast<int>(r.color), static_cast<int>(r.area), r.bbox.x, r.bbox.y, r.bbox.width,
                       r.bbox.height);
  }
  std::sort(blobs.begin(), blobs.end());
  return blobs;
}

RegionParams pairParams(int kernel, int tile) {
  RegionParams p;
  p.morph_kernel = kernel;
  p.require_pair = true;
  p.tile_size = tile;
  p.min_area = 1;
  p.max_area = 100000;
  p.max_regions_per_class = 100000;
  p.coverage_weighted_moments = false;
  return p;
}

}  // namespace

TEST(RegionPairs, CheckerboardScanFindsExactlyTheComponentsHoldingAnAdjacentPair) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> width(20, 200), height(20, 160);
  int images = 0, regions = 0, dropped = 0;
  for (const int kernel : {0, 1}) {
    for (const int tile : {8, 16}) {
      for (int i = 0; i < 30; ++i) {
        const cv::Mat1b labels = randomLabels(rng, {width(rng), height(rng)});
        const RegionParams params = pairParams(kernel, tile);
        const std::vector<Blob> want = reference(labels, params, dropped);
        const cv::Mat image = colorsOf(labels);
        const FrameClassifier frame(paletteClassifier(), image, PixelLayout::Bgr, BlockOffsets{});
        RegionExtractor extractor(params);
        std::vector<Region> got;
        RegionStatistics stats;
        extractor.extract(frame, {}, got, stats);
        ASSERT_EQ(blobsOf(got), want) << "kernel " << kernel << " tile " << tile << " image " << i;
        // The checkerboard: half the pixels (rounded up per row).
        EXPECT_LE(stats.grid_points, static_cast<std::uint32_t>(labels.rows * ((labels.cols + 1) / 2)));
        EXPECT_GE(stats.grid_points, static_cast<std::uint32_t>(labels.rows * (labels.cols / 2)));
        ++images;
        regions += static_cast<int>(want.size());
      }
    }
  }
  std::printf("[ pairs ] %d images: %d regions equal to the reference, %d unpaired components dropped\n",
              images, regions, dropped);
  EXPECT_GT(regions, 1000);
  EXPECT_GT(dropped, 500);  // single pixels and diagonal chains were there to drop
}

// In windows: a region crossing the window border is returned whole, one outside is not,
// and a single pixel inside is dropped.
TEST(RegionPairs, WindowsReturnPairedRegionsWhole) {
  cv::Mat1b labels(60, 80, static_cast<std::uint8_t>(ColorClass::None));
  labels(cv::Rect(18, 10, 8, 3)).setTo(static_cast<int>(ColorClass::Blue));    // crosses x = 20
  labels(cv::Rect(50, 40, 4, 4)).setTo(static_cast<int>(ColorClass::Yellow));  // outside the window
  labels(5, 30) = static_cast<std::uint8_t>(ColorClass::Pink);                 // single pixel inside
  const cv::Mat image = colorsOf(labels);
  const FrameClassifier frame(paletteClassifier(), image, PixelLayout::Bgr, BlockOffsets{});
  RegionExtractor extractor(pairParams(1, 8));
  std::vector<Region> got;
  RegionStatistics stats;
  extractor.extract(frame, {cv::Rect(20, 0, 20, 30)}, got, stats);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].color, ColorClass::Blue);
  EXPECT_EQ(got[0].area, 24u);
  EXPECT_EQ(got[0].bbox, cv::Rect(18, 10, 8, 3));
  EXPECT_DOUBLE_EQ(got[0].cx, 21.5);
  EXPECT_DOUBLE_EQ(got[0].cy, 11.0);
  EXPECT_EQ(stats.grid_points, 300u);  // 20 x 30 window, every other pixel
}

TEST(RegionPairs, LabelParamsAskForPairsWhereTheyTurnTheOpeningOff) {
  const RegionParams p;  // kernel 3
  EXPECT_FALSE(labelParams(p, 1280).require_pair);
  EXPECT_FALSE(labelParams(p, 960).require_pair);  // the opening is kept
  EXPECT_TRUE(labelParams(p, 780).require_pair);
  EXPECT_TRUE(quadLabelParams(p).require_pair);
  RegionParams off = p;
  off.morph_kernel = 0;  // the user turned morphology off: every region, as asked
  EXPECT_FALSE(quadLabelParams(off).require_pair);
  RegionParams five = p;
  five.morph_kernel = 5;  // halved to 2: the opening stays on
  EXPECT_FALSE(quadLabelParams(five).require_pair);
}
