#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "soccer_vision/tracking/ball_filter.h"

using namespace soccer_vision;

namespace {
constexpr double kDt = 1.0 / 60;
}

TEST(BallFilter, FastRollingBallConverges) {
  BallFilterParams p;
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, p.sigma_xy);
  const Eigen::Vector2d v(9.0, -4.0);
  BallFilter f(p, -3.0, 1.0);
  double sq = 0, measured_sq = 0;
  int n = 0;
  for (int k = 1; k <= 60; ++k) {
    f.predict(kDt);
    const Eigen::Vector2d truth = Eigen::Vector2d(-3.0, 1.0) + v * k * kDt;
    const Eigen::Vector2d m = truth + Eigen::Vector2d(noise(rng), noise(rng));
    const BallGate gate = f.update(m.x(), m.y(), kDt);
    EXPECT_NE(gate, BallGate::Rejected) << "frame " << k;
    if (k > 1) {  // frame 1 may count as a kick from rest
      EXPECT_EQ(gate, BallGate::Accepted) << "frame " << k;
    }
    if (k >= 20) {
      sq += (f.state().head<2>() - truth).squaredNorm();
      measured_sq += (m - truth).squaredNorm();
      ++n;
    }
  }
  EXPECT_LT(std::sqrt(sq / n), std::sqrt(measured_sq / n));
  EXPECT_LT((f.state().tail<2>() - v).norm(), 0.3);
}

TEST(BallFilter, KickRestartsAtTheMeasurementAndPicksUpTheNewVelocity) {
  BallFilterParams p;
  BallFilter f(p, 0.5, 0.5);
  for (int k = 0; k < 60; ++k) {  // a ball at rest
    f.predict(kDt);
    ASSERT_EQ(f.update(0.5, 0.5, kDt), BallGate::Accepted);
  }
  // Kicked at 14 m/s at the start of the next frame interval.
  const Eigen::Vector2d v(-14.0 * 0.6, 14.0 * 0.8);
  bool kicked = false;
  for (int k = 1; k <= 10; ++k) {
    f.predict(kDt);
    const Eigen::Vector2d truth = Eigen::Vector2d(0.5, 0.5) + v * k * kDt;
    const BallGate gate = f.update(truth.x(), truth.y(), kDt);
    ASSERT_NE(gate, BallGate::Rejected) << "frame " << k;
    kicked = kicked || gate == BallGate::Kick;
    if (k >= 3) {
      EXPECT_LT((f.state().head<2>() - truth).norm(), 0.01) << "frame " << k;
      EXPECT_LT((f.state().tail<2>() - v).norm(), 1.0) << "frame " << k;
    }
  }
  EXPECT_TRUE(kicked);
}

TEST(BallFilter, ImplausibleJumpIsRejected) {
  BallFilter f({}, 0, 0);
  for (int k = 0; k < 10; ++k) {
    f.predict(kDt);
    f.update(0, 0, kDt);
  }
  f.predict(kDt);
  // 1 m in one frame = 60 m/s: no kick does that.
  EXPECT_EQ(f.classify(1.0, 0.0, kDt), BallGate::Rejected);
  EXPECT_EQ(f.update(1.0, 0.0, kDt), BallGate::Rejected);
  EXPECT_NEAR(f.state()(0), 0.0, 1e-3);
  // After 0.2 s without measurements the same spot is within reach (15 m/s * 0.2 s = 3 m).
  EXPECT_EQ(f.classify(1.0, 0.0, 0.2), BallGate::Kick);
}

TEST(BallFilter, RejectsNonsenseParameters) {
  BallFilterParams p;
  p.max_speed = -1;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = {};
  p.kick_margin = NAN;
  EXPECT_THROW(validate(p), std::invalid_argument);
}
