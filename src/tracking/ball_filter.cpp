#include "soccer_vision/tracking/ball_filter.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "soccer_vision/tracking/constant_velocity.h"

namespace soccer_vision {
namespace {

void requirePositive(double v, const char* name) {
  if (!(v > 0) || !std::isfinite(v)) {
    throw std::invalid_argument(std::string("ball filter: ") + name + " must be > 0 (got " +
                                std::to_string(v) + ")");
  }
}

}  // namespace

void validate(const BallFilterParams& p) {
  requirePositive(p.accel_noise, "accel_noise");
  requirePositive(p.sigma_xy, "sigma_xy");
  requirePositive(p.init_sigma_v, "init_sigma_v");
  requirePositive(p.kick_sigma_v, "kick_sigma_v");
  requirePositive(p.max_speed, "max_speed");
  requirePositive(p.gate_d2, "gate_d2");
  if (!(p.kick_margin >= 0)) throw std::invalid_argument("ball filter: kick_margin must be >= 0");
  if (!(p.gate_min_distance >= 0)) throw std::invalid_argument("ball filter: gate_min_distance must be >= 0");
  if (!(p.wall_x >= 0 && p.wall_y >= 0 && std::isfinite(p.wall_x) && std::isfinite(p.wall_y)))
    throw std::invalid_argument("ball filter: wall_x and wall_y must be finite and >= 0 (0 = no walls)");
}

BallFilter::BallFilter(const BallFilterParams& params, double x, double y) : p_(params) {
  x_ << x, y, 0, 0;
  P_ = Covariance::Zero();
  P_(0, 0) = P_(1, 1) = p_.sigma_xy * p_.sigma_xy;
  P_(2, 2) = P_(3, 3) = p_.init_sigma_v * p_.init_sigma_v;
  last_measured_ = {x, y};
}

void BallFilter::predicted(double dt, State& x, Covariance& P) const {
  dt = std::max(0.0, dt);
  const auto F = constantVelocityTransition<2>(dt);
  x = F * x_;
  P = F * P_ * F.transpose() +
      constantVelocityProcessNoise<2>(Eigen::Vector2d(p_.accel_noise, p_.accel_noise), dt);
  // Off the walls: position mirrored at the wall, velocity across it reversed (the
  // covariance's terms between that axis and the other change sign with them).
  const double walls[2] = {p_.wall_x, p_.wall_y};
  for (int k = 0; k < 2; ++k) {
    const double w = walls[k];
    if (!(w > 0)) continue;
    bool reflected = false;
    // Bounced back and forth at most a few times in one prediction; beyond, left where it is.
    for (int bounce = 0; bounce < 4 && std::abs(x(k)) > w; ++bounce) {
      x(k) = (x(k) > 0 ? 1.0 : -1.0) * (2 * w - std::abs(x(k)));
      x(k + 2) = -x(k + 2);
      reflected = !reflected;
    }
    if (reflected) {
      Eigen::Matrix4d J = Eigen::Matrix4d::Identity();
      J(k, k) = J(k + 2, k + 2) = -1;
      P = J * P * J.transpose();
    }
  }
}

void BallFilter::predict(double dt) {
  if (!(dt > 0)) return;
  State x;
  Covariance P;
  predicted(dt, x, P);
  x_ = x;
  P_ = P;
}

void BallFilter::observation(double lag, Eigen::Matrix<double, 2, 4>& H, Eigen::Matrix2d& R) const {
  lag = std::max(0.0, lag);
  H = laggedPositionObservation<2>(lag);
  const Eigen::Vector2d variance = Eigen::Vector2d::Constant(p_.sigma_xy * p_.sigma_xy) +
                                   lagNoiseVariance<2>(Eigen::Vector2d::Constant(p_.accel_noise), lag);
  R = variance.asDiagonal();
}

double BallFilter::distance2(double x, double y, double lag) const {
  const Eigen::Vector2d innovation(x - x_(0), y - x_(1));
  Eigen::Matrix<double, 2, 4> H;
  Eigen::Matrix2d R;
  observation(lag, H, R);
  const Eigen::Matrix2d S = H * P_ * H.transpose() + R;
  return innovation.dot(S.ldlt().solve(innovation));
}

BallGate BallFilter::classify(double x, double y, double time_since_update, double lag) const {
  // Nothing farther than a ball kicked right after the last measurement can be this ball,
  // however uncertain a coasting filter has become.
  const double jump = std::hypot(x - last_measured_.x(), y - last_measured_.y());
  const double reach = p_.max_speed * std::max(0.0, time_since_update) + p_.kick_margin;
  if (jump > reach) return BallGate::Rejected;
  const double distance = std::hypot(x - x_(0), y - x_(1));
  if (distance <= p_.gate_min_distance || distance2(x, y, lag) <= p_.gate_d2) return BallGate::Accepted;
  return BallGate::Kick;
}

BallGate BallFilter::update(double x, double y, double time_since_update, double lag) {
  const BallGate gate = classify(x, y, time_since_update, lag);
  if (gate == BallGate::Accepted) {
    const Eigen::Vector2d innovation(x - x_(0), y - x_(1));
    Eigen::Matrix<double, 2, 4> H;
    Eigen::Matrix2d R;
    observation(lag, H, R);
    const Eigen::Matrix2d S = H * P_ * H.transpose() + R;
    const Eigen::Matrix<double, 4, 2> K = P_ * H.transpose() * S.inverse();
    x_ += K * innovation;
    const Covariance I_KH = Covariance::Identity() - K * H;
    P_ = I_KH * P_ * I_KH.transpose() + K * R * K.transpose();
  } else if (gate == BallGate::Kick) {
    // Restart at the measurement; velocity from the jump (the kick happened somewhere in
    // between, so this underestimates it: hence the broad variance).
    Eigen::Vector2d v(0, 0);
    if (time_since_update > 0) v = (Eigen::Vector2d(x, y) - last_measured_) / time_since_update;
    if (v.norm() > p_.max_speed) v *= p_.max_speed / v.norm();
    x_ << x, y, v.x(), v.y();
    P_ = Covariance::Zero();
    P_(0, 0) = P_(1, 1) = p_.sigma_xy * p_.sigma_xy;
    P_(2, 2) = P_(3, 3) = p_.kick_sigma_v * p_.kick_sigma_v;
  } else {
    return gate;
  }
  last_measured_ = {x, y};
  return gate;
}

}  // namespace soccer_vision
