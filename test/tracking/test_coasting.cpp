// Honest tracks: a robot or ball that is no longer measured is a prediction (visible false)
// and leaves the output once coast_sigmas x its predicted position's std-dev exceeds
// max_coast_uncertainty (3 sigma > 25 mm by default); the tracker keeps it for the search
// windows and takes it back when it is seen again.
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "soccer_vision/tracking/tracker.h"

using namespace soccer_vision;

namespace {

constexpr double kDt = 1.0 / 60;
constexpr double kT0 = 1700000000.0;
constexpr double kSpeed = 1.5;  // [m/s] along x

double largestSigma(const Eigen::Matrix2d& P) {
  const double a = P(0, 0), d = P(1, 1), b = P(0, 1);
  return std::sqrt(0.5 * (a + d) + std::sqrt(0.25 * (a - d) * (a - d) + b * b));
}

RobotDetection robot(int id, double x, double y) {
  RobotDetection d;
  d.team = Team::Yellow;
  d.id = id;
  d.x = x;
  d.y = y;
  d.theta = 0.3;
  d.confidence = 0.9;
  return d;
}

BallDetection ball(double x, double y) {
  BallDetection b;
  b.x = x;
  b.y = y;
  b.confidence = 0.8;
  return b;
}

const TrackedRobot* find(const TrackerOutput& out, int id) {
  for (const auto& r : out.robots) {
    if (r.id == id) return &r;
  }
  return nullptr;
}

// Robot 1 and the ball move at kSpeed with measurement noise (4 mm, 5 mm) for `seen`
// frames, then only robot 2 (still) is detected until frame `reappear`, from which robot 1
// and the ball are detected again. Returns per frame after the disappearance how the
// output and the predictions looked.
struct CoastRecord {
  int robot_frames_in_output = 0, ball_frames_in_output = 0;  // coasting frames still output
  double worst_robot_error = 0, worst_ball_error = 0;         // [m] of those outputs
  double worst_robot_3sigma = 0, worst_ball_3sigma = 0;       // [m] of those outputs
  bool coasting_ever_visible = false;
  bool kept_for_windows = true;                 // predictions() had both while unseen
  bool back_when_seen = false;                  // robot 1 and the ball output, visible, same track ids
  int withheld_robots = 0, withheld_balls = 0;  // in the last unseen frame
};

CoastRecord coast(const TrackerParams& params, int seen, int reappear, int total) {
  Tracker tracker(params);
  std::mt19937 rng(7);
  std::normal_distribution<double> robot_noise(0, 0.004), ball_noise(0, 0.005);
  CoastRecord rec;
  int robot_track = -1, ball_track = -1;
  for (int k = 0; k < total; ++k) {
    const double t = kT0 + k * kDt;
    const double x = -1.0 + kSpeed * k * kDt;
    CameraFrameDetections f;
    f.stamp = t;
    f.robots.push_back(robot(2, 2.0, 1.0));
    const bool visible = k < seen || k >= reappear;
    if (visible) {
      f.robots.push_back(robot(1, x + robot_noise(rng), 0.5 + robot_noise(rng)));
      f.balls.push_back(ball(x + ball_noise(rng), -0.5 + ball_noise(rng)));
    }
    tracker.update(f);
    const TrackerOutput out = tracker.output(t);
    const TrackerOutput all = tracker.predictions(t);
    if (k == seen - 1) {
      robot_track = find(out, 1)->track_id;
      ball_track = out.primaryBall()->track_id;
    }
    if (!visible) {
      rec.kept_for_windows = rec.kept_for_windows && find(all, 1) && all.balls.size() == 1;
      if (const TrackedRobot* r = find(out, 1)) {
        ++rec.robot_frames_in_output;
        rec.coasting_ever_visible = rec.coasting_ever_visible || r->visible;
        rec.worst_robot_error = std::max(rec.worst_robot_error, std::hypot(r->x - x, r->y - 0.5));
        rec.worst_robot_3sigma = std::max(rec.worst_robot_3sigma, 3 * largestSigma(r->position_covariance));
      }
      if (!out.balls.empty()) {
        const TrackedBall& b = out.balls.front();
        ++rec.ball_frames_in_output;
        rec.coasting_ever_visible = rec.coasting_ever_visible || b.visible;
        rec.worst_ball_error = std::max(rec.worst_ball_error, std::hypot(b.x - x, b.y + 0.5));
        rec.worst_ball_3sigma = std::max(rec.worst_ball_3sigma, 3 * largestSigma(b.position_covariance));
      }
      rec.withheld_robots = out.withheld_robots;
      rec.withheld_balls = out.withheld_balls;
    }
    if (k == reappear) {
      const TrackedRobot* r = find(out, 1);
      rec.back_when_seen = r && r->visible && r->track_id == robot_track && out.primaryBall() &&
                           out.primaryBall()->visible && out.primaryBall()->track_id == ball_track;
    }
  }
  return rec;
}

}  // namespace

TEST(Coasting, UnseenRobotAndBallLeaveTheOutputOnceThreeSigmaExceeds25Millimetres) {
  const TrackerParams params;  // defaults: 3 sigma, 25 mm
  ASSERT_DOUBLE_EQ(params.max_coast_uncertainty, 0.025);
  ASSERT_DOUBLE_EQ(params.coast_sigmas, 3.0);
  // Seen for 1 s, unseen for 0.4 s (less than the 0.5 s lost timeout), then seen again.
  const CoastRecord rec = coast(params, 60, 84, 90);
  std::printf(
      "coasting in the output: robot %d frames (worst 3 sigma %.1f mm, error %.1f mm), "
      "ball %d frames (%.1f mm, %.1f mm) at 60 Hz, %.1f m/s\n",
      rec.robot_frames_in_output, rec.worst_robot_3sigma * 1e3, rec.worst_robot_error * 1e3,
      rec.ball_frames_in_output, rec.worst_ball_3sigma * 1e3, rec.worst_ball_error * 1e3, kSpeed);
  EXPECT_FALSE(rec.coasting_ever_visible);  // a prediction is never "visible"
  // A frame or two of prediction is worth giving; 24 unseen frames are not.
  EXPECT_GE(rec.robot_frames_in_output, 1);
  EXPECT_GE(rec.ball_frames_in_output, 1);
  EXPECT_LE(rec.robot_frames_in_output, 12);
  EXPECT_LE(rec.ball_frames_in_output, 12);
  // What was output stayed within the bound, and the bound was honest about the error.
  EXPECT_LE(rec.worst_robot_3sigma, 0.025);
  EXPECT_LE(rec.worst_ball_3sigma, 0.025);
  EXPECT_LE(rec.worst_robot_error, 0.025);
  EXPECT_LE(rec.worst_ball_error, 0.025);
  EXPECT_EQ(rec.withheld_robots, 1);
  EXPECT_EQ(rec.withheld_balls, 1);
  EXPECT_TRUE(rec.kept_for_windows);  // the search windows still look for them
  EXPECT_TRUE(rec.back_when_seen);    // and the same tracks come back, measured
}

TEST(Coasting, TheBoundIsTheParameter) {
  TrackerParams tight;
  tight.max_coast_uncertainty = 0.015;
  TrackerParams loose;
  loose.max_coast_uncertainty = 0.060;
  const CoastRecord t = coast(tight, 60, 84, 90), l = coast(loose, 60, 84, 90);
  EXPECT_LT(t.robot_frames_in_output, l.robot_frames_in_output);
  EXPECT_LT(t.ball_frames_in_output, l.ball_frames_in_output);
  EXPECT_LE(t.worst_robot_3sigma, 0.015);
  EXPECT_LE(l.worst_robot_3sigma, 0.060);
}

TEST(Coasting, OffKeepsPredictionsUntilTheLostTimeout) {
  TrackerParams off;
  off.max_coast_uncertainty = 0;
  const CoastRecord rec = coast(off, 60, 84, 90);
  EXPECT_EQ(rec.robot_frames_in_output, 24);  // every unseen frame (0.4 s < lost timeout)
  EXPECT_EQ(rec.ball_frames_in_output, 24);
  EXPECT_FALSE(rec.coasting_ever_visible);
  EXPECT_EQ(rec.withheld_robots, 0);
}

TEST(Coasting, BadBoundsAreRefused) {
  TrackerParams p;
  p.max_coast_uncertainty = -0.01;
  EXPECT_THROW(Tracker{p}, std::invalid_argument);
  p = TrackerParams{};
  p.coast_sigmas = 0;
  EXPECT_THROW(Tracker{p}, std::invalid_argument);
}
