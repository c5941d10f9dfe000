#include "soccer_vision/simulation/camera_response.h"

#include <cmath>

#include <opencv2/imgproc.hpp>

namespace soccer_vision {

namespace {

constexpr double kBalancedFor = 5500.0;  // K: the camera's white balance

// Red and blue of a black body at `kelvin` relative to one at kBalancedFor (green = 1): a
// power-law fit of the Planckian locus over 2500-10000 K, good to a few per cent.
cv::Vec3f temperatureGain(double kelvin) {
  if (kelvin <= 0) return {1, 1, 1};
  const double r = std::pow(kBalancedFor / kelvin, 0.55), b = std::pow(kelvin / kBalancedFor, 0.75);
  return {static_cast<float>(b), 1.f, static_cast<float>(r)};
}

}  // namespace

CameraResponse::CameraResponse(const AppearanceConfig& appearance, const SensorConfig&, int width, int height,
                               std::uint64_t seed)
    : config_(appearance), seed_(seed * 0x94D049BB133111EBULL + 11), width_(width), height_(height) {
  const cv::Vec3f t = temperatureGain(config_.color_temperature);
  cv::RNG rng(seed_);
  const double direction = rng.uniform(-M_PI, M_PI);
  const double e = config_.white_balance_error;
  channel_gain_ = {static_cast<float>(config_.gain * t[0] * (1 + e * std::sin(direction))),
                   static_cast<float>(config_.gain * t[1]),
                   static_cast<float>(config_.gain * t[2] * (1 + e * std::cos(direction)))};
  if (config_.vignetting > 0) {
    cv::Mat v(height, width, CV_32F);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) v.at<float>(y, x) = vignette(x, y);
    cv::merge(std::vector<cv::Mat>{v, v, v}, vignette_);
  }
  active_ = config_.color_temperature > 0 || e > 0 || config_.gain != 1 || config_.gamma != 1 ||
            config_.saturation != 1 || config_.vignetting > 0 || config_.lens_blur > 0 ||
            config_.shot_noise > 0;
}

float CameraResponse::vignette(int u, int v) const {
  if (config_.vignetting <= 0) return 1.f;
  // Smooth radial falloff, 1 - V at the corners: (1 - V r^2 / r_corner^2).
  const double cx = (width_ - 1) / 2.0, cy = (height_ - 1) / 2.0;
  const double r2 = ((u - cx) * (u - cx) + (v - cy) * (v - cy)) / (cx * cx + cy * cy);
  return static_cast<float>(1 - config_.vignetting * r2);
}

void CameraResponse::apply(cv::Mat& linear, double global_gain, const cv::Mat& read_noise,
                           std::int64_t frame_index, cv::Mat dst) const {
  // Optics and light on the sensor.
  cv::multiply(linear,
               cv::Scalar(global_gain * channel_gain_[0], global_gain * channel_gain_[1],
                          global_gain * channel_gain_[2]),
               linear);
  if (!vignette_.empty()) cv::multiply(linear, vignette_, linear);
  if (config_.lens_blur > 0) cv::GaussianBlur(linear, linear, cv::Size(), config_.lens_blur);
  // Sensor: shot noise (variance proportional to the signal), read noise.
  if (config_.shot_noise > 0) {
    cv::Mat n(linear.size(), CV_32FC3), level;
    cv::RNG rng(seed_ + static_cast<std::uint64_t>(frame_index) * 0xBF58476D1CE4E5B9ULL);
    rng.fill(n, cv::RNG::NORMAL, 0.0, 1.0);
    cv::threshold(linear, level, 0.0, 0.0, cv::THRESH_TOZERO);
    level *= config_.shot_noise;
    cv::sqrt(level, level);
    linear += n.mul(level);
  }
  if (!read_noise.empty()) linear += read_noise;
  // Processing: saturation about the grey value, then the response curve.
  if (config_.saturation != 1) {
    cv::Mat grey;
    cv::transform(linear, grey, cv::Matx13f(0.114f, 0.587f, 0.299f));
    cv::Mat grey3;
    cv::merge(std::vector<cv::Mat>{grey, grey, grey}, grey3);
    cv::addWeighted(linear, config_.saturation, grey3, 1 - config_.saturation, 0.0, linear);
  }
  if (config_.gamma != 1) {
    cv::threshold(linear, linear, 0.0, 0.0, cv::THRESH_TOZERO);
    linear *= 1.0 / 255;
    cv::pow(linear, config_.gamma, linear);
    linear *= 255.0;
  }
  linear.convertTo(dst, CV_8U);
}

}  // namespace soccer_vision
