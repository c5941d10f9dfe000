// Demosaicing a Bayer image of a ROS encoding ("bayer_rggb8", ...) with OpenCV: the one map
// from ROS's names (the sensor's top-left 2x2 block) to OpenCV's (named after the second row).
#pragma once

#include <string>

#include <opencv2/core.hpp>

namespace soccer_vision {

// cv::cvtColor code that demosaics a Bayer encoding (8 or 16 bit) to BGR, or -1 when the
// encoding is not Bayer.
int bayerToBgrCode(const std::string& encoding);

// An image of a ROS encoding as BGR at full resolution, as a camera shows it (what a person
// paints samples on and the field-line fit works on; colour calibration itself reads the
// classifier's colours, classifiedColors): bgr8 shared, rgb8 swapped, an 8-bit Bayer mosaic
// demosaiced. Throws std::invalid_argument for any other encoding.
cv::Mat bgrOfEncoding(const cv::Mat& image, const std::string& encoding);

}  // namespace soccer_vision
