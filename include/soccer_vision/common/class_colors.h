// The nominal painted colour of each colour class: what the simulator paints a marker, the
// carpet or a line with, and what debug images draw a class's pixels in.
#pragma once

#include <opencv2/core.hpp>

#include "soccer_vision/common/color_class.h"

namespace soccer_vision {

// Linear BGR albedo (0..255 at unit illumination, with headroom: white stays below 255).
cv::Vec3f classAlbedo(ColorClass c);

// BGR from 0..255 RGB on the same scale as classAlbedo.
cv::Vec3f albedoFromRgb(float r, float g, float b);

}  // namespace soccer_vision
