#include "soccer_vision/common/bayer_encoding.h"

#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace soccer_vision {

int bayerToBgrCode(const std::string& e) {
  // OpenCV names a Bayer layout after the second row's 2nd/3rd pixels, so a sensor whose
  // top-left 2x2 block is R G / G B ("rggb") is OpenCV's BayerBG (as in cv_bridge).
  if (e == "bayer_rggb8" || e == "bayer_rggb16") return cv::COLOR_BayerBG2BGR;
  if (e == "bayer_bggr8" || e == "bayer_bggr16") return cv::COLOR_BayerRG2BGR;
  if (e == "bayer_gbrg8" || e == "bayer_gbrg16") return cv::COLOR_BayerGR2BGR;
  if (e == "bayer_grbg8" || e == "bayer_grbg16") return cv::COLOR_BayerGB2BGR;
  return -1;
}

cv::Mat bgrOfEncoding(const cv::Mat& image, const std::string& encoding) {
  if (encoding == "bgr8") return image;
  cv::Mat bgr;
  if (encoding == "rgb8") {
    cv::cvtColor(image, bgr, cv::COLOR_RGB2BGR);
  } else if (const int code = bayerToBgrCode(encoding); code >= 0 && encoding.back() == '8') {
    cv::cvtColor(image, bgr, code);
  } else {
    throw std::invalid_argument("no BGR view of encoding '" + encoding + "' (bgr8, rgb8, bayer_*8)");
  }
  return bgr;
}

}  // namespace soccer_vision
