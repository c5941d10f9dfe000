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

// The labels as the regions see them: each marker colour's pixels kept where its mask
// survives an opening with a k x k square (RegionParams::morph_kernel; the closing after it
// only fills holes in what is kept). k <= 1: as they are.
inline cv::Mat1b openedMarkers(const cv::Mat1b& labels, int k) {
  cv::Mat1b out = labels.clone();
  if (k <= 1) return out;
  const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k));
  for (int c = 0; c < kNumColorClasses; ++c) {
    if (!isMarkerColor(static_cast<ColorClass>(c))) continue;
    const cv::Mat1b mask = labels == c;
    cv::Mat1b opened;
    cv::morphologyEx(mask, opened, cv::MORPH_OPEN, kernel);
    out.setTo(static_cast<int>(ColorClass::None), mask & ~opened);
  }
  return out;
}

}  // namespace soccer_vision::test
