// Weighted least-squares rigid motion (rotation + translation, no scale) in the plane that
// maps pattern points (robot frame) onto observed points (field frame): the closed-form
// 2-D Procrustes solution, optionally pulled towards a heading measured another way (the
// team tag's axis).
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

namespace soccer_vision {

struct Pose2d {
  double x = 0, y = 0, theta = 0;
  Eigen::Vector2d apply(const Eigen::Vector2d& local) const;  // robot frame -> field
};

struct HeadingPrior {
  double theta = 0;   // rad
  double weight = 0;  // 0..1: share of the prior in the heading (circular weighted mean)
};

// model.size() == observed.size() == weights.size() >= 1; with one point (or points that
// coincide) the heading is the prior's (0 without one). Translation is then the weighted
// least-squares one for that heading.
Pose2d fitRigid2d(const std::vector<Eigen::Vector2d>& model, const std::vector<Eigen::Vector2d>& observed,
                  const std::vector<double>& weights,
                  const std::optional<HeadingPrior>& prior = std::nullopt);

}  // namespace soccer_vision
