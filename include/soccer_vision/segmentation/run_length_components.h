// 8-connected components of a bit-packed mask from its runs (horizontal stretches of
// foreground): runs of consecutive rows that overlap or touch diagonally are joined by
// union-find. Area, bounding box and the sums of x, y, x², xy, y² of a component come from
// its runs in closed form, so no pixel is visited twice and no label image is written.
// Components are numbered in raster order of their first pixel (OpenCV's block-based
// labelling may number them differently).
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "soccer_vision/segmentation/binary_morphology.h"

namespace soccer_vision {

struct PixelRun {
  int y = 0, x_begin = 0, x_end = 0;  // [x_begin, x_end) in row y
  int component = -1;
};

struct ComponentStats {
  std::uint32_t area = 0;
  cv::Rect bbox;
  // Sums over the pixels, for moments.
  std::int64_t sum_x = 0, sum_y = 0, sum_xx = 0, sum_xy = 0, sum_yy = 0;
};

class RunLengthComponents {
 public:
  // Components of `mask` inside `rect` (cut at its border); every coordinate below is
  // relative to rect.tl().
  void compute(const BitMask& mask, const cv::Rect& rect);

  const std::vector<ComponentStats>& components() const { return components_; }
  // Component of a pixel, -1 for background.
  int componentAt(int x, int y) const;
  // The runs of a component, in raster order.
  const PixelRun* runsBegin(int component) const;
  const PixelRun* runsEnd(int component) const;

 private:
  int findRoot(int run);

  std::vector<PixelRun> runs_;  // raster order
  std::vector<int> row_begin_;  // first run of each row, plus the end
  std::vector<int> parent_;     // union-find over runs
  std::vector<ComponentStats> components_;
  std::vector<PixelRun> runs_by_component_;  // grouped by component, raster order within
  std::vector<int> component_begin_;         // into runs_by_component_, plus the end
};

}  // namespace soccer_vision
