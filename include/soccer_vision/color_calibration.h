// Colour calibration as the tool, the nodelet's ~calibrate service and the benchmark do
// it: sample pixels from one or more BGR images and their sample polygons, the paper's
// colour table from them, and the illumination reference (block means of V) of the same
// images, so that run-time adaptation measures light changes against the calibration.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "soccer_vision/color_table.h"
#include "soccer_vision/exchange_formats.h"

namespace soccer_vision {

struct CalibrationImage {
  cv::Mat bgr;            // CV_8UC3
  ColorSamples samples;   // polygons in this image's pixel coordinates
};

// Throws std::invalid_argument for no images, images of different sizes or types, or
// samples that select no pixel at all.
ColorTable calibrateColorTable(const std::vector<CalibrationImage>& images,
                               const ColorTableParams& params = {});

}  // namespace soccer_vision
