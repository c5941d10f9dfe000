// Frames for the browser: a BGR image as JPEG bytes, and a throttle so that however many
// browsers ask, a camera's frame is encoded at most `max_rate` times a second.
#pragma once

#include <chrono>
#include <mutex>
#include <string>

#include <opencv2/core.hpp>

namespace soccer_vision {

// Throws std::runtime_error when OpenCV cannot encode the image.
std::string encodeJpeg(const cv::Mat& bgr, int quality);

class JpegThrottle {
 public:
  explicit JpegThrottle(double max_rate) : min_interval_(max_rate > 0 ? 1.0 / max_rate : 0.0) {}
  // The cached JPEG while it is for `frame_key` or younger than 1 / max_rate; otherwise
  // encode() (called without holding the cache) becomes the new cache.
  template <class Encode>
  std::string get(double frame_key, Encode encode) {
    const auto now = std::chrono::steady_clock::now();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const double age = std::chrono::duration<double>(now - encoded_at_).count();
      if (!jpeg_.empty() && (frame_key == key_ || age < min_interval_)) return jpeg_;
    }
    std::string fresh = encode();
    std::lock_guard<std::mutex> lock(mutex_);
    jpeg_ = fresh;
    key_ = frame_key;
    encoded_at_ = now;
    return fresh;
  }

 private:
  double min_interval_;
  std::mutex mutex_;
  std::string jpeg_;
  double key_ = -1;
  std::chrono::steady_clock::time_point encoded_at_{};
};

}  // namespace soccer_vision
