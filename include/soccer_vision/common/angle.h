// Angles in (-pi, pi]: the convention of RobotPose.theta and of every filter state.
#pragma once

#include <cmath>

namespace soccer_vision {

inline double wrapToPi(double a) {
  if (!std::isfinite(a)) return a;
  a = std::remainder(a, 2.0 * M_PI);  // [-pi, pi]
  return a <= -M_PI ? a + 2.0 * M_PI : a;
}

// a - b wrapped to (-pi, pi]: the signed turn from b to a.
inline double angleDifference(double a, double b) { return wrapToPi(a - b); }

}  // namespace soccer_vision
