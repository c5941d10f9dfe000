#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "soccer_vision/common/angle.h"
#include "soccer_vision/tracking/robot_filter.h"

using namespace soccer_vision;

namespace {

constexpr double kDt = 1.0 / 60;

}  // namespace

TEST(RobotFilter, ConstantVelocityTargetConverges) {
  RobotFilterParams p;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise_xy(0.0, p.sigma_x), noise_theta(0.0, p.sigma_theta);
  const double vx = 1.5, vy = -0.8, omega = 1.0;
  auto truth = [&](int k) {
    const double t = k * kDt;
    return Eigen::Vector3d(-1.0 + vx * t, 0.5 + vy * t, wrapToPi(0.3 + omega * t));
  };
  RobotFilter f(
      p, {truth(0).x() + noise_xy(rng), truth(0).y() + noise_xy(rng), truth(0).z() + noise_theta(rng), true});
  double filter_sq = 0, measurement_sq = 0, theta_sq = 0, v_sq = 0, omega_sq = 0;
  int n = 0;
  for (int k = 1; k <= 300; ++k) {
    f.predict(kDt);
    const Eigen::Vector3d g = truth(k);
    const RobotMeasurement m{g.x() + noise_xy(rng), g.y() + noise_xy(rng), wrapToPi(g.z() + noise_theta(rng)),
                             true};
    ASSERT_EQ(f.update(m), GateResult::Accepted) << "frame " << k;
    if (k >= 60) {  // after one second
      filter_sq += std::pow(f.state()(0) - g.x(), 2) + std::pow(f.state()(1) - g.y(), 2);
      measurement_sq += std::pow(m.x - g.x(), 2) + std::pow(m.y - g.y(), 2);
      theta_sq += std::pow(wrapToPi(f.state()(2) - g.z()), 2);
      v_sq += std::pow(f.state()(3) - vx, 2) + std::pow(f.state()(4) - vy, 2);
      omega_sq += std::pow(f.state()(5) - omega, 2);
      ++n;
    }
  }
  const double rmse = std::sqrt(filter_sq / n), measurement_rmse = std::sqrt(measurement_sq / n);
  const double theta_rmse = std::sqrt(theta_sq / n), v_rmse = std::sqrt(v_sq / n),
               omega_rmse = std::sqrt(omega_sq / n);
  std::printf(
      "robot CV (defaults): position RMSE %.2f mm (measurements %.2f mm), heading RMSE "
      "%.4f rad (measurements %.3f), velocity RMSE %.3f m/s, omega RMSE %.3f rad/s\n",
      1e3 * rmse, 1e3 * measurement_rmse, theta_rmse, p.sigma_theta, v_rmse, omega_rmse);
  EXPECT_LT(rmse, 0.85 * measurement_rmse);
  EXPECT_LT(theta_rmse, 0.8 * p.sigma_theta);
  EXPECT_LT(v_rmse, 0.2);  // of 1.7 m/s
  EXPECT_LT(omega_rmse, 0.5);
  // The estimate is unbiased: the final velocity is close, and a filter made for a
  // smoother target (lower process noise) gets the velocity much better.
  EXPECT_LT(std::hypot(f.state()(3) - vx, f.state()(4) - vy), 0.3);
}

TEST(RobotFilter, LowerProcessNoiseSmoothsAConstantVelocityTargetMore) {
  RobotFilterParams p;
  p.accel_noise_xy = 0.1;
  std::mt19937 rng(8);
  std::normal_distribution<double> noise(0.0, p.sigma_x);
  RobotFilter f(p, {0, 0, 0, true});
  double v_sq = 0;
  int n = 0;
  for (int k = 1; k <= 300; ++k) {
    f.predict(kDt);
    f.update({2.0 * k * kDt + noise(rng), -1.0 * k * kDt + noise(rng), 0, true});
    if (k >= 120) {
      v_sq += std::pow(f.state()(3) - 2.0, 2) + std::pow(f.state()(4) + 1.0, 2);
      ++n;
    }
  }
  EXPECT_LT(std::sqrt(v_sq / n), 0.03);
}

TEST(RobotFilter, HeadingWrapsAcrossPi) {
  RobotFilterParams p;
  const double omega = 3.0;  // rad/s: crosses +pi -> -pi after ~0.05 s and again later
  RobotFilter f(p, {0, 0, 3.0, true});
  for (int k = 1; k <= 20; ++k) {  // settle on the angular velocity before the crossing
    f.predict(kDt);
    f.update({0, 0, wrapToPi(3.0 + omega * k * kDt), true});
  }
  double worst = 0;
  int crossings = 0;
  double previous = f.state()(2);
  for (int k = 21; k <= 300; ++k) {
    f.predict(kDt);
    const double truth = wrapToPi(3.0 + omega * k * kDt);
    EXPECT_EQ(f.update({0, 0, truth, true}), GateResult::Accepted) << "frame " << k;
    const double theta = f.state()(2);
    EXPECT_GT(theta, -M_PI);
    EXPECT_LE(theta, M_PI);
    if (std::abs(theta - previous) > M_PI) ++crossings;
    previous = theta;
    worst = std::max(worst, std::abs(wrapToPi(theta - truth)));
    EXPECT_NEAR(f.state()(5), omega, 0.2) << "frame " << k;  // no spike at the wrap
  }
  EXPECT_GE(crossings, 2);
  EXPECT_LT(worst, 0.01);
}

TEST(RobotFilter, StillRobotFacingPiWithNoisyHeadings) {
  // Measurements scatter on both sides of +-pi: every innovation must be taken the short way.
  RobotFilterParams p;
  std::mt19937 rng(2);
  std::normal_distribution<double> noise(0.0, p.sigma_theta);
  RobotFilter f(p, {1.0, 1.0, M_PI, true});
  double sq = 0, worst = 0;
  int wrapped = 0;
  for (int k = 1; k <= 300; ++k) {
    f.predict(kDt);
    const double z = wrapToPi(M_PI + noise(rng));
    wrapped += z < 0;
    EXPECT_EQ(f.update({1.0, 1.0, z, true}), GateResult::Accepted) << "frame " << k;
    const double error = std::abs(wrapToPi(f.state()(2) - M_PI));
    sq += error * error;
    worst = std::max(worst, error);
  }
  EXPECT_GT(wrapped, 100);  // about half the measurements are near -pi
  EXPECT_LT(std::sqrt(sq / 300), 0.8 * p.sigma_theta);
  EXPECT_LT(worst, 3 * p.sigma_theta);
  EXPECT_NEAR(f.state()(5), 0.0, 0.3);
}

TEST(RobotFilter, PredictionsComposeExactly) {
  RobotFilter a({}, {1, 2, 0.5, true}), b({}, {1, 2, 0.5, true});
  a.update({1.01, 2.0, 0.5, true});
  b.update({1.01, 2.0, 0.5, true});
  a.predict(0.004);
  a.predict(0.013);
  b.predict(0.017);
  EXPECT_LT((a.state() - b.state()).norm(), 1e-12);
  EXPECT_LT((a.covariance() - b.covariance()).norm(), 1e-12);
}

TEST(RobotFilter, GateRejectsOutliersAndRestartsAfterConsecutiveOnes) {
  RobotFilterParams p;
  p.reinit_after_rejections = 3;
  RobotFilter f(p, {0, 0, 0, true});
  for (int k = 0; k < 30; ++k) {
    f.predict(kDt);
    f.update({0, 0, 0, true});
  }
  f.predict(kDt);
  EXPECT_EQ(f.update({0.5, 0, 0, true}), GateResult::Rejected);
  EXPECT_NEAR(f.state()(0), 0.0, 1e-3);  // untouched
  f.predict(kDt);
  EXPECT_EQ(f.update({0.002, 0, 0, true}), GateResult::Accepted);  // resets the count
  f.predict(kDt);
  EXPECT_EQ(f.update({0.5, 0, 0, true}), GateResult::Rejected);
  f.predict(kDt);
  EXPECT_EQ(f.update({0.5, 0, 0, true}), GateResult::Rejected);
  f.predict(kDt);
  EXPECT_EQ(f.update({0.5, 0, 0, true}), GateResult::Reinitialised);
  EXPECT_DOUBLE_EQ(f.state()(0), 0.5);
  EXPECT_DOUBLE_EQ(f.state()(3), 0.0);
}

TEST(RobotFilter, HeadingFlipIsRejectedButPositionUsed) {
  RobotFilter f({}, {0, 0, 0.2, true});
  for (int k = 0; k < 30; ++k) {
    f.predict(kDt);
    f.update({0, 0, 0.2, true});
  }
  f.predict(kDt);
  EXPECT_EQ(f.update({0.003, 0, wrapToPi(0.2 + M_PI), true}), GateResult::HeadingRejected);
  EXPECT_NEAR(f.state()(2), 0.2, 1e-3);
  EXPECT_GT(f.state()(0), 0.0005);  // position moved toward the measurement
  // A position-only measurement (team-only pattern) never touches the heading.
  f.predict(kDt);
  EXPECT_EQ(f.update({0.003, 0, 0, false}), GateResult::Accepted);
  EXPECT_NEAR(f.state()(2), 0.2, 1e-3);
}

TEST(RobotFilter, LateMeasurementCountsLessAndWidensTheGate) {
  // A track converged on a robot at 1 m/s. A measurement from 50 ms ago, moved forward along
  // the estimated velocity, says less about where the robot is now than a current one: the
  // velocity is known only so well, and the robot may have accelerated since.
  RobotFilterParams p;
  const double v = 1.0, lag = 0.05;
  RobotFilter f(p, {0.0, 0.0, 0.0, true});
  for (int k = 1; k <= 30; ++k) {
    f.predict(kDt);
    ASSERT_EQ(f.update({v * k * kDt, 0.0, 0.0, true}), GateResult::Accepted);
  }
  f.predict(kDt);
  const double now = 31 * kDt, prior = f.state()(0);
  EXPECT_LT(f.positionDistance2(now * v + 0.01, 0.0, lag), 0.8 * f.positionDistance2(now * v + 0.01, 0.0));
  EXPECT_DOUBLE_EQ(f.positionDistance2(now * v + 0.01, 0.0, 0.0), f.positionDistance2(now * v + 0.01, 0.0));

  // Both 1 cm ahead of the truth (the late one after moving it forward by v̂ · lag).
  RobotFilter current = f, late = f, lag_zero = f;
  RobotMeasurement m{now * v + 0.01, 0.0, 0.1, true};
  ASSERT_EQ(current.update(m), GateResult::Accepted);
  ASSERT_EQ(lag_zero.update(m), GateResult::Accepted);  // lag 0 is the plain update
  m.x = (now - lag) * v + 0.01 + f.state()(3) * lag;
  m.lag = lag;
  ASSERT_EQ(late.update(m), GateResult::Accepted);
  EXPECT_EQ(lag_zero.state(), current.state());
  // The current one moves the position towards it; the late one hardly (it speaks of
  // where the robot was, so mostly of the velocity since).
  EXPECT_GT(current.state()(0) - prior, 0.005);
  EXPECT_LT(std::abs(late.state()(0) - prior), 0.3 * (current.state()(0) - prior));
  EXPECT_NE(late.state()(3), f.state()(3));
  EXPECT_LT(late.state()(2), current.state()(2));
  EXPECT_GT(late.covariance()(0, 0), current.covariance()(0, 0));
}

TEST(RobotFilter, RejectsNonsenseParameters) {
  RobotFilterParams p;
  p.sigma_x = 0;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = {};
  p.reinit_after_rejections = 0;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = {};
  p.accel_noise_theta = NAN;
  EXPECT_THROW(validate(p), std::invalid_argument);
  EXPECT_NO_THROW(validate(RobotFilterParams{}));
}
