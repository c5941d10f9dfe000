// Point lamps over the field: inverse-square falloff with the cosine of incidence
// (irradiance ~ H / d^3 on the carpet), each drifting slowly on its own, and the soft
// shadows robots cast from them. Positions, periods and phases are drawn from the seed.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/simulation/scenario.h"

namespace soccer_vision {

struct Lamp {
  double x = 0, y = 0, z = 6.0;  // m, in `field`
  double period = 10.0;          // s, of its drift
  double phase = 0.0;            // rad
};

class LampSet {
 public:
  LampSet(const AppearanceConfig& config, const FieldGeometry& field, std::uint64_t seed);

  bool empty() const { return lamps_.empty(); }
  std::size_t size() const { return lamps_.size(); }
  const Lamp& lamp(std::size_t k) const { return lamps_[k]; }

  // Irradiance of lamp k at a carpet point, scaled so that the sum over all lamps has mean
  // 1 over the carpet (without drift).
  double irradiance(std::size_t k, double x, double y) const;
  // Lamp k's relative intensity at time t: 1 + drift sin(2 pi t / period + phase).
  double drift(std::size_t k, double t) const;
  // Where the shadow of a cylinder's top centre (at height h above (x, y)) falls on the
  // carpet from lamp k: the shadow is the capsule from (x, y) to there, of the cylinder's radius.
  Eigen::Vector2d shadowTip(std::size_t k, double x, double y, double h) const;

 private:
  std::vector<Lamp> lamps_;
  double drift_ = 0, norm_ = 1;
};

}  // namespace soccer_vision
