// The carpet's own look, fixed to the field: fibre noise (3 mm fibres), worn or dirty
// patches (0.5-2 m) and mowing stripes (0.5 m wide, along the length), as a relative shade
// around 1. Patch positions and signs are drawn from the seed.
#pragma once

#include <cstdint>
#include <vector>

#include "soccer_vision/simulation/scenario.h"

namespace soccer_vision {

class CarpetTexture {
 public:
  CarpetTexture(const AppearanceConfig& config, std::uint64_t seed);
  bool active() const { return fibre_ > 0 || patches_ > 0 || stripes_ > 0; }
  // Relative shade of the carpet at a field point (1 without texture).
  double shade(double x, double y) const;

 private:
  struct Patch {
    double x, y, sigma, sign;
  };
  double fibre_, patches_, stripes_;
  std::uint64_t seed_;
  std::vector<Patch> patch_list_;
};

}  // namespace soccer_vision
