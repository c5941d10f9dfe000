// Test helper: classification of a frame against the renderer's per-pixel labels.
// Marker interior: a pixel whose label is a marker colour and whose 8 neighbours share it
// (edge pixels are mixtures). Background: a non-marker pixel with no marker pixel among its
// 8 neighbours; a false positive is one classified as a marker colour.
#pragma once

#include <cstdint>
#include <set>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "soccer_vision/common/color_class.h"

namespace soccer_vision::test {

struct Accuracy {
  std::int64_t interior = 0, interior_right = 0, background = 0, background_as_marker = 0;
  double markers() const { return static_cast<double>(interior_right) / interior; }
  double falsePositives() const { return static_cast<double>(background_as_marker) / background; }
  void add(const Accuracy& o) {
    interior += o.interior;
    interior_right += o.interior_right;
    background += o.background;
    background_as_marker += o.background_as_marker;
  }
};

// Adds the frame's counts to `a`. `counted`: the marker colours whose interiors count (all
// when empty).
inline void countMarkerInteriors(const cv::Mat1b& truth, const cv::Mat1b& labels, Accuracy& a,
                                 const std::set<ColorClass>& counted = {}) {
  for (int y = 1; y + 1 < truth.rows; ++y) {
    for (int x = 1; x + 1 < truth.cols; ++x) {
      const std::uint8_t t = truth(y, x);
      bool uniform = true, near_marker = false;
      for (int j = -1; j <= 1; ++j) {
        for (int i = -1; i <= 1; ++i) {
          uniform = uniform && truth(y + j, x + i) == t;
          near_marker = near_marker || isMarkerColor(static_cast<ColorClass>(truth(y + j, x + i)));
        }
      }
      if (isMarkerColor(static_cast<ColorClass>(t))) {
        if (!counted.empty() && !counted.count(static_cast<ColorClass>(t))) continue;
        a.interior += uniform;
        a.interior_right += uniform && labels(y, x) == t;
      } else if (!near_marker) {
        ++a.background;
        a.background_as_marker += isMarkerColor(static_cast<ColorClass>(labels(y, x)));
      }
    }
  }
}

// Whether the region extractor's scan with a grid of `stride` reads pixel (x, y) of a
// `size` image: a grid point, or any pixel of the last column or row when the grid misses
// them (scanGridStride, region_extractor.cpp's scanUnion).
inline bool scanReads(int x, int y, cv::Size size, int stride) {
  return (x % stride == 0 && y % stride == 0) || (x == size.width - 1 && (size.width - 1) % stride != 0) ||
         (y == size.height - 1 && (size.height - 1) % stride != 0);
}

// The labels as the regions see them: each marker colour's pixels kept where its mask
// survives an opening with a k x k square (RegionParams::morph_kernel; the closing after it
// only fills holes in what is kept; k <= 1: none) in a component of at least min_area
// pixels (RegionParams::min_area: smaller ones make no region) that holds a point of the
// scan's grid (`stride`, RegionParams::scan_stride; any pixel of the last column or row
// when the grid misses them).
inline cv::Mat1b openedMarkers(const cv::Mat1b& labels, int k, int min_area = 1, int stride = 1) {
  cv::Mat1b out = labels.clone();
  if (k <= 1 && min_area <= 1 && stride <= 1) return out;
  const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(std::max(k, 1), std::max(k, 1)));
  for (int c = 0; c < kNumColorClasses; ++c) {
    if (!isMarkerColor(static_cast<ColorClass>(c))) continue;
    const cv::Mat1b mask = labels == c;
    // Centred as the segmentation's (binary_morphology.h): the dilation takes the erosion's
    // anchor reflected, or an even k would shift the result by a pixel.
    const cv::Point anchor(k / 2, k / 2), reflected(k - 1 - k / 2, k - 1 - k / 2);
    cv::Mat1b opened = mask.clone();
    if (k > 1) {
      cv::erode(mask, opened, kernel, anchor);
      cv::dilate(opened, opened, kernel, reflected);
    }
    cv::Mat1i components;
    cv::Mat stats, centroids;
    const int n = cv::connectedComponentsWithStats(opened, components, stats, centroids, 8, CV_32S);
    std::vector<char> seen(static_cast<std::size_t>(n), stride <= 1);
    for (int y = 0; y < labels.rows && stride > 1; ++y) {
      for (int x = 0; x < labels.cols; ++x) {
        if (opened(y, x) && scanReads(x, y, labels.size(), stride))
          seen[static_cast<std::size_t>(components(y, x))] = 1;
      }
    }
    for (int l = 1; l < n; ++l) {
      if (stats.at<int>(l, cv::CC_STAT_AREA) < min_area || !seen[static_cast<std::size_t>(l)])
        opened.setTo(0, components == l);
    }
    out.setTo(static_cast<int>(ColorClass::None), mask & ~opened);
  }
  return out;
}

}  // namespace soccer_vision::test
