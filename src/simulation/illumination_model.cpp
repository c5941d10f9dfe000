#include <algorithm>
#include <cmath>
#include <vector>

#include "soccer_vision/simulation/field_renderer.h"

namespace soccer_vision {

namespace {

constexpr double kGridStep = 0.05;  // m: sampling of the carpet for min/max/mean

// Independent cv::RNG streams (OpenCV's generator: same numbers on every platform).
cv::RNG streamFor(std::uint64_t seed, std::uint64_t purpose) {
  return cv::RNG(seed * 0x9E3779B97F4A7C15ULL + purpose * 0xD1B54A32D192ED03ULL + 1);
}

}  // namespace

IlluminationModel::IlluminationModel(const LightingConfig& config, const FieldGeometry& field,
                                     std::uint64_t seed)
    : config_(config), seed_(seed) {
  const double hx = field.carpetHalfLength();
  const double hy = field.carpetHalfWidth();

  cv::RNG rng = streamFor(seed, 1);
  const double gradient_angle = rng.uniform(-M_PI, M_PI);
  const double gradient_strength = rng.uniform(0.2, 0.6);  // over a half carpet
  a_ = gradient_strength * std::cos(gradient_angle) / hx;
  b_ = gradient_strength * std::sin(gradient_angle) / hy;
  spot_x_ = rng.uniform(-0.8, 0.8) * hx;
  spot_y_ = rng.uniform(-0.8, 0.8) * hy;
  spot_sigma_ = rng.uniform(1.2, 2.5);
  spot_weight_ = rng.uniform(0.5, 1.2);
  drift_phase_ = rng.uniform(0.0, 2 * M_PI);

  // The grid includes the carpet's edges and corners, where the plane has its extremes.
  const int nx = static_cast<int>(std::ceil(2 * hx / kGridStep));
  const int ny = static_cast<int>(std::ceil(2 * hy / kGridStep));
  std::vector<double> samples;
  for (int i = 0; i <= nx; ++i)
    for (int j = 0; j <= ny; ++j) samples.push_back(shape(-hx + 2 * hx * i / nx, -hy + 2 * hy * j / ny));
  const auto [lo, hi] = std::minmax_element(samples.begin(), samples.end());
  shape_min_ = *lo;
  shape_range_ = *hi - *lo;

  double sum = 0;
  for (double s : samples) sum += std::pow(config_.uneven_ratio, (s - shape_min_) / shape_range_);
  norm_ = config_.brightness * static_cast<double>(samples.size()) / sum;
}

double IlluminationModel::shape(double x, double y) const {
  const double r2 = (x - spot_x_) * (x - spot_x_) + (y - spot_y_) * (y - spot_y_);
  return 1 + a_ * x + b_ * y + spot_weight_ * std::exp(-r2 / (2 * spot_sigma_ * spot_sigma_));
}

double IlluminationModel::spatialGain(double x, double y) const {
  // Clamped to the grid's range, so the extremes between grid points cannot exceed it.
  const double s = std::clamp((shape(x, y) - shape_min_) / shape_range_, 0.0, 1.0);
  return norm_ * std::pow(config_.uneven_ratio, s);
}

double IlluminationModel::globalGain(double t, std::int64_t frame_index) const {
  double gain = 1;
  if (config_.drift_amplitude != 0 && config_.drift_period > 0)
    gain *= 1 + config_.drift_amplitude * std::sin(2 * M_PI * t / config_.drift_period + drift_phase_);
  if (config_.flicker != 0) {
    cv::RNG rng = streamFor(seed_, 2 + static_cast<std::uint64_t>(frame_index));
    gain *= 1 + config_.flicker * rng.gaussian(1.0);
  }
  return std::max(0.0, gain);
}

}  // namespace soccer_vision
