#include "soccer_vision/tracking/robot_filter.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>

#include "soccer_vision/common/angle.h"
#include "soccer_vision/tracking/constant_velocity.h"

namespace soccer_vision {
namespace {

void requirePositive(double v, const char* name) {
  if (!(v > 0) || !std::isfinite(v)) {
    throw std::invalid_argument(std::string("robot filter: ") + name + " must be > 0 (got " +
                                std::to_string(v) + ")");
  }
}

// Heading std-dev of a track started without a heading: any direction.
constexpr double kUnknownHeadingSigma = M_PI;
// Largest heading innovation ever taken as a turn manoeuvre: a pattern read the wrong way
// round is pi off, and must stay an outlier however long the robot was not seen.
constexpr double kMaxManeuverTurn = M_PI / 2;

}  // namespace

void validate(const RobotFilterParams& p) {
  requirePositive(p.accel_noise_xy, "accel_noise_xy");
  requirePositive(p.accel_noise_theta, "accel_noise_theta");
  requirePositive(p.sigma_x, "sigma_x");
  requirePositive(p.sigma_y, "sigma_y");
  requirePositive(p.sigma_theta, "sigma_theta");
  requirePositive(p.init_sigma_v, "init_sigma_v");
  requirePositive(p.init_sigma_omega, "init_sigma_omega");
  requirePositive(p.gate_position_d2, "gate_position_d2");
  requirePositive(p.gate_heading_d2, "gate_heading_d2");
  if (!(p.gate_min_distance >= 0))
    throw std::invalid_argument("robot filter: gate_min_distance must be >= 0");
  if (!(p.gate_min_angle >= 0)) throw std::invalid_argument("robot filter: gate_min_angle must be >= 0");
  if (!(p.maneuver_speed_change >= 0) || !std::isfinite(p.maneuver_speed_change)) {
    throw std::invalid_argument("robot filter: maneuver_speed_change must be >= 0");
  }
  if (!(p.maneuver_omega_change >= 0) || !std::isfinite(p.maneuver_omega_change)) {
    throw std::invalid_argument("robot filter: maneuver_omega_change must be >= 0");
  }
  if (p.reinit_after_rejections < 1) {
    throw std::invalid_argument("robot filter: reinit_after_rejections must be >= 1");
  }
}

RobotFilter::RobotFilter(const RobotFilterParams& params, const RobotMeasurement& m) : p_(params) {
  start(m);
}

void RobotFilter::start(const RobotMeasurement& m) {
  x_ = State::Zero();
  x_(0) = m.x;
  x_(1) = m.y;
  P_ = Covariance::Zero();
  P_(0, 0) = p_.sigma_x * p_.sigma_x;
  P_(1, 1) = p_.sigma_y * p_.sigma_y;
  P_(3, 3) = P_(4, 4) = p_.init_sigma_v * p_.init_sigma_v;
  startHeading(m.heading_valid ? m.theta : 0.0);
  if (!m.heading_valid) P_(2, 2) = kUnknownHeadingSigma * kUnknownHeadingSigma;
  rejections_ = 0;
  heading_rejections_ = 0;
  since_update_ = 0;
  unturned_.reset();
}

void RobotFilter::startHeading(double theta) {
  x_(2) = wrapToPi(theta);
  x_(5) = 0;
  since_heading_ = 0;
  P_.row(2).setZero();
  P_.col(2).setZero();
  P_.row(5).setZero();
  P_.col(5).setZero();
  P_(2, 2) = p_.sigma_theta * p_.sigma_theta;
  P_(5, 5) = p_.init_sigma_omega * p_.init_sigma_omega;
  unturned_.reset();
}

void RobotFilter::propagate(double dt, const State& x0, const Covariance& P0, State& x, Covariance& P) const {
  dt = std::max(0.0, dt);
  const auto F = constantVelocityTransition<3>(dt);
  const Eigen::Vector3d noise(p_.accel_noise_xy, p_.accel_noise_xy, p_.accel_noise_theta);
  x = F * x0;  // the products go through temporaries: x may be x0, P may be P0
  x(2) = wrapToPi(x(2));
  P = F * P0 * F.transpose() + constantVelocityProcessNoise<3>(noise, dt);
}

void RobotFilter::predicted(double dt, State& x, Covariance& P) const { propagate(dt, x_, P_, x, P); }

void RobotFilter::predict(double dt) {
  if (!(dt > 0)) return;
  State x;
  Covariance P;
  predicted(dt, x, P);
  x_ = x;
  P_ = P;
  since_update_ += dt;
  since_heading_ += dt;
  if (unturned_) {
    propagate(dt, unturned_->x, unturned_->P, unturned_->x, unturned_->P);
    unturned_->since_heading += dt;
  }
}

bool RobotFilter::headingInGate(const State& x, const Covariance& P, double theta, double lag) const {
  const double dtheta = wrapToPi(theta - x(2));
  const Observation o = observation(lag);
  const double s = (o.H.row(2) * P * o.H.row(2).transpose()).value() + o.variance(2);
  return std::abs(dtheta) <= p_.gate_min_angle || dtheta * dtheta / s <= p_.gate_heading_d2;
}

RobotFilter::Observation RobotFilter::observation(double lag) const {
  lag = std::max(0.0, lag);
  const Eigen::Vector3d noise(p_.accel_noise_xy, p_.accel_noise_xy, p_.accel_noise_theta);
  const Eigen::Vector3d sigma(p_.sigma_x, p_.sigma_y, p_.sigma_theta);
  return {laggedPositionObservation<3>(lag), sigma.cwiseProduct(sigma) + lagNoiseVariance<3>(noise, lag)};
}

double RobotFilter::positionDistance2(double x, double y, double lag) const {
  const Eigen::Vector2d innovation(x - x_(0), y - x_(1));
  const Observation o = observation(lag);
  const Eigen::Matrix<double, 2, 6> H = o.H.topRows<2>();
  const Eigen::Matrix2d S = H * P_ * H.transpose() + Eigen::Matrix2d(o.variance.head<2>().asDiagonal());
  return innovation.dot(S.ldlt().solve(innovation));
}

template <int Rows>
void RobotFilter::applyUpdate(const Eigen::Matrix<double, Rows, 1>& innovation, const Observation& o) {
  using RowsMatrix = Eigen::Matrix<double, Rows, Rows>;
  const Eigen::Matrix<double, Rows, 6> H = o.H.topRows<Rows>();
  const RowsMatrix R = o.variance.head<Rows>().asDiagonal();
  const RowsMatrix S = H * P_ * H.transpose() + R;
  const Eigen::Matrix<double, 6, Rows> K = P_ * H.transpose() * S.ldlt().solve(RowsMatrix::Identity());
  x_ += K * innovation;
  x_(2) = wrapToPi(x_(2));
  // Joseph form: stays symmetric positive definite over thousands of updates.
  const Covariance I_KH = Covariance::Identity() - K * H;
  P_ = I_KH * P_ * I_KH.transpose() + K * R * K.transpose();
}

GateResult RobotFilter::update(const RobotMeasurement& m) {
  double dx = m.x - x_(0), dy = m.y - x_(1);
  const double distance = std::hypot(dx, dy);
  bool position_ok =
      distance <= p_.gate_min_distance || positionDistance2(m.x, m.y, m.lag) <= p_.gate_position_d2;
  const bool maneuver = !position_ok && !m.unsure && p_.maneuver_speed_change > 0 &&
                        distance <= p_.maneuver_speed_change * since_update_ + p_.gate_min_distance;
  if (maneuver) {
    // A velocity jump dv at the last update moves the position by dv * t since then.
    const double var = 0.25 * p_.maneuver_speed_change * p_.maneuver_speed_change;
    const double t = since_update_;
    for (int i = 0; i < 2; ++i) {
      P_(i, i) += var * t * t;
      P_(i, i + 3) += var * t;
      P_(i + 3, i) += var * t;
      P_(i + 3, i + 3) += var;
    }
    position_ok = true;
  }
  if (!position_ok) {
    if (++rejections_ >= p_.reinit_after_rejections) {
      start(m);
      return GateResult::Reinitialised;
    }
    return GateResult::Rejected;
  }
  rejections_ = 0;
  since_update_ = 0;

  bool use_heading = false;
  bool heading_maneuver = false;
  bool undone = false;
  if (m.heading_valid) {
    use_heading = headingInGate(x_, P_, m.theta, m.lag);
    if (!use_heading && unturned_ && headingInGate(unturned_->x, unturned_->P, m.theta, m.lag)) {
      // The last manoeuvre's heading was a misread: back to the state that did not use it.
      x_ = unturned_->x;
      P_ = unturned_->P;
      since_heading_ = unturned_->since_heading;
      dx = m.x - x_(0);
      dy = m.y - x_(1);
      use_heading = undone = true;
    }
    unturned_.reset();  // decided by this heading
    const double dtheta = wrapToPi(m.theta - x_(2));
    heading_maneuver =
        !use_heading && !m.unsure && p_.maneuver_omega_change > 0 &&
        std::abs(dtheta) <=
            std::min(kMaxManeuverTurn, p_.maneuver_omega_change * since_heading_ + p_.gate_min_angle);
    if (heading_maneuver) {
      // On probation: the state in which this heading is a misread, its position used.
      const State x = x_;
      const Covariance P = P_;
      applyUpdate<2>(Eigen::Vector2d(dx, dy), observation(m.lag));
      unturned_ = Unturned{x_, P_, since_heading_};
      x_ = x;
      P_ = P;
      // An angular-velocity jump dω at the last heading update turns the robot by dω * t since.
      const double var = 0.25 * p_.maneuver_omega_change * p_.maneuver_omega_change;
      const double t = since_heading_;
      P_(2, 2) += var * t * t;
      P_(2, 5) += var * t;
      P_(5, 2) += var * t;
      P_(5, 5) += var;
      use_heading = true;
    }
    if (!use_heading && ++heading_rejections_ >= p_.reinit_after_rejections) {
      startHeading(m.theta);  // the heading really changed (or the track began without one)
      heading_rejections_ = 0;
      use_heading = false;  // just set from this measurement; update the position below
    } else if (use_heading) {
      heading_rejections_ = 0;
    }
  }

  const Observation o = observation(m.lag);
  if (use_heading) {
    since_heading_ = 0;
    applyUpdate<3>(Eigen::Vector3d(dx, dy, wrapToPi(m.theta - x_(2))), o);
  } else {
    applyUpdate<2>(Eigen::Vector2d(dx, dy), o);
  }
  if (maneuver) return GateResult::Maneuver;
  if (undone) return GateResult::ManeuverUndone;
  if (heading_maneuver) return GateResult::HeadingManeuver;
  return (m.heading_valid && !use_heading) ? GateResult::HeadingRejected : GateResult::Accepted;
}

}  // namespace soccer_vision
