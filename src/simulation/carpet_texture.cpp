#include "soccer_vision/simulation/carpet_texture.h"

#include <algorithm>
#include <cmath>

#include <opencv2/core.hpp>

namespace soccer_vision {

namespace {

constexpr double kFibre = 0.003;      // m, side of one fibre cell
constexpr double kStripeWidth = 0.5;  // m
constexpr double kStripeEdge = 0.05;  // m, the soft transition between two stripes
constexpr int kPatches = 24;

// Uniform in [-1, 1) from a cell index and the seed (splitmix64).
double cellNoise(std::int64_t i, std::int64_t j, std::uint64_t seed) {
  std::uint64_t z = seed + static_cast<std::uint64_t>(i) * 0x9E3779B97F4A7C15ULL +
                    static_cast<std::uint64_t>(j) * 0xC2B2AE3D27D4EB4FULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) / static_cast<double>(1ULL << 52) - 1.0;
}

}  // namespace

CarpetTexture::CarpetTexture(const AppearanceConfig& config, std::uint64_t seed)
    : fibre_(config.carpet_fibre),
      patches_(config.carpet_patches),
      stripes_(config.mowing_stripes),
      seed_(seed * 0xD6E8FEB86659FD93ULL + 3) {
  cv::RNG rng(seed_);
  for (int k = 0; k < kPatches && patches_ > 0; ++k)
    patch_list_.push_back({rng.uniform(-6.5, 6.5), rng.uniform(-5.0, 5.0), rng.uniform(0.25, 1.0),
                           rng.uniform(0, 2) == 0 ? -1.0 : 1.0});
}

double CarpetTexture::shade(double x, double y) const {
  double s = 1;
  if (fibre_ > 0) {
    // Uniform [-1, 1) has std-dev 1 / sqrt(3).
    s *= 1 + fibre_ * std::sqrt(3.0) *
                 cellNoise(static_cast<std::int64_t>(std::floor(x / kFibre)),
                           static_cast<std::int64_t>(std::floor(y / kFibre)), seed_);
  }
  if (patches_ > 0) {
    double p = 0;
    for (const Patch& q : patch_list_) {
      const double r2 = (x - q.x) * (x - q.x) + (y - q.y) * (y - q.y);
      p += q.sign * std::exp(-r2 / (2 * q.sigma * q.sigma));
    }
    s *= 1 + patches_ * std::clamp(p, -1.0, 1.0);
  }
  if (stripes_ > 0) {
    // Alternating stripes across x, with soft edges: +-stripes_.
    const double phase = std::sin(M_PI * x / kStripeWidth);
    s *= 1 + stripes_ * std::clamp(phase * kStripeWidth / (M_PI * kStripeEdge), -1.0, 1.0);
  }
  return s;
}

}  // namespace soccer_vision
