// Pixels on the painted field lines of one image, to sub-pixel precision: white on green.
// Whiteness is the smallest of B, G, R (high only for white and grey: not for the carpet,
// the coloured markers or the ball); a line is a bright ridge of it, found by the Hessian of
// the smoothed image (Steger's detector): where the curvature across the ridge is strongly
// negative and the ridge's centre, from a second-order fit across it, lies within the pixel.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace soccer_vision {

struct FieldLinePixelParams {
  // Gaussian smoothing [px] before the Hessian; <= 0: 1.5 px per 1280 px of image width
  // (a 10 mm line is about 2 px wide at 1280 px over half a Division B field).
  double sigma = 0;
  double min_contrast = 25;  // whiteness of the ridge above the local background (8-bit levels)
  int max_points = 6000;     // evenly thinned to at most this many (0: all)
};

struct FieldLinePixel {
  Eigen::Vector2d pixel;   // sub-pixel ridge centre (raw image pixel coordinates)
  Eigen::Vector2d normal;  // unit normal of the line in the image
  double contrast = 0;     // whiteness above the local background
};

// `bgr`: CV_8UC3. Throws std::invalid_argument for another type or an empty image.
std::vector<FieldLinePixel> detectFieldLinePixels(const cv::Mat& bgr,
                                                  const FieldLinePixelParams& params = {});

}  // namespace soccer_vision
