#include "soccer_vision/simulation/lamps.h"

#include <cmath>

#include <opencv2/core.hpp>

namespace soccer_vision {

namespace {
constexpr double kGridStep = 0.1;  // m: carpet sampling for the normalisation
}

LampSet::LampSet(const AppearanceConfig& config, const FieldGeometry& field, std::uint64_t seed)
    : drift_(config.lamp_drift) {
  if (config.lamps <= 0) return;
  const double hx = field.carpetHalfLength(), hy = field.carpetHalfWidth();
  cv::RNG rng(seed * 0x9E3779B97F4A7C15ULL + 0xA24BAED4963EE407ULL);
  for (int k = 0; k < config.lamps; ++k) {
    Lamp l;
    l.x = rng.uniform(-0.9, 0.9) * hx;
    l.y = rng.uniform(-0.9, 0.9) * hy;
    l.z = config.lamp_height * rng.uniform(0.9, 1.1);
    l.period = rng.uniform(6.0, 20.0);
    l.phase = rng.uniform(0.0, 2 * M_PI);
    lamps_.push_back(l);
  }
  double sum = 0;
  int n = 0;
  for (double x = -hx; x <= hx; x += kGridStep)
    for (double y = -hy; y <= hy; y += kGridStep, ++n)
      for (std::size_t k = 0; k < lamps_.size(); ++k) sum += irradiance(k, x, y);
  norm_ = n / sum;
}

double LampSet::irradiance(std::size_t k, double x, double y) const {
  const Lamp& l = lamps_[k];
  const double d2 = (x - l.x) * (x - l.x) + (y - l.y) * (y - l.y) + l.z * l.z;
  return norm_ * l.z / (d2 * std::sqrt(d2));
}

double LampSet::drift(std::size_t k, double t) const {
  const Lamp& l = lamps_[k];
  return 1 + drift_ * std::sin(2 * M_PI * t / l.period + l.phase);
}

Eigen::Vector2d LampSet::shadowTip(std::size_t k, double x, double y, double h) const {
  const Lamp& l = lamps_[k];
  const double s = l.z / (l.z - h);  // the ray lamp -> top, continued down to z = 0
  return {l.x + (x - l.x) * s, l.y + (y - l.y) * s};
}

}  // namespace soccer_vision
