// Checking a sensor_msgs/Image before its bytes are read as pixels: the segmentation nodelet
// and the bag reader drop the same malformed frames.
#pragma once

#include <opencv2/core.hpp>
#include <sensor_msgs/Image.h>

#include "soccer_vision/segmentation/pixel_classifier.h"

namespace soccer_vision {

// True when the size fields and the data agree for `layout` (the encoding's layout): a
// non-empty image at most kMaxImageSide (camera_model.h) a side, a step that holds a row, data for every row,
// and a Bayer mosaic of whole 2x2 quads (even width and height).
bool imageMessageIsConsistent(const sensor_msgs::Image& msg, PixelLayout layout);

// The message's pixels as a cv::Mat sharing its data, or an empty Mat when the message is
// not consistent (`malformed` then says so).
cv::Mat imageView(const sensor_msgs::Image& msg, PixelLayout layout, bool* malformed = nullptr);

}  // namespace soccer_vision
