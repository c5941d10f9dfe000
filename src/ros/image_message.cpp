#include "soccer_vision/ros/image_message.h"

#include <cstddef>
#include <cstdint>

#include "soccer_vision/common/camera_model.h"

namespace soccer_vision {

namespace {

int cvTypeOf(PixelLayout layout) { return isBayer(layout) ? CV_8UC1 : CV_8UC3; }

}  // namespace

bool imageMessageIsConsistent(const sensor_msgs::Image& msg, PixelLayout layout) {
  const std::size_t row = static_cast<std::size_t>(msg.width) * CV_ELEM_SIZE(cvTypeOf(layout));
  const auto max_side = static_cast<std::uint32_t>(kMaxImageSide);
  return msg.width > 0 && msg.height > 0 && msg.width <= max_side && msg.height <= max_side &&
         msg.step >= row && msg.data.size() >= static_cast<std::size_t>(msg.step) * msg.height &&
         (!isBayer(layout) || (msg.width % 2 == 0 && msg.height % 2 == 0));
}

cv::Mat imageView(const sensor_msgs::Image& msg, PixelLayout layout, bool* malformed) {
  const bool bad = !imageMessageIsConsistent(msg, layout);
  if (malformed) *malformed = bad;
  if (bad) return {};
  return cv::Mat(static_cast<int>(msg.height), static_cast<int>(msg.width), cvTypeOf(layout),
                 const_cast<std::uint8_t*>(msg.data.data()), msg.step);
}

}  // namespace soccer_vision
