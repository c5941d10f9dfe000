#include <stdexcept>

#include <gtest/gtest.h>

#include "soccer_vision/ssl/kicked_ball.h"

using namespace soccer_vision;

namespace {

TrackerOutput withBall(double stamp, double x, double y, double vx, double vy) {
  TrackerOutput out;
  out.stamp = stamp;
  soccer_vision::TrackedBall b;
  b.primary = true;
  b.x = x;
  b.y = y;
  b.vx = vx;
  b.vy = vy;
  out.balls = {b};
  soccer_vision::TrackedRobot kicker;
  kicker.team = Team::Yellow;
  kicker.id = 2;
  kicker.x = 0.9;
  kicker.y = 0.0;
  soccer_vision::TrackedRobot far;
  far.team = Team::Blue;
  far.id = 1;
  far.x = 3.0;
  out.robots = {kicker, far};
  return out;
}

}  // namespace

TEST(KickedBallEstimator, SpeedJumpIsAKickFromTheLastRestingPlaceByTheNearestRobot) {
  ssl::KickedBallEstimator estimator;
  EXPECT_FALSE(estimator.update(withBall(10.0, 1.0, 0.0, 0.0, 0.0)).has_value());
  const auto& kick = estimator.update(withBall(10.0 + 1.0 / 60, 1.05, 0.0, 3.0, 0.0));
  ASSERT_TRUE(kick.has_value());
  EXPECT_DOUBLE_EQ(kick->start_time, 10.0);
  EXPECT_NEAR(kick->start_position.x(), 1.0, 1e-12);
  EXPECT_NEAR(kick->velocity.x(), 3.0, 1e-12);
  ASSERT_TRUE(kick->kicker_team.has_value());
  EXPECT_EQ(*kick->kicker_team, Team::Yellow);
  EXPECT_EQ(kick->kicker_id, 2);
  // 3 m/s at 0.3 m/s²: stops 10 s and 15 m later.
  EXPECT_NEAR(kick->stop_time - (10.0 + 1.0 / 60), 10.0, 1e-9);
  EXPECT_NEAR(kick->stop_position.x(), 1.05 + 15.0, 1e-9);
}

TEST(KickedBallEstimator, SlowRollingIsNoKickAndAStoppedBallEndsIt) {
  ssl::KickedBallEstimator estimator;
  estimator.update(withBall(0.0, 0.0, 0.0, 0.0, 0.0));
  EXPECT_FALSE(estimator.update(withBall(0.02, 0.0, 0.0, 0.8, 0.0)).has_value());  // a dribble
  EXPECT_TRUE(estimator.update(withBall(0.04, 0.0, 0.0, 2.5, 0.0)).has_value());
  EXPECT_TRUE(estimator.update(withBall(0.06, 0.05, 0.0, 2.4, 0.0)).has_value());
  EXPECT_FALSE(estimator.update(withBall(0.08, 0.1, 0.0, 0.05, 0.0)).has_value());
}

TEST(KickedBallEstimator, NoKickAcrossAGapOrWithoutABall) {
  ssl::KickedBallEstimator estimator;
  estimator.update(withBall(0.0, 0.0, 0.0, 0.0, 0.0));
  EXPECT_FALSE(estimator.update(withBall(0.5, 1.0, 0.0, 3.0, 0.0)).has_value());  // 0.5 s apart
  estimator.update(withBall(0.52, 1.0, 0.0, 0.0, 0.0));
  TrackerOutput empty;
  empty.stamp = 0.54;
  EXPECT_FALSE(estimator.update(empty).has_value());
}

TEST(KickedBallEstimator, RejectsParametersOutOfRange) {
  ssl::KickedBallParams p;
  p.rolling_deceleration = 0;
  EXPECT_THROW(ssl::KickedBallEstimator{p}, std::invalid_argument);
  p = {};
  p.stop_speed = 2 * p.min_speed;
  EXPECT_THROW(ssl::validate(p), std::invalid_argument);
}
