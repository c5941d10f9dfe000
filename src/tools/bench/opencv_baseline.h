// The segmentation a team would write by hand with OpenCV, as the benchmark's yardstick:
// cvtColor to HSV, inRange per marker class (box around the class's valid samples:
// mean ± 2.5 sigma in H, S and V, taken from the colour table's statistics), morphologyEx
// open + close with a 3x3 square, connectedComponentsWithStats. Same frames, same work.
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "soccer_vision/segmentation/color_table.h"

namespace soccer_vision {

class OpenCvBaseline {
 public:
  explicit OpenCvBaseline(const ColorTable& table);
  // Runs the pipeline on a bgr8 frame; returns the number of regions found (all classes).
  std::uint64_t run(const cv::Mat& bgr) const;

 private:
  struct ClassRange {
    // OpenCV 8-bit HSV: H 0..179 (degrees / 2), S and V 0..255; hue may wrap (two ranges).
    std::vector<std::pair<cv::Scalar, cv::Scalar>> ranges;
  };
  std::vector<ClassRange> classes_;
  mutable cv::Mat hsv_, mask_, part_, morph_, labels_, stats_, centroids_;
};

}  // namespace soccer_vision
