// Regions of the paper (§III): the stride-grid + tiles extractor against the full-frame
// OpenCV reference (open + close, 8-connected components, area filter), search windows,
// sub-pixel moments of anti-aliased shapes, the cap, bounded work on colour noise, and
// marker centroids on rendered frames.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "label_colors.h"
#include "marker_interior_accuracy.h"
#include "soccer_vision/common/statistics.h"
#include "soccer_vision/segmentation/color_table.h"
#include "soccer_vision/segmentation/pixel_classifier.h"
#include "soccer_vision/segmentation/region_extractor.h"
#include "soccer_vision/segmentation/segmenter.h"
#include "soccer_vision/simulation/calibration_samples.h"
#include "soccer_vision/simulation/field_renderer.h"
#include "soccer_vision/simulation/game_simulator.h"
#include "soccer_vision/simulation/synthetic_calibration.h"

using namespace soccer_vision;

namespace {

// ------------------------------------------------------------------ label images as colours

// One pure colour per class; None is a grey that no class claims.
const std::vector<std::pair<ColorClass, cv::Vec3b>> kPalette = {
    {ColorClass::Blue, {200, 80, 20}},   {ColorClass::Yellow, {30, 220, 240}},
    {ColorClass::Pink, {180, 80, 255}},  {ColorClass::Orange, {0, 120, 255}},
    {ColorClass::Carpet, {45, 120, 50}},  // not a marker class: must never yield regions
};
const cv::Vec3b kNoneColor(128, 128, 128);

std::shared_ptr<const ColorTable> paletteTable() {
  static const std::shared_ptr<const ColorTable> table = [] {
    ClassPixels samples;
    for (const auto& [c, color] : kPalette) samples[c].assign(4, color);
    return std::make_shared<const ColorTable>(ColorTable::build(samples));
  }();
  return table;
}

cv::Mat colorsOf(const cv::Mat1b& labels) { return test::paintLabels(labels, kPalette, kNoneColor); }

// Random blobs of several classes: rectangles, rotated ellipses, thin lines, polygons,
// some touching each other or the image border.
cv::Mat1b randomLabels(std::mt19937& rng, cv::Size size) {
  cv::Mat1b labels(size, static_cast<std::uint8_t>(ColorClass::None));
  std::uniform_int_distribution<int> shape(0, 3), count(10, 40),
      klass(0, static_cast<int>(kPalette.size()) - 1);
  std::uniform_int_distribution<int> px(-10, size.width + 10), py(-10, size.height + 10), extent(1, 40),
      thickness(1, 4), angle(0, 179);
  const int n = count(rng);
  for (int i = 0; i < n; ++i) {
    const cv::Scalar value(static_cast<int>(kPalette[static_cast<std::size_t>(klass(rng))].first));
    const cv::Point p(px(rng), py(rng));
    switch (shape(rng)) {
      case 0:
        cv::rectangle(labels, cv::Rect(p, cv::Size(extent(rng), extent(rng))), value, cv::FILLED);
        break;
      case 1:
        cv::ellipse(labels, p, cv::Size(extent(rng) / 2, extent(rng) / 2), angle(rng), 0, 360, value,
                    cv::FILLED);
        break;
      case 2:
        cv::line(labels, p, p + cv::Point(extent(rng) * 2 - 40, extent(rng) * 2 - 40), value, thickness(rng));
        break;
      default: {
        std::vector<cv::Point> poly;
        for (int v = 0; v < 5; ++v) poly.push_back(p + cv::Point(extent(rng) - 20, extent(rng) - 20));
        cv::fillPoly(labels, std::vector<std::vector<cv::Point>>{poly}, value);
      }
    }
  }
  return labels;
}

struct Blob {
  ColorClass color;
  int area;
  cv::Rect bbox;
  double cx, cy;
  bool operator<(const Blob& o) const {
    return std::tie(color, bbox.y, bbox.x, area, bbox.width, bbox.height) <
           std::tie(o.color, o.bbox.y, o.bbox.x, o.area, o.bbox.width, o.bbox.height);
  }
};

// The full-frame reference: per class open + close with a k x k square on the whole
// label image, 8-connected components, area filter. With a scan grid coarser than the
// kernel (RegionParams::scan_stride), only the components holding an opened pixel the scan
// reads: a grid point, or any pixel of the last column or row when the grid misses them.
std::vector<Blob> reference(const cv::Mat1b& labels, const RegionParams& p) {
  std::vector<Blob> blobs;
  const int k = std::max(1, p.morph_kernel);
  const int stride = scanGridStride(p);
  const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k));
  for (int c = 0; c < kNumColorClasses; ++c) {
    if (!(p.classes & classBit(static_cast<ColorClass>(c)))) continue;
    cv::Mat mask = labels == c;
    cv::Mat opened = mask;
    if (p.morph_kernel > 1) {  // centred open + close (binary_morphology.h)
      const cv::Point a(k / 2, k / 2), reflected(k - 1 - k / 2, k - 1 - k / 2);
      cv::erode(mask, mask, kernel, a);
      cv::dilate(mask, mask, kernel, reflected);
      opened = mask.clone();
      cv::dilate(mask, mask, kernel, a);
      cv::erode(mask, mask, kernel, reflected);
    }
    cv::Mat1i cc;
    cv::Mat stats, centroids;
    const int n = cv::connectedComponentsWithStats(mask, cc, stats, centroids, 8, CV_32S);
    std::vector<char> seen(static_cast<std::size_t>(n), stride <= k);
    if (stride > k) {
      for (int y = 0; y < labels.rows; ++y) {
        for (int x = 0; x < labels.cols; ++x) {
          if (opened.at<std::uint8_t>(y, x) && test::scanReads(x, y, labels.size(), stride))
            seen[static_cast<std::size_t>(cc(y, x))] = 1;
        }
      }
    }
    for (int l = 1; l < n; ++l) {
      const int area = stats.at<int>(l, cv::CC_STAT_AREA);
      if (!seen[static_cast<std::size_t>(l)] || area < p.min_area || area > p.max_area) continue;
      blobs.push_back({static_cast<ColorClass>(c), area,
                       cv::Rect(stats.at<int>(l, cv::CC_STAT_LEFT), stats.at<int>(l, cv::CC_STAT_TOP),
                                stats.at<int>(l, cv::CC_STAT_WIDTH), stats.at<int>(l, cv::CC_STAT_HEIGHT)),
                       centroids.at<double>(l, 0), centroids.at<double>(l, 1)});
    }
  }
  std::sort(blobs.begin(), blobs.end());
  return blobs;
}

std::vector<Blob> blobsOf(const std::vector<Region>& regions) {
  std::vector<Blob> blobs;
  for (const Region& r : regions) blobs.push_back({r.color, static_cast<int>(r.area), r.bbox, r.cx, r.cy});
  std::sort(blobs.begin(), blobs.end());
  return blobs;
}

std::string describe(const Blob& b) {
  char text[160];
  std::snprintf(text, sizeof text, "%s area %d bbox (%d,%d %dx%d) centroid (%.3f, %.3f)",
                std::string(colorClassName(b.color)).c_str(), b.area, b.bbox.x, b.bbox.y, b.bbox.width,
                b.bbox.height, b.cx, b.cy);
  return text;
}

// Same blobs (class, area, bbox exactly; centroid to rounding).
::testing::AssertionResult sameBlobs(const std::vector<Blob>& got, const std::vector<Blob>& want) {
  for (std::size_t i = 0; i < std::max(got.size(), want.size()); ++i) {
    const bool same = i < got.size() && i < want.size() && got[i].color == want[i].color &&
                      got[i].area == want[i].area && got[i].bbox == want[i].bbox &&
                      std::abs(got[i].cx - want[i].cx) < 1e-9 && std::abs(got[i].cy - want[i].cy) < 1e-9;
    if (!same) {
      return ::testing::AssertionFailure()
             << got.size() << " regions vs " << want.size() << " in the reference; first "
             << "difference at " << i << ": got " << (i < got.size() ? describe(got[i]) : "nothing")
             << ", want " << (i < want.size() ? describe(want[i]) : "nothing");
    }
  }
  return ::testing::AssertionSuccess();
}

struct Extraction {
  std::vector<Region> regions;
  RegionStatistics stats;
};

const PixelClassifier& paletteClassifier() {
  static const PixelClassifier classifier(paletteTable());
  return classifier;
}

Extraction extract(const cv::Mat& bgr, const RegionParams& params, const std::vector<cv::Rect>& windows = {},
                   const PixelClassifier& classifier = paletteClassifier()) {
  const BlockOffsets offsets;
  const FrameClassifier frame(classifier, bgr, PixelLayout::Bgr, offsets);
  RegionExtractor extractor(params);
  Extraction e;
  extractor.extract(frame, windows, e.regions, e.stats);
  return e;
}

RegionParams binaryParams(int kernel, int tile) {
  RegionParams p;
  p.morph_kernel = kernel;
  p.tile_size = tile;
  p.min_area = 3;
  p.max_area = 600;  // some blobs are larger: the drop must not depend on the tiling
  p.max_regions_per_class = 100000;
  p.coverage_weighted_moments = false;
  return p;
}

}  // namespace

// ------------------------------------------------------------------ equality with the reference

TEST(RegionExtractor, PaletteTableMapsEachColourToItsClass) {
  const ColorTable& table = *paletteTable();
  for (const auto& [c, color] : kPalette) EXPECT_EQ(table.classify(color[0], color[1], color[2]), c);
  EXPECT_EQ(table.classify(kNoneColor[0], kNoneColor[1], kNoneColor[2]), ColorClass::None);
}

TEST(RegionExtractor, EqualsFullFrameMorphologyAndComponentsOnRandomLabelImages) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> width(40, 260), height(40, 200);
  int images = 0, regions = 0;
  for (const int kernel : {0, 1, 2, 3, 4, 5, 7}) {
    for (const int tile : {8, 16, 32}) {
      for (int i = 0; i < 24; ++i) {
        const cv::Mat1b labels = randomLabels(rng, {width(rng), height(rng)});
        const RegionParams params = binaryParams(kernel, tile);
        const std::vector<Blob> want = reference(labels, params);
        const Extraction got = extract(colorsOf(labels), params);
        ASSERT_TRUE(sameBlobs(blobsOf(got.regions), want))
            << "kernel " << kernel << " tile " << tile << " image " << i << " (" << labels.cols << "x"
            << labels.rows << ")";
        ++images;
        regions += static_cast<int>(want.size());
      }
    }
  }
  std::printf("[ regions ] %d random label images, %d regions, all equal to the full-frame reference\n",
              images, regions);
  EXPECT_GT(regions, 1000);
}

// Regions crossing tile borders in every direction, and touching regions of other classes.
TEST(RegionExtractor, EqualsReferenceForShapesAcrossTileBordersAndTouchingClasses) {
  cv::Mat1b labels(96, 128, static_cast<std::uint8_t>(ColorClass::None));
  const auto value = [](ColorClass c) { return cv::Scalar(static_cast<int>(c)); };
  cv::rectangle(labels, cv::Rect(10, 28, 60, 6), value(ColorClass::Blue), cv::FILLED);    // across x = 32, 64
  cv::rectangle(labels, cv::Rect(10, 34, 60, 6), value(ColorClass::Yellow), cv::FILLED);  // touching it below
  cv::line(labels, {100, 2}, {70, 93}, value(ColorClass::Pink), 3);        // diagonal, border to border
  cv::circle(labels, {32, 70}, 9, value(ColorClass::Orange), cv::FILLED);  // on a tile corner
  cv::rectangle(labels, cv::Rect(120, 60, 8, 36), value(ColorClass::Blue),
                cv::FILLED);  // in the image corner
  cv::rectangle(labels, cv::Rect(63, 60, 2, 30), value(ColorClass::Orange),
                cv::FILLED);  // too thin: opened away
  for (const int kernel : {0, 3, 5}) {
    const RegionParams params = binaryParams(kernel, 32);
    const Extraction got = extract(colorsOf(labels), params);
    const std::vector<Blob> want = reference(labels, params);
    EXPECT_TRUE(sameBlobs(blobsOf(got.regions), want)) << "kernel " << kernel;
    EXPECT_GE(want.size(), kernel == 0 ? 6u : 5u);
  }
}

// Markers on a diagonal make one 8-connected tile group whose bounding box is mostly
// empty: only the tiles near hits are classified (the rest is None without a look), and
// the regions still equal the reference. Classifying the whole area would take its
// 128 x 128 core plus the margin, 17424 pixels.
TEST(RegionExtractor, ClassifiesOnlyTilesNearHitsOfPackedMarkers) {
  cv::Mat1b labels(160, 160, static_cast<std::uint8_t>(ColorClass::None));
  for (int t = 0; t < 8; ++t) {
    cv::circle(labels, {16 * t + 8, 16 * t + 8}, 5, cv::Scalar(static_cast<int>(ColorClass::Blue)),
               cv::FILLED);
  }
  const RegionParams params = binaryParams(3, 16);
  const Extraction got = extract(colorsOf(labels), params);
  EXPECT_TRUE(sameBlobs(blobsOf(got.regions), reference(labels, params)));
  EXPECT_EQ(got.regions.size(), 8u);
  // 8 tiles of 16 x 16 (2048 px), plus the 5 x 5 opening tests of hits scanned before
  // their tile was known to be needed.
  std::printf("[ packed ] %u pixels classified for 8 markers in a 128 x 128 area\n",
              got.stats.classified_pixels);
  EXPECT_GE(got.stats.classified_pixels, 8u * 256u);
  EXPECT_LE(got.stats.classified_pixels, 8u * 256u + 8u * 4u * 25u);
}

// ------------------------------------------------------------------ search windows

TEST(RegionExtractor, WindowsReturnCrossingRegionsWholeAndNothingOutside) {
  cv::Mat1b labels(200, 300, static_cast<std::uint8_t>(ColorClass::None));
  cv::rectangle(labels, cv::Rect(40, 50, 70, 12), cv::Scalar(static_cast<int>(ColorClass::Blue)), cv::FILLED);
  cv::circle(labels, {220, 140}, 10, cv::Scalar(static_cast<int>(ColorClass::Pink)), cv::FILLED);
  const cv::Mat bgr = colorsOf(labels);
  RegionParams params = binaryParams(3, 32);
  params.max_area = 20000;
  const std::vector<Blob> global = blobsOf(extract(bgr, params).regions);
  ASSERT_EQ(global.size(), 2u);

  // The window holds the left half of the bar and none of the disc.
  const std::vector<Blob> windowed = blobsOf(extract(bgr, params, {cv::Rect(0, 20, 75, 60)}).regions);
  ASSERT_EQ(windowed.size(), 1u);
  EXPECT_TRUE(sameBlobs(windowed, {global[0]}));
  EXPECT_EQ(windowed[0].area, 70 * 12);
}

// Overlapping windows (robots close together) are scanned as their union: each grid point
// once, the regions those of the union. Two copies of a window cost what one does; a
// window and a shifted copy cost the grid points of their union, counted by hand.
TEST(RegionExtractor, OverlappingWindowsScanTheirUnionOnce) {
  cv::Mat1b labels(200, 300, static_cast<std::uint8_t>(ColorClass::None));
  cv::rectangle(labels, cv::Rect(40, 50, 70, 12), cv::Scalar(static_cast<int>(ColorClass::Blue)), cv::FILLED);
  cv::circle(labels, {120, 100}, 10, cv::Scalar(static_cast<int>(ColorClass::Pink)), cv::FILLED);
  const cv::Mat bgr = colorsOf(labels);
  RegionParams params = binaryParams(3, 16);
  params.max_area = 20000;
  const cv::Rect a(30, 40, 90, 60), b(60, 70, 90, 60);  // union: 30..150 x 40..130, minus two corners
  const Extraction one = extract(bgr, params, {a});
  const Extraction twice = extract(bgr, params, {a, a});
  EXPECT_EQ(twice.stats.grid_points, one.stats.grid_points);
  EXPECT_EQ(one.stats.grid_points, 30u * 20u);  // multiples of 3 in [30, 120) x [40, 100)
  EXPECT_TRUE(sameBlobs(blobsOf(twice.regions), blobsOf(one.regions)));
  const Extraction both = extract(bgr, params, {a, b});
  // Columns 30..147 (40 multiples of 3) over rows 72..99 (10 rows: both windows), columns
  // 30..117 (30) over rows 42..69 (10), columns 60..147 (30) over rows 102..129 (10).
  EXPECT_EQ(both.stats.grid_points, 40u * 10u + 30u * 10u + 30u * 10u);
  const std::vector<Blob> union_regions = blobsOf(both.regions);
  ASSERT_EQ(union_regions.size(), 2u);
  EXPECT_TRUE(sameBlobs(union_regions, blobsOf(extract(bgr, params).regions)));
}

TEST(RegionExtractor, WindowedRegionsAreGlobalRegionsAndCoverTheWindows) {
  std::mt19937 rng(11);
  int checked = 0, returned = 0;
  for (const int kernel : {0, 2, 3, 5}) {
    for (int i = 0; i < 30; ++i) {
      const cv::Mat1b labels = randomLabels(rng, {240, 180});
      const cv::Mat bgr = colorsOf(labels);
      const RegionParams params = binaryParams(kernel, 16);
      const std::vector<Blob> global = blobsOf(extract(bgr, params).regions);
      std::uniform_int_distribution<int> x(-20, 230), y(-20, 170), side(10, 90);
      std::vector<cv::Rect> windows;
      for (int w = 0; w < 3; ++w) windows.emplace_back(x(rng), y(rng), side(rng), side(rng));
      const std::vector<Blob> got = blobsOf(extract(bgr, params, windows).regions);
      returned += static_cast<int>(got.size());
      // Every returned region is a whole global region near a window ...
      for (const Blob& b : got) {
        ASSERT_TRUE(std::binary_search(global.begin(), global.end(), b))
            << describe(b) << " is no global region";
        const Blob& g = *std::lower_bound(global.begin(), global.end(), b);
        EXPECT_TRUE(sameBlobs({b}, {g}));
        const cv::Rect near(b.bbox.x - 2, b.bbox.y - 2, b.bbox.width + 4, b.bbox.height + 4);
        EXPECT_TRUE(std::any_of(windows.begin(), windows.end(),
                                [&](const cv::Rect& w) { return !(w & near).empty(); }))
            << describe(b) << " is outside every window";
      }
      // ... and every global region inside a window is returned.
      for (const Blob& g : global) {
        const bool inside = std::any_of(windows.begin(), windows.end(),
                                        [&](const cv::Rect& w) { return (w & g.bbox) == g.bbox; });
        if (!inside) continue;
        ++checked;
        EXPECT_TRUE(std::binary_search(got.begin(), got.end(), g))
            << describe(g) << " inside a window is missing";
      }
    }
  }
  std::printf("[ windows ] %d regions returned, %d regions fully inside windows all found\n", returned,
              checked);
  EXPECT_GT(checked, 50);
}

// ------------------------------------------------------------------ moments of anti-aliased shapes

namespace {

// Exact-enough coverage: 64 x 64 samples in pixels near the edge, blended linearly
// between the shape colour and the background (the renderer's linear light model).
cv::Mat renderCoverage(cv::Size size, const std::function<double(double, double)>& sdf,
                       const cv::Vec3b& shape, const cv::Vec3b& background) {
  constexpr int kSamples = 64;
  cv::Mat3b image(size);
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) {
      double coverage;
      const double d = sdf(x, y);
      if (d < -1) {
        coverage = 1;
      } else if (d > 1) {
        coverage = 0;
      } else {
        int in = 0;
        for (int sy = 0; sy < kSamples; ++sy) {
          for (int sx = 0; sx < kSamples; ++sx) {
            in += sdf(x - 0.5 + (sx + 0.5) / kSamples, y - 0.5 + (sy + 0.5) / kSamples) < 0;
          }
        }
        coverage = static_cast<double>(in) / (kSamples * kSamples);
      }
      for (int c = 0; c < 3; ++c) {
        image(y, x)[c] =
            cv::saturate_cast<std::uint8_t>(background[c] + coverage * (shape[c] - background[c]));
      }
    }
  }
  return image;
}

// A table that, like one calibrated on real markers, takes the shape colour and its
// mixtures down to 60 % coverage, and the background as a background class.
std::shared_ptr<const ColorTable> blendTable(const cv::Vec3b& shape, const cv::Vec3b& background,
                                             ColorClass c) {
  ClassPixels samples;
  for (int i = 60; i <= 100; i += 2) {
    cv::Vec3b p;
    for (int k = 0; k < 3; ++k)
      p[k] = cv::saturate_cast<std::uint8_t>(background[k] + i / 100.0 * (shape[k] - background[k]));
    samples[c].push_back(p);
  }
  samples[ColorClass::RobotTop].assign(4, background);
  return std::make_shared<const ColorTable>(ColorTable::build(samples));
}

}  // namespace

TEST(RegionExtractor, CoverageWeightedMomentsOfAntiAliasedDiscsAndRectangles) {
  const cv::Vec3b pink(180, 80, 255), black(25, 25, 25);
  const PixelClassifier classifier(blendTable(pink, black, ColorClass::Pink));
  RegionParams params;
  params.max_regions_per_class = 4;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> sub(-0.5, 0.5), angle(-M_PI / 2, M_PI / 2);
  double disc_worst = 0, rect_worst = 0, angle_worst = 0, binary_worst = 0;
  for (int i = 0; i < 40; ++i) {
    const double cx = 32 + sub(rng), cy = 30 + sub(rng);
    // Disc of a 40 mm role tag at ~5 mm/px.
    const double radius = 4.0 + 0.05 * i;
    const cv::Mat disc = renderCoverage(
        {64, 60}, [&](double x, double y) { return std::hypot(x - cx, y - cy) - radius; }, pink, black);
    const Extraction d = extract(disc, params, {}, classifier);
    ASSERT_EQ(d.regions.size(), 1u) << "disc " << i;
    disc_worst = std::max(disc_worst, std::hypot(d.regions[0].cx - cx, d.regions[0].cy - cy));
    RegionParams binary = params;
    binary.coverage_weighted_moments = false;
    const Extraction db = extract(disc, binary, {}, classifier);
    binary_worst = std::max(binary_worst, std::hypot(db.regions[0].cx - cx, db.regions[0].cy - cy));

    // Team tag 80 x 30 mm: 16 x 6 px.
    const double theta = angle(rng), c = std::cos(theta), s = std::sin(theta);
    const cv::Mat rect = renderCoverage(
        {64, 60},
        [&](double x, double y) {
          const double u = (x - cx) * c + (y - cy) * s, v = -(x - cx) * s + (y - cy) * c;
          return std::max(std::abs(u) - 8.0, std::abs(v) - 3.0);
        },
        pink, black);
    const Extraction r = extract(rect, params, {}, classifier);
    ASSERT_EQ(r.regions.size(), 1u) << "rectangle " << i;
    rect_worst = std::max(rect_worst, std::hypot(r.regions[0].cx - cx, r.regions[0].cy - cy));
    const double error = std::remainder(r.regions[0].orientation - theta, M_PI);
    angle_worst = std::max(angle_worst, std::abs(error) * 180 / M_PI);
  }
  std::printf(
      "[ moments ] worst centroid error: discs %.4f px (binary moments %.3f px), 16x6 rectangles %.4f px; "
      "worst orientation error %.3f deg\n",
      disc_worst, binary_worst, rect_worst, angle_worst);
  EXPECT_LT(disc_worst, 0.05);
  EXPECT_LT(rect_worst, 0.05);
  EXPECT_LT(angle_worst, 0.5);
}

// The default opening (2x2) against a team tag in a wide-angle lens' corner: 4 px wide, on
// the diagonal, a few of its pixels read orange (held-out seeds 9031/9032: a 3x3 opening cut
// such a tag into 18 + 9 px, each too small for a tag). It stays one region with most of its
// pixels; a one-pixel yellow rim around an orange ball (its edge mixed with the carpet)
// leaves no region that the ball would seem to lie on.
TEST(RegionExtractor, TheDefaultOpeningKeepsAThinSplitTagAndDropsAOnePixelRim) {
  cv::Mat1b labels(64, 64, static_cast<std::uint8_t>(ColorClass::None));
  const auto yellow = static_cast<std::uint8_t>(ColorClass::Yellow);
  const auto orange = static_cast<std::uint8_t>(ColorClass::Orange);
  int tag_pixels = 0;
  for (int y = 0; y < labels.rows; ++y) {
    for (int x = 0; x < labels.cols; ++x) {
      // An 18 px bar of half-width 2.1 px from (12, 40) up and to the right.
      const double along = ((x - 12) - (y - 40)) / std::sqrt(2.0);
      const double across = std::abs((x - 12) + (y - 40)) / std::sqrt(2.0);
      if (along >= 0 && along <= 18 && across <= 2.1) labels(y, x) = yellow, ++tag_pixels;
      const double r = std::hypot(x - 45, y - 45);  // the ball and its rim
      if (r <= 4.0) labels(y, x) = orange;
      if (r > 4.0 && r <= 5.2) labels(y, x) = yellow;
    }
  }
  int holes = 0;
  for (const cv::Point p :
       {cv::Point(14, 39), cv::Point(17, 37), cv::Point(18, 35), cv::Point(21, 33), cv::Point(23, 31)}) {
    ASSERT_EQ(labels(p), yellow);
    labels(p) = orange;
    ++holes;
  }
  const Extraction e = extract(colorsOf(labels), RegionParams{});
  std::vector<const Region*> yellows, oranges;
  for (const Region& r : e.regions) (r.color == ColorClass::Yellow ? yellows : oranges).push_back(&r);
  ASSERT_EQ(yellows.size(), 1u) << "the tag in one piece, the rim in none";
  EXPECT_LT(std::hypot(yellows[0]->cx - 18.4, yellows[0]->cy - 33.6), 1.5);
  EXPECT_GE(yellows[0]->area, 0.85 * (tag_pixels - holes));
  ASSERT_EQ(oranges.size(), 1u);
  EXPECT_NEAR(oranges[0]->cx, 45, 0.5);
}

// ------------------------------------------------------------------ the cap and bounded work

TEST(RegionExtractor, CapKeepsTheLargestRegionsAndCountsTheRest) {
  cv::Mat1b labels(120, 400, static_cast<std::uint8_t>(ColorClass::None));
  for (int i = 0; i < 20; ++i) {
    cv::rectangle(labels, cv::Rect(5 + 19 * i, 10 + (i % 3) * 35, 6 + (i * 7) % 11, 5 + i),
                  cv::Scalar(static_cast<int>(ColorClass::Blue)), cv::FILLED);
  }
  cv::circle(labels, {200, 100}, 8, cv::Scalar(static_cast<int>(ColorClass::Orange)), cv::FILLED);
  const cv::Mat bgr = colorsOf(labels);
  RegionParams all = binaryParams(3, 32);
  const std::vector<Region> uncapped = extract(bgr, all).regions;
  ASSERT_EQ(std::count_if(uncapped.begin(), uncapped.end(),
                          [](const Region& r) { return r.color == ColorClass::Blue; }),
            20);

  RegionParams capped = all;
  capped.max_regions_per_class = 5;
  const Extraction got = extract(bgr, capped);
  std::vector<std::uint32_t> want_areas, got_areas;
  for (const Region& r : uncapped) {
    if (r.color == ColorClass::Blue) want_areas.push_back(r.area);
  }
  for (const Region& r : got.regions) {
    if (r.color == ColorClass::Blue) got_areas.push_back(r.area);
  }
  std::sort(want_areas.rbegin(), want_areas.rend());
  want_areas.resize(5);
  std::sort(got_areas.rbegin(), got_areas.rend());
  EXPECT_EQ(got_areas, want_areas);
  EXPECT_EQ(got.stats.cap_hits[static_cast<int>(ColorClass::Blue)], 15u);
  EXPECT_EQ(got.stats.cap_hits[static_cast<int>(ColorClass::Orange)], 0u);
  EXPECT_EQ(std::count_if(got.regions.begin(), got.regions.end(),
                          [](const Region& r) { return r.color == ColorClass::Orange; }),
            1);
}

// ------------------------------------------------------------------ rendered frames

namespace {

struct RenderedField {
  ScenarioConfig scenario;
  FieldGeometry field;
  PatternSet patterns;
  std::vector<std::unique_ptr<FieldRenderer>> renderers;
  std::shared_ptr<const ColorTable> table;

  // Table from the calibration samples of both cameras at the start (as in the colour
  // table's own test).
  explicit RenderedField(GameSimulator& sim, const ScenarioConfig& s = {})
      : scenario(s), patterns(patternSetByName(s.pattern)) {
    for (int camera = 0; camera < 2; ++camera) {
      renderers.push_back(std::make_unique<FieldRenderer>(
          CameraModel::defaultCamera(field, camera, scenario.width, scenario.height), field, patterns,
          scenario));
    }
    ClassPixels samples;
    for (const auto& renderer : renderers) {
      RenderedFrame frame;
      renderer->render(sim.state(), 0, frame);
      const ColorSamples polygons = calibrationSamples(sim.state(), renderer->camera(), field, patterns);
      for (auto& [c, px] : collectSamplePixels(frame.image, polygons)) {
        samples[c].insert(samples[c].end(), px.begin(), px.end());
      }
    }
    table = std::make_shared<const ColorTable>(ColorTable::build(samples));
  }
};

// Median times of `a` and `b`, run alternately `repeats` times each: a slower phase of a
// shared machine weighs on both alike.
std::pair<double, double> alternatingMedianMs(const std::function<void()>& a, const std::function<void()>& b,
                                              int repeats) {
  auto ms = [](const std::function<void()>& run) {
    const auto start = std::chrono::steady_clock::now();
    run();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  };
  std::vector<double> a_ms, b_ms;
  for (int i = 0; i < repeats; ++i) {
    a_ms.push_back(ms(a));
    b_ms.push_back(ms(b));
  }
  return {percentile(a_ms, 50), percentile(b_ms, 50)};
}

}  // namespace

// Colour noise hits the grid everywhere, but the opening kills all but specks: the hit check must
// keep the work within a bounded number of normal frames (ratio measured in this run, not
// absolute). A generalised table (ColorTableParams::generalize_sigmas) gives marker colours
// to more of the colour cube, so uniform noise hits about half the frame's tiles: 12-14x a
// normal frame on a quiet machine, where the table of the samples' bodies alone gave 2-4x
// (docs/segmentation.md); 24-27x while another build ran beside it (the noise frame's
// larger working set suffers more). The markers' brightness variants
// (ColorTableParams::brightness_spread) widen the classes further: the tiles the noise
// frame's grid hits now hold 94 % of its pixels (54 % without): 35x a normal frame on a
// quiet machine, 48x with an evaluation running beside it; the ball's carpet mixture levels
// (ColorTableParams::ball_carpet_mix, ball_carpet_unmix) 96.0 %. The fallback of holes to
// the nearest marker (ColorTableParams::fallback_sigmas 4.5) makes more hits survive the
// hit check, whose patches are classified before the tiles: 1.52x the frame's pixels
// classified, 64-67x a normal frame on a quiet machine (3.5 sigmas: 1.16x, 44x; 6 sigmas:
// 1.91x, 75x). Another print's spread of the markers (ColorTableParams::print_spread 0.1):
// 1.78x the frame's pixels, 47-61x a normal frame. The V' band tests (2026-12-05) made the
// normal frame ~2x faster and the noise frame no dearer per pixel (its random colours miss
// the caches at every lookup): 1.24x the frame's pixels, 94-106x a normal frame on a quiet
// machine, 166x beside a build; with a faster scan tried on 2026-12-06 114-187x, and once 363x
// under load. That ratio is printed, not asserted: the two frames suffer load differently.
// The time is bounded against classifying every pixel of the noise frame once, which misses
// the same caches (4.1-4.2x, stable under load); the pixel count, which does not depend on
// the machine, is the tight bound.
TEST(RegionExtractorOnRenderedFrames, ColourNoiseCostsAtMostAFewWholeFrameLookups) {
  ScenarioConfig scenario;
  const FieldGeometry field;
  GameSimulator sim(scenario, field, patternSetByName(scenario.pattern).maxRobotsPerTeam());
  RenderedField rendered(sim);
  RenderedFrame frame;
  rendered.renderers[0]->render(sim.state(), 0, frame);
  cv::Mat noise(frame.image.size(), CV_8UC3);
  cv::RNG(5).fill(noise, cv::RNG::UNIFORM, 0, 256);

  const PixelClassifier classifier(rendered.table);
  const BlockOffsets offsets;
  RegionExtractor extractor;
  std::vector<Region> regions;
  RegionStatistics normal_stats, noise_stats;
  const FrameClassifier normal_frame(classifier, frame.image, PixelLayout::Bgr, offsets);
  const FrameClassifier noise_frame(classifier, noise, PixelLayout::Bgr, offsets);
  const auto [normal_ms, noise_ms] =
      alternatingMedianMs([&] { extractor.extract(normal_frame, {}, regions, normal_stats); },
                          [&] { extractor.extract(noise_frame, {}, regions, noise_stats); }, 9);
  // Every pixel of the noise frame looked up once, with the same random colours missing the
  // same caches: the work the pixel bound below allows, timed against the extraction.
  const auto model = SegmentationModel::fromTable(rendered.table);
  const auto [whole_ms, noise_again_ms] =
      alternatingMedianMs([&] { classifyAll(*model, noise, PixelLayout::Bgr); },
                          [&] { extractor.extract(noise_frame, {}, regions, noise_stats); }, 5);
  std::printf(
      "[ noise ] normal frame %.2f ms (%u grid points, %u pixels classified); colour noise %.2f ms "
      "(%u pixels classified, %zu regions): ratio %.2f; every noise pixel classified once %.2f ms, "
      "the noise frame's extraction %.2f times that\n",
      normal_ms, normal_stats.grid_points, normal_stats.classified_pixels, noise_ms,
      noise_stats.classified_pixels, regions.size(), noise_ms / normal_ms, whole_ms,
      noise_again_ms / whole_ms);
  // The 2x2 opening leaves a few specks of chance 2x2 squares of one class (22 of 5-10 px
  // on this frame; the 3x3 opening left none): far fewer than the frame's markers and far
  // smaller (a role tag here is ~50 px, a team tag ~100 px).
  EXPECT_LE(regions.size(), noise.total() / 40000);
  for (const Region& r : regions) EXPECT_LE(r.area, 12u) << colorClassName(r.color);
  EXPECT_LE(noise_again_ms, 8 * whole_ms);
  EXPECT_LE(noise_stats.classified_pixels, noise.total() * 2);
}

namespace {

// Centroid errors of the regions of one rendered frame against the projections of the
// visible markers and ball: every target must have exactly one region of its class within
// 4 px (its error appended to `errors`); regions matching none away from the image border
// are counted in `extra` (those of robots partly in the image are expected).
void matchMarkers(const GameSimulator& sim, const RenderedField& rendered, const FieldRenderer& renderer,
                  const std::vector<Region>& regions, cv::Size image, std::vector<double>& errors,
                  int& extra) {
  struct Target {
    ColorClass color;
    Eigen::Vector3d centre;
    std::string name;
  };
  std::vector<Target> targets;
  for (const RobotState& robot : sim.state().robots) {
    if (!renderer.robotVisible(robot)) continue;
    const double c = std::cos(robot.theta), s = std::sin(robot.theta);
    for (const ColoredMarker& m : rendered.patterns.markers(robot.team, robot.id)) {
      targets.push_back({m.color,
                         {robot.x + c * m.shape.x - s * m.shape.y, robot.y + s * m.shape.x + c * m.shape.y,
                          rendered.patterns.height(robot.team)},
                         std::string(teamName(robot.team)) + " " + std::to_string(robot.id)});
    }
  }
  for (const BallState& ball : sim.state().balls) {
    if (renderer.ballVisible(ball, sim.state().robots))
      targets.push_back({ColorClass::Orange, {ball.x, ball.y, ball.z}, "ball"});
  }
  std::vector<int> matched(regions.size(), 0);
  for (const Target& t : targets) {
    const Eigen::Vector2d expected = *renderer.camera().project(t.centre);
    int found = 0;
    double error = 0;
    for (std::size_t r = 0; r < regions.size(); ++r) {
      const double d = std::hypot(regions[r].cx - expected.x(), regions[r].cy - expected.y());
      if (regions[r].color != t.color || d > 4.0) continue;
      ++found;
      ++matched[r];
      error = d;
    }
    EXPECT_EQ(found, 1) << colorClassName(t.color) << " marker of " << t.name << " at "
                        << expected.transpose();
    if (found == 1) errors.push_back(error);
  }
  for (std::size_t r = 0; r < regions.size(); ++r) {
    if (matched[r]) continue;
    const cv::Point2d c(regions[r].cx, regions[r].cy);
    extra += !(c.x < 40 || c.y < 40 || c.x > image.width - 40 || c.y > image.height - 40);
  }
}

// The median and 90th percentile of `errors` (sorted in place), printed under `title` with
// the largest.
std::pair<double, double> printErrors(const char* title, std::vector<double>& errors, int extra) {
  std::sort(errors.begin(), errors.end());
  const auto at = [&](double q) { return errors[static_cast<std::size_t>(q * (errors.size() - 1))]; };
  std::printf(
      "[ %s ] %zu markers: centroid error median %.3f px, 90 %% %.3f px, max %.3f px; "
      "%d unmatched regions away from the image border\n",
      title, errors.size(), at(0.5), at(0.9), errors.back(), extra);
  return {at(0.5), at(0.9)};
}

}  // namespace

TEST(RegionExtractorOnRenderedFrames, EveryVisibleMarkerGivesOneRegionAtItsProjectedCentre) {
  ScenarioConfig scenario;
  const FieldGeometry field;
  GameSimulator sim(scenario, field, patternSetByName(scenario.pattern).maxRobotsPerTeam());
  RenderedField rendered(sim);
  const PixelClassifier classifier(rendered.table);
  const BlockOffsets offsets;
  RegionExtractor extractor;

  std::vector<double> errors;
  int extra = 0;
  for (std::int64_t later = 1; later <= 4; ++later) {
    for (int i = 0; i < 90; ++i) sim.step(1.0 / scenario.fps);
    for (const auto& renderer : rendered.renderers) {
      RenderedFrame frame;
      renderer->render(sim.state(), later * 90, frame);
      const FrameClassifier classified(classifier, frame.image, PixelLayout::Bgr, offsets);
      std::vector<Region> regions;
      RegionStatistics stats;
      extractor.extract(classified, {}, regions, stats);
      matchMarkers(sim, rendered, *renderer, regions, frame.image.size(), errors, extra);
    }
  }
  ASSERT_GT(errors.size(), 40u);
  printErrors("rendered", errors, extra);
  EXPECT_LT(errors.back(), 0.3);
  EXPECT_EQ(extra, 0);
}

// The same frames from an RGGB sensor, segmented on its 2x2 quads, with both patterns. A
// quad's R, G and B are seen a pixel apart: each site weighs its own coverage at its own
// position (with the quad's coverage placed at its centre: median 0.41 px, 90 % 0.69 px,
// two-tag), only the ring's quads that touch the region weigh in (with the 2-quad ring the
// carpet beyond the robot's rim counted as half-covered green around the SSL pattern's
// green dots: median 0.44 px, 90 % 1.62 px), and the colour fringes along the field lines
// are dropped (mosaic_fringes.h; without: 1015 unmatched regions in these 8 two-tag
// frames, and two sky-blue markers pushed out by the cap).
TEST(RegionExtractorOnRenderedFrames, OnBayerQuadsEveryMarkerCentroidLiesAtItsProjectedCentre) {
  struct Case {
    const char* pattern;
    double median, p90;  // px, bounds of the centroid error
    int extra;  // unmatched regions in the 8 frames (fringes where a line runs along a quad's diagonal)
  };
  for (const Case& c : {Case{"two_tag", 0.1, 0.25, 8 * 12}, Case{"ssl", 0.15, 0.5, 8 * 12}}) {
    SCOPED_TRACE(c.pattern);
    ScenarioConfig scenario;
    scenario.pattern = c.pattern;
    const FieldGeometry field;
    GameSimulator sim(scenario, field, patternSetByName(scenario.pattern).maxRobotsPerTeam());
    RenderedField rendered(sim, scenario);
    ScenarioConfig bayer = scenario;
    bayer.sensor.bayer = "rggb";
    SegmentationParams params;
    params.illumination_k = 0;  // the light as calibrated
    Segmenter segmenter(params);
    // Tables of the quads' colours, as a Bayer camera is calibrated (calibrateColorTable on
    // classifiedColors): a table of the colour image takes the quads across the white lines'
    // edges (R on the line, B on the carpet) for yellow.
    std::vector<std::shared_ptr<const SegmentationModel>> models;
    for (int camera = 0; camera < 2; ++camera) {
      models.push_back(SegmentationModel::fromTable(
          std::make_shared<const ColorTable>(calibrateSyntheticCamera(bayer, camera, {4, 0.5}))));
    }
    std::vector<double> errors;
    int extra = 0;
    for (std::int64_t later = 1; later <= 4; ++later) {
      for (int i = 0; i < 90; ++i) sim.step(1.0 / scenario.fps);
      for (int camera = 0; camera < 2; ++camera) {
        const FieldRenderer renderer(rendered.renderers[camera]->camera(), field, rendered.patterns, bayer);
        RenderedFrame frame;
        renderer.render(sim.state(), later * 90, frame);
        ASSERT_EQ(frame.image.type(), CV_8UC1);
        SegmentationResult result;
        segmenter.process(*models[camera], frame.image, PixelLayout::BayerRggb, {}, result);
        matchMarkers(sim, rendered, renderer, result.regions, frame.image.size(), errors, extra);
      }
    }
    ASSERT_GT(errors.size(), 40u);
    const std::string title = std::string("rendered, Bayer quads, ") + c.pattern;
    const auto [median, p90] = printErrors(title.c_str(), errors, extra);
    EXPECT_LT(median, c.median);
    EXPECT_LT(p90, c.p90);
    EXPECT_LE(extra, c.extra);
  }
}
