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

// Observation of the positions of a measurement taken `lag` >= 0 seconds before the filter's
// time (a camera's frame fused late): p(t - lag) = p(t) - v(t) * lag, so H = [I, -lag * I].
// The tracker moves the measured positions forward along the estimated velocity first, so
// the innovation is the plain difference; H carries the velocity's uncertainty into the
// innovation covariance and the gain. lag = 0 is the usual [I, 0].
template <int N>
Eigen::Matrix<double, N, 2 * N> laggedPositionObservation(double lag) {
  Eigen::Matrix<double, N, 2 * N> H = Eigen::Matrix<double, N, 2 * N>::Zero();
  H.template leftCols<N>().setIdentity();
  H.template rightCols<N>() = -lag * Eigen::Matrix<double, N, N>::Identity();
  return H;
}

// The accelerations over that lag, which moving forward along the velocity cannot know:
// q * lag³ / 3 per axis, added to the measurement noise.
template <int N>
Eigen::Matrix<double, N, 1> lagNoiseVariance(const Eigen::Matrix<double, N, 1>& accel_noise, double lag) {
  return accel_noise.cwiseProduct(accel_noise) * (lag * lag * lag / 3.0);
}

}  // namespace soccer_vision
