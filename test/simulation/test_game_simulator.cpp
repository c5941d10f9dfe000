// The simulated game must respect its own limits: evaluation numbers are only meaningful
// if nothing in the ground truth is physically impossible.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "soccer_vision/common/ball.h"
#include "soccer_vision/simulation/game_simulator.h"

using namespace soccer_vision;

namespace {

constexpr double kRobotRadius = 0.09;
constexpr double kEps = 1e-9;

ScenarioConfig preset(const std::string& name) {
  return loadScenario(std::string(SOCCER_VISION_SOURCE_DIR) + "/config/scenarios/" + name + ".yaml");
}

void expectSameState(const SceneState& a, const SceneState& b) {
  ASSERT_EQ(a.robots.size(), b.robots.size());
  ASSERT_EQ(a.balls.size(), b.balls.size());
  EXPECT_EQ(a.time, b.time);
  for (std::size_t i = 0; i < a.robots.size(); ++i) {
    const RobotState &p = a.robots[i], &q = b.robots[i];
    EXPECT_TRUE(p.team == q.team && p.id == q.id && p.x == q.x && p.y == q.y && p.theta == q.theta &&
                p.vx == q.vx && p.vy == q.vy && p.omega == q.omega)
        << "robot " << i;
  }
  for (std::size_t i = 0; i < a.balls.size(); ++i) {
    const BallState &p = a.balls[i], &q = b.balls[i];
    EXPECT_TRUE(p.x == q.x && p.y == q.y && p.z == q.z && p.vx == q.vx && p.vy == q.vy) << "ball " << i;
  }
}

}  // namespace

TEST(GameSimulator, SameSeedSameGame) {
  const ScenarioConfig scenario = preset("fast_motion");
  const FieldGeometry field;
  GameSimulator a(scenario, field, 5), b(scenario, field, 5);
  for (int k = 0; k < 300; ++k) {
    a.step(1 / 60.0);
    b.step(1 / 60.0);
  }
  expectSameState(a.state(), b.state());
  EXPECT_NEAR(a.state().time, 5.0, 1e-9);

  ScenarioConfig other = scenario;
  other.seed += 1;
  GameSimulator c(other, field, 5);
  EXPECT_NE(a.state().robots[0].x, c.state().robots[0].x);
}

TEST(GameSimulator, TeamsAndIdsFollowTheScenarioAndThePatternCap) {
  ScenarioConfig scenario;
  scenario.blue_robots = 7;
  scenario.yellow_robots = 3;
  scenario.balls = 2;
  GameSimulator sim(scenario, FieldGeometry{}, 5);
  const auto& robots = sim.state().robots;
  ASSERT_EQ(robots.size(), 8u);  // blue capped at the pattern's 5 ids
  for (int id = 0; id < 5; ++id) EXPECT_TRUE(robots[id].team == Team::Blue && robots[id].id == id);
  for (int id = 0; id < 3; ++id) EXPECT_TRUE(robots[5 + id].team == Team::Yellow && robots[5 + id].id == id);
  EXPECT_EQ(sim.state().balls.size(), 2u);
}

// Every limit of the brief, checked at every frame of a few simulated seconds.
TEST(GameSimulator, StaysWithinSpeedsSeparationAndTheField) {
  const FieldGeometry field;
  for (const std::string name : {"fast_motion", "crowded", "ssl_pattern"}) {
    SCOPED_TRACE(name);
    const ScenarioConfig scenario = preset(name);
    const MotionConfig& m = scenario.motion;
    GameSimulator sim(scenario, field, 16);
    const double dt = 1 / scenario.fps;
    const double contact = 2 * kRobotRadius + m.min_separation;
    const double ball_limit = std::min(m.ball_max_speed, 15.0);
    double fastest_robot = 0, fastest_ball = 0;
    SceneState previous = sim.state();
    for (int frame = 0; frame < 8 * static_cast<int>(scenario.fps); ++frame) {
      sim.step(dt);
      const SceneState& s = sim.state();
      int failures = 0;
      for (std::size_t i = 0; i < s.robots.size(); ++i) {
        const RobotState& r = s.robots[i];
        const RobotState& before = previous.robots[i];
        const double speed = std::hypot(r.vx, r.vy);
        fastest_robot = std::max(fastest_robot, speed);
        failures += !(speed <= m.robot_max_speed + kEps);
        failures += !(std::hypot(r.x - before.x, r.y - before.y) <= m.robot_max_speed * dt + kEps);
        failures += !(std::abs(r.omega) <= m.robot_max_omega + kEps);
        failures += !(r.theta > -M_PI && r.theta <= M_PI);
        failures += !(r.x >= m.area_x_min + kRobotRadius - kEps && r.x <= m.area_x_max - kRobotRadius + kEps);
        failures += !(r.y >= m.area_y_min + kRobotRadius - kEps && r.y <= m.area_y_max - kRobotRadius + kEps);
        for (std::size_t j = i + 1; j < s.robots.size(); ++j)
          failures += !(std::hypot(r.x - s.robots[j].x, r.y - s.robots[j].y) >= contact - kEps);
      }
      for (const BallState& b : s.balls) {
        const double speed = std::hypot(b.vx, b.vy);
        fastest_ball = std::max(fastest_ball, speed);
        failures += !(speed <= ball_limit + kEps);
        failures += !field.onCarpet(b.x, b.y, -kBallRadius + kEps);
        failures += b.z != kBallRadius;
      }
      ASSERT_EQ(failures, 0) << "at frame " << frame;
      previous = s;
    }
    // The limits are reached, not just respected by standing still.
    EXPECT_GT(fastest_robot, 0.8 * m.robot_max_speed);
    EXPECT_GT(fastest_ball, 0.3 * ball_limit);
  }
}

TEST(GameSimulator, BallBouncesOffTheCarpetEdgeAndRobots) {
  ScenarioConfig scenario;
  scenario.blue_robots = 16;
  scenario.yellow_robots = 16;
  scenario.motion.robot_max_speed = 0;  // still robots as obstacles
  scenario.motion.ball_max_speed = 15;
  scenario.motion.ball_friction = 0;  // between kicks the speed is constant...
  scenario.motion.kick_interval = 2.0;
  const FieldGeometry field;
  GameSimulator sim(scenario, field, 16);
  const std::vector<RobotState> robots = sim.state().robots;

  // ...so a turn at unchanged speed is a bounce; a change of speed is a kick.
  int edge_bounces = 0, robot_bounces = 0;
  BallState before = sim.state().balls[0];
  for (int k = 0; k < 30 * 60; ++k) {
    sim.step(1 / 60.0);
    const BallState& b = sim.state().balls[0];
    ASSERT_TRUE(field.onCarpet(b.x, b.y, -kBallRadius + kEps)) << "frame " << k;
    double nearest_robot = HUGE_VAL;
    for (const RobotState& r : robots)
      nearest_robot = std::min(nearest_robot, std::hypot(b.x - r.x, b.y - r.y));
    ASSERT_GE(nearest_robot, kRobotRadius + kBallRadius - kEps) << "frame " << k;

    const double speed = std::hypot(b.vx, b.vy), speed_before = std::hypot(before.vx, before.vy);
    const double cross = b.vx * before.vy - b.vy * before.vx, dot = b.vx * before.vx + b.vy * before.vy;
    const bool turned = speed > 0 && (std::abs(cross) > 1e-6 * speed * speed || dot < 0);
    if (turned && std::abs(speed - speed_before) < 1e-9) {
      if (nearest_robot < kRobotRadius + kBallRadius + 0.3) ++robot_bounces;
      if (!field.onCarpet(b.x, b.y, -kBallRadius - 0.3)) ++edge_bounces;
    }
    before = b;
  }
  EXPECT_GT(edge_bounces, 0);
  EXPECT_GT(robot_bounces, 0);
}

TEST(GameSimulator, StaticScenarioDoesNotMove) {
  const ScenarioConfig scenario = preset("even_static");
  ASSERT_EQ(scenario.motion.robot_max_speed, 0.0);
  ASSERT_EQ(scenario.motion.ball_max_speed, 0.0);
  GameSimulator sim(scenario, FieldGeometry{}, 5);
  SceneState start = sim.state();
  for (int k = 0; k < 600; ++k) sim.step(1 / 60.0);
  start.time = sim.state().time;
  expectSameState(start, sim.state());
}

TEST(GameSimulator, ExtrapolateMovesAlongTheVelocities) {
  SceneState s;
  s.time = 1.0;
  RobotState r;
  r.x = 1;
  r.vx = 2;
  r.vy = -1;
  r.theta = 3.0;
  r.omega = 10;
  s.robots = {r};
  BallState b;
  b.vx = 4;
  s.balls = {b};
  const SceneState e = extrapolate(s, 0.1);
  EXPECT_DOUBLE_EQ(e.time, 1.1);
  EXPECT_DOUBLE_EQ(e.robots[0].x, 1.2);
  EXPECT_DOUBLE_EQ(e.robots[0].y, -0.1);
  EXPECT_NEAR(e.robots[0].theta, 4.0 - 2 * M_PI, 1e-12);  // wrapped to (-pi, pi]
  EXPECT_DOUBLE_EQ(e.balls[0].x, 0.4);
  EXPECT_DOUBLE_EQ(e.balls[0].z, 0.0215);
}
