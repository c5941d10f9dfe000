// What a real camera does to the light reaching it, after the scene is lit: colour of the
// light and white-balance error, gain, vignetting, lens blur, shot and read noise, then
// its processing: saturation and a gamma response, quantised to 8 bits. The white-balance
// error's direction is drawn from the seed, the noise from the seed and the frame index.
#pragma once

#include <cstdint>

#include <opencv2/core.hpp>

#include "soccer_vision/simulation/scenario.h"

namespace soccer_vision {

class CameraResponse {
 public:
  CameraResponse(const AppearanceConfig& appearance, const SensorConfig& sensor, int width, int height,
                 std::uint64_t seed);

  // Anything beyond a linear exposure with additive read noise (the renderer's fast path).
  bool active() const { return active_; }
  // Per-channel (B, G, R) gain of the light's colour and the white-balance error, times the gain.
  cv::Vec3f channelGain() const { return channel_gain_; }
  // Relative light at pixel (u, v) after vignetting (1 at the centre).
  float vignette(int u, int v) const;

  // `linear`: CV_32FC3, the scene's light in 8-bit units of a white-balanced camera
  // (changed in place). `read_noise`: CV_32FC3 plane of the same size or empty.
  void apply(cv::Mat& linear, double global_gain, const cv::Mat& read_noise, std::int64_t frame_index,
             cv::Mat dst) const;

 private:
  AppearanceConfig config_;
  std::uint64_t seed_;
  bool active_ = false;
  cv::Vec3f channel_gain_{1, 1, 1};
  int width_ = 0, height_ = 0;
  cv::Mat vignette_;  // CV_32FC3, empty without vignetting
};

}  // namespace soccer_vision
