#include "soccer_vision/simulation/ball_light.h"

#include <algorithm>
#include <cmath>

namespace soccer_vision {

BallLight::BallLight(const LampSet& lamps, const std::vector<double>& intensity,
                     const Eigen::Vector3d& ball) {
  double top = 0;  // irradiance on a horizontal surface: sum of I / d^2 x cos(incidence)
  for (std::size_t k = 0; k < lamps.size(); ++k) {
    const Lamp& lamp = lamps.lamp(k);
    const Eigen::Vector3d to_lamp = Eigen::Vector3d(lamp.x, lamp.y, lamp.z) - ball;
    const double d2 = to_lamp.squaredNorm();
    if (!(d2 > 0)) continue;
    const double i = k < intensity.size() ? intensity[k] : 1.0;
    directions_.push_back(to_lamp / std::sqrt(d2));
    weights_.push_back(i / d2);
    top += weights_.back() * std::max(0.0, directions_.back().z());
  }
  if (!(top > 0)) {  // no lamps (or none above): the smooth light model's light from above
    directions_.assign(1, Eigen::Vector3d::UnitZ());
    weights_.assign(1, 1.0);
    return;
  }
  for (double& w : weights_) w /= top;
}

double BallLight::diffuse(const Eigen::Vector3d& normal) const {
  double facing = 0;
  for (std::size_t k = 0; k < directions_.size(); ++k)
    facing += weights_[k] * std::max(0.0, normal.dot(directions_[k]));
  return kIndirect + (1 - kIndirect) * facing;
}

double BallLight::specular(const Eigen::Vector3d& normal, const Eigen::Vector3d& to_viewer,
                           double shininess) const {
  double sum = 0;
  for (std::size_t k = 0; k < directions_.size(); ++k) {
    const Eigen::Vector3d half = (directions_[k] + to_viewer).normalized();
    sum += weights_[k] * std::pow(std::max(0.0, normal.dot(half)), shininess);
  }
  return sum;
}

}  // namespace soccer_vision
