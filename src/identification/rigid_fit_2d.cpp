#include "soccer_vision/identification/rigid_fit_2d.h"

#include <cmath>
#include <stdexcept>

#include "soccer_vision/common/angle.h"

namespace soccer_vision {

Eigen::Vector2d Pose2d::apply(const Eigen::Vector2d& local) const {
  const double c = std::cos(theta), s = std::sin(theta);
  return {x + c * local.x() - s * local.y(), y + s * local.x() + c * local.y()};
}

Pose2d fitRigid2d(const std::vector<Eigen::Vector2d>& model, const std::vector<Eigen::Vector2d>& observed,
                  const std::vector<double>& weights, const std::optional<HeadingPrior>& prior) {
  if (model.empty() || model.size() != observed.size() || model.size() != weights.size()) {
    throw std::invalid_argument("fitRigid2d: need as many model points, observed points and weights (>= 1)");
  }
  double wsum = 0;
  Eigen::Vector2d mm = Eigen::Vector2d::Zero(), mo = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < model.size(); ++i) {
    wsum += weights[i];
    mm += weights[i] * model[i];
    mo += weights[i] * observed[i];
  }
  mm /= wsum;
  mo /= wsum;
  // arg of sum w conj(a) b with a, b the centred points (as complex numbers).
  double re = 0, im = 0;
  for (std::size_t i = 0; i < model.size(); ++i) {
    const Eigen::Vector2d a = model[i] - mm, b = observed[i] - mo;
    re += weights[i] * (a.x() * b.x() + a.y() * b.y());
    im += weights[i] * (a.x() * b.y() - a.y() * b.x());
  }
  const double norm = std::hypot(re, im);
  double theta = 0;
  if (norm > 1e-18) {
    theta = std::atan2(im, re);
    if (prior && prior->weight > 0) {
      const double w = std::min(prior->weight, 1.0);
      const double c = (1 - w) * std::cos(theta) + w * std::cos(prior->theta);
      const double s = (1 - w) * std::sin(theta) + w * std::sin(prior->theta);
      theta = std::atan2(s, c);
    }
  } else if (prior) {
    theta = prior->theta;
  }
  Pose2d p;
  p.theta = wrapToPi(theta);
  const double c = std::cos(p.theta), s = std::sin(p.theta);
  p.x = mo.x() - (c * mm.x() - s * mm.y());
  p.y = mo.y() - (s * mm.x() + c * mm.y());
  return p;
}

}  // namespace soccer_vision
