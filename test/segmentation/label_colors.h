// Test helper: a label image (ColorClass values) painted as a colour image, one pure
// colour per class of the palette and `none` elsewhere, so that a colour table built from
// the palette classifies it back into the labels.
#pragma once

#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "soccer_vision/common/color_class.h"

namespace soccer_vision::test {

using Palette = std::vector<std::pair<ColorClass, cv::Vec3b>>;

inline cv::Mat paintLabels(const cv::Mat1b& labels, const Palette& palette, const cv::Vec3b& none) {
  cv::Mat3b image(labels.size(), none);
  for (int y = 0; y < labels.rows; ++y) {
    for (int x = 0; x < labels.cols; ++x) {
      for (const auto& [c, color] : palette) {
        if (labels(y, x) == static_cast<std::uint8_t>(c)) image(y, x) = color;
      }
    }
  }
  return image;
}

}  // namespace soccer_vision::test
