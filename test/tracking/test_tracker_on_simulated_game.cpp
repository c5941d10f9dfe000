// The tracker on the GameSimulator's ground truth seen by the two default cameras:
// noisy detections (calibration mismatch between the cameras, missed detections, stray
// ball candidates), both cameras fused. Prints the figures; asserts zero identity
// switches, full coverage and errors below the measurement noise.
#include <cmath>
#include <cstdio>
#include <map>
#include <random>

#include <gtest/gtest.h>

#include "soccer_vision/common/angle.h"
#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/simulation/game_simulator.h"
#include "soccer_vision/tracking/tracker.h"

using namespace soccer_vision;

namespace {

struct Figures {
  long robot_samples = 0, robot_missing = 0, identity_switches = 0;
  long withheld = 0;  // coasting robot and ball outputs withheld (too uncertain)
  double position_sq = 0, measurement_sq = 0, heading_sq = 0, velocity_sq = 0, omega_sq = 0;
  long measurements = 0;
  long ball_samples = 0, ball_tracked = 0;
  double ball_sq = 0;
  double rmse() const { return std::sqrt(position_sq / robot_samples); }
  double measurementRmse() const { return std::sqrt(measurement_sq / measurements); }
  double headingRmse() const { return std::sqrt(heading_sq / robot_samples); }
  double velocityRmse() const { return std::sqrt(velocity_sq / robot_samples); }
  double omegaRmse() const { return std::sqrt(omega_sq / robot_samples); }
  double ballRmse() const { return std::sqrt(ball_sq / ball_tracked); }
};

Figures simulate(bool team_only, int frames, const TrackerParams& params = {}) {
  ScenarioConfig scenario;
  scenario.seed = 4;
  scenario.motion.robot_max_speed = 3.0;
  scenario.motion.ball_max_speed = 10.0;
  const FieldGeometry field;
  GameSimulator sim(scenario, field, 5);
  const CameraModel cameras[2] = {CameraModel::defaultCamera(field, 0), CameraModel::defaultCamera(field, 1)};
  const double bias[2] = {-0.0015, 0.0015};  // camera-to-camera calibration mismatch [m]
  std::mt19937 rng(17);
  std::normal_distribution<double> noise_xy(0.0, 0.003), noise_theta(0.0, 0.02), noise_ball(0.0, 0.004);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);

  Tracker tracker(params);
  Figures fig;
  std::map<std::pair<int, int>, int> track_of;  // true robot -> track id it was matched to
  const double dt = 1.0 / scenario.fps, t0 = 1700000000.0;
  for (int k = 0; k < frames; ++k) {
    sim.step(dt);
    const SceneState& s = sim.state();
    const double stamp = t0 + s.time;
    for (int c = 0; c < 2; ++c) {
      CameraFrameDetections f;
      f.stamp = stamp;
      f.camera_id = c;
      for (const auto& r : s.robots) {
        const auto px = cameras[c].project({r.x, r.y, 0.15});
        if (!px || !cameras[c].inImage(*px, 20) || uniform(rng) < 0.01) continue;  // 1 % missed
        RobotDetection d;
        d.team = r.team;
        d.id = team_only ? -1 : r.id;
        d.x = r.x + bias[c] + noise_xy(rng);
        d.y = r.y + noise_xy(rng);
        d.theta = wrapToPi(r.theta + noise_theta(rng));
        d.heading_valid = !team_only;
        d.confidence = 0.9;
        fig.measurement_sq += std::pow(d.x - r.x, 2) + std::pow(d.y - r.y, 2);
        ++fig.measurements;
        f.robots.push_back(d);
      }
      for (const auto& b : s.balls) {
        const auto px = cameras[c].project({b.x, b.y, b.z});
        if (!px || !cameras[c].inImage(*px, 5) || uniform(rng) < 0.02) continue;
        BallDetection d;
        d.x = b.x + bias[c] + noise_ball(rng);
        d.y = b.y + noise_ball(rng);
        d.confidence = 0.9;
        f.balls.push_back(d);
      }
      if (uniform(rng) < 0.05) {  // a stray orange blob somewhere on the field
        BallDetection d;
        d.x = (uniform(rng) - 0.5) * 9.0;
        d.y = (uniform(rng) - 0.5) * 6.0;
        d.confidence = 0.3;
        f.balls.push_back(d);
      }
      tracker.update(f);
    }
    // The tracks themselves, coasting ones included (output() withholds those whose 3 sigma
    // exceeds 25 mm: test_coasting.cpp); how often it did is printed.
    const auto out = tracker.predictions(stamp);
    if (k >= 30) {
      const auto honest = tracker.output(stamp);
      fig.withheld += honest.withheld_robots + honest.withheld_balls;
    }
    if (k < 30) continue;  // let the tracks settle
    for (const auto& r : s.robots) {
      ++fig.robot_samples;
      const TrackedRobot* best = nullptr;
      double best_distance = 0.1;  // [m] a track farther away is not this robot's
      for (const auto& t : out.robots) {
        if (t.team != r.team || (!team_only && t.id != r.id)) continue;
        const double distance = std::hypot(t.x - r.x, t.y - r.y);
        if (distance < best_distance) {
          best_distance = distance;
          best = &t;
        }
      }
      if (!best) {
        ++fig.robot_missing;
        --fig.robot_samples;
        continue;
      }
      const auto key = std::make_pair(static_cast<int>(r.team), r.id);
      const auto it = track_of.find(key);
      if (it == track_of.end()) {
        track_of[key] = best->track_id;
      } else if (it->second != best->track_id) {
        ++fig.identity_switches;
        it->second = best->track_id;
      }
      fig.position_sq += best_distance * best_distance;
      fig.heading_sq += team_only ? 0.0 : std::pow(wrapToPi(best->theta - r.theta), 2);
      fig.velocity_sq += std::pow(best->vx - r.vx, 2) + std::pow(best->vy - r.vy, 2);
      fig.omega_sq += team_only ? 0.0 : std::pow(best->omega - r.omega, 2);
    }
    for (const auto& b : s.balls) {
      ++fig.ball_samples;
      const auto* tb = out.primaryBall();
      if (tb && std::hypot(tb->x - b.x, tb->y - b.y) < 0.1) {
        ++fig.ball_tracked;
        fig.ball_sq += std::pow(tb->x - b.x, 2) + std::pow(tb->y - b.y, 2);
      }
    }
  }
  std::printf(
      "%s: %ld robot samples, %ld without a track, %ld identity switches; position RMSE "
      "%.2f mm (measurements %.2f mm), heading RMSE %.3f°, velocity RMSE %.3f m/s, omega RMSE %.2f rad/s; "
      "ball "
      "tracked %.2f %% of %ld frames, RMSE %.2f mm; stats: outliers %ld, reinit %ld, "
      "kicks %ld, tracks created %ld; outputs withheld while coasting %ld\n",
      team_only ? "team-only" : "identity", fig.robot_samples, fig.robot_missing, fig.identity_switches,
      1e3 * fig.rmse(), 1e3 * fig.measurementRmse(), fig.headingRmse() * 180 / M_PI, fig.velocityRmse(),
      fig.omegaRmse(), 100.0 * fig.ball_tracked / fig.ball_samples, fig.ball_samples, 1e3 * fig.ballRmse(),
      tracker.stats().robot_outliers, tracker.stats().robots_reinitialised, tracker.stats().ball_kicks,
      tracker.stats().tracks_created, fig.withheld);
  return fig;
}

}  // namespace

TEST(TrackingSimulation, IdentityPatternGame) {
  const Figures fig = simulate(false, 1800);  // 30 s at 60 Hz, both cameras
  EXPECT_EQ(fig.identity_switches, 0);
  EXPECT_EQ(fig.robot_missing, 0);
  EXPECT_LT(fig.rmse(), 0.9 * fig.measurementRmse());
  EXPECT_LT(fig.headingRmse(), 1.0 * M_PI / 180);  // measurements: 0.02 rad = 1.15°
  EXPECT_LT(fig.velocityRmse(), 0.2);
  EXPECT_GT(static_cast<double>(fig.ball_tracked) / fig.ball_samples, 0.995);
  EXPECT_LT(fig.ballRmse(), 0.006);  // measurements: 5.7 mm
}

TEST(TrackingSimulation, TeamOnlyPatternGame) {
  const Figures fig = simulate(true, 1800);
  EXPECT_EQ(fig.identity_switches, 0);
  EXPECT_EQ(fig.robot_missing, 0);
  EXPECT_LT(fig.rmse(), 0.9 * fig.measurementRmse());
  EXPECT_LT(fig.velocityRmse(), 0.2);
}
