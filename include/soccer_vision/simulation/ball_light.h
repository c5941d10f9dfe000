// How the lamps light the ball, a sphere: Lambertian shading with the hall's indirect light,
// and a Blinn-Phong highlight, both relative to the light a horizontal surface at the
// ball's top receives, so that the carpet's spatial gain still sets the ball's level. A
// real ball seen from above is brightest and palest where it mirrors the lamps and darker
// towards its rim (the 2008 SSL frame's ball: a pale centre in a darker orange ring), not
// the evenly lit disc the renderer drew before. Without lamps, one light straight above.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "soccer_vision/simulation/lamps.h"

namespace soccer_vision {

class BallLight {
 public:
  // The lights as seen from the ball centre `ball` [m, field], lamp k at intensity[k] (its
  // drift; empty: every lamp at 1).
  BallLight(const LampSet& lamps, const std::vector<double>& intensity, const Eigen::Vector3d& ball);

  // Light on the sphere where its outward unit normal is `normal`, relative to its top:
  // kIndirect + (1 - kIndirect) x the lamps' share the normal faces (1 at the top under a
  // lamp straight above).
  double diffuse(const Eigen::Vector3d& normal) const;
  // The highlight towards a viewer in unit direction `to_viewer` [relative to the top's
  // diffuse light], sum over lamps of (n . h)^shininess.
  double specular(const Eigen::Vector3d& normal, const Eigen::Vector3d& to_viewer, double shininess) const;

  // Share of the light a surface gets indirectly (walls, ceiling, carpet), whatever it faces.
  static constexpr double kIndirect = 0.3;

 private:
  std::vector<Eigen::Vector3d> directions_;  // unit, from the ball towards each light
  std::vector<double> weights_;              // each light's irradiance on the top, summing to 1
};

}  // namespace soccer_vision
