// Constant-velocity motion with continuous white-noise acceleration, for a state laid out
// as [p_1 .. p_N, v_1 .. v_N] (N axes). Shared by the robot and the ball filter.
#pragma once

#include <Eigen/Core>

namespace soccer_vision {

// Transition F(dt): p += v * dt.
template <int N>
Eigen::Matrix<double, 2 * N, 2 * N> constantVelocityTransition(double dt) {
  Eigen::Matrix<double, 2 * N, 2 * N> F = Eigen::Matrix<double, 2 * N, 2 * N>::Identity();
  F.template topRightCorner<N, N>() = dt * Eigen::Matrix<double, N, N>::Identity();
  return F;
}

// Process noise Q(dt) for densities q_i = accel_noise_i² per axis:
// q * [dt³/3, dt²/2; dt²/2, dt]. Exact for any split of dt into steps.
template <int N>
Eigen::Matrix<double, 2 * N, 2 * N> constantVelocityProcessNoise(
    const Eigen::Matrix<double, N, 1>& accel_noise, double dt) {
  Eigen::Matrix<double, 2 * N, 2 * N> Q = Eigen::Matrix<double, 2 * N, 2 * N>::Zero();
  for (int i = 0; i < N; ++i) {
    const double q = accel_noise(i) * accel_noise(i);
    Q(i, i) = q * dt * dt * dt / 3.0;
    Q(i, N + i) = Q(N + i, i) = q * dt * dt / 2.0;
    Q(N + i, N + i) = q * dt;
  }
  return Q;
}

}  // namespace soccer_vision
