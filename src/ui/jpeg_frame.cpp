#include "soccer_vision/ui/jpeg_frame.h"

#include <stdexcept>
#include <vector>

#include <opencv2/imgcodecs.hpp>

namespace soccer_vision {

std::string encodeJpeg(const cv::Mat& bgr, int quality) {
  std::vector<unsigned char> bytes;
  if (bgr.empty() || !cv::imencode(".jpg", bgr, bytes, {cv::IMWRITE_JPEG_QUALITY, quality}))
    throw std::runtime_error("cannot encode a " + std::to_string(bgr.cols) + "x" + std::to_string(bgr.rows) +
                             " image as JPEG");
  return std::string(bytes.begin(), bytes.end());
}

}  // namespace soccer_vision
