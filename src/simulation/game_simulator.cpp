#include "soccer_vision/simulation/game_simulator.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Core>

#include "soccer_vision/common/angle.h"
#include "soccer_vision/common/ball.h"

namespace soccer_vision {

namespace {

constexpr double kMaxSubStep = 0.002;      // s
constexpr double kRobotSpeedCap = 5.0;     // m/s, the game's limits
constexpr double kBallSpeedCap = 15.0;     // m/s
constexpr double kArrivalDistance = 0.05;  // m: target reached, pick the next one
constexpr double kHeadingTime = 0.25;      // s: time constant of the heading controller
constexpr double kAvoidRange = 0.30;       // m of gap where robots start steering apart
constexpr int kPlacementTries = 20000;

// Scales v down to at most `limit` in length.
Eigen::Vector2d clampNorm(const Eigen::Vector2d& v, double limit) {
  const double n = v.norm();
  return n > limit ? Eigen::Vector2d(v * (limit / n)) : v;
}

}  // namespace

GameSimulator::GameSimulator(const ScenarioConfig& scenario, const FieldGeometry& field, int max_ids)
    : scenario_(scenario), field_(field), rng_(scenario.seed) {
  const MotionConfig& m = scenario_.motion;
  const double r = robot_radius_;
  if (m.area_x_max - m.area_x_min < 2 * r || m.area_y_max - m.area_y_min < 2 * r)
    throw std::invalid_argument("GameSimulator: the motion area is smaller than a robot");

  const double contact = 2 * r + m.min_separation;
  auto place = [&](Team team, int count) {
    for (int id = 0; id < std::min(count, max_ids); ++id) {
      RobotState robot;
      robot.team = team;
      robot.id = id;
      int tries = 0;
      bool free = false;
      while (!free) {
        if (++tries > kPlacementTries)
          throw std::runtime_error("GameSimulator: cannot place " + std::to_string(state_.robots.size() + 1) +
                                   " robots without overlap in the motion area");
        robot.x = uniform(m.area_x_min + r, m.area_x_max - r);
        robot.y = uniform(m.area_y_min + r, m.area_y_max - r);
        free = std::all_of(state_.robots.begin(), state_.robots.end(), [&](const RobotState& o) {
          return std::hypot(o.x - robot.x, o.y - robot.y) >= contact;
        });
      }
      robot.theta = wrapToPi(uniform(-M_PI, M_PI));
      state_.robots.push_back(robot);
    }
  };
  place(Team::Blue, scenario_.blue_robots);
  place(Team::Yellow, scenario_.yellow_robots);

  const std::size_t n = state_.robots.size();
  target_x_.resize(n);
  target_y_.resize(n);
  target_theta_.resize(n);
  target_deadline_.resize(n);
  for (std::size_t i = 0; i < n; ++i) pickTarget(i);

  // Balls start at rest, on the carpet part of the area, clear of every robot.
  const double cx = field_.carpetHalfLength() - kBallRadius;
  const double cy = field_.carpetHalfWidth() - kBallRadius;
  const double x0 = std::max(m.area_x_min, -cx), x1 = std::min(m.area_x_max, cx);
  const double y0 = std::max(m.area_y_min, -cy), y1 = std::min(m.area_y_max, cy);
  for (int k = 0; k < scenario_.balls; ++k) {
    BallState ball;
    int tries = 0;
    bool free = false;
    while (!free) {
      if (++tries > kPlacementTries)
        throw std::runtime_error("GameSimulator: no free carpet left for the ball");
      ball.x = uniform(x0, x1);
      ball.y = uniform(y0, y1);
      free = std::all_of(state_.robots.begin(), state_.robots.end(), [&](const RobotState& o) {
        return std::hypot(o.x - ball.x, o.y - ball.y) >= r + kBallRadius + 0.01;
      });
    }
    state_.balls.push_back(ball);
  }
  next_kick_ = m.kick_interval * uniform(0.2, 1.0);
}

double GameSimulator::uniform(double lo, double hi) {
  // From the raw 64-bit stream: std:: distributions differ between standard libraries.
  return lo + (hi - lo) * static_cast<double>(rng_() >> 11) * 0x1.0p-53;
}

void GameSimulator::pickTarget(std::size_t i) {
  const MotionConfig& m = scenario_.motion;
  const double r = robot_radius_;
  target_x_[i] = uniform(m.area_x_min + r, m.area_x_max - r);
  target_y_[i] = uniform(m.area_y_min + r, m.area_y_max - r);
  target_theta_[i] = uniform(-M_PI, M_PI);
  target_deadline_[i] = state_.time + uniform(2.0, 6.0);
}

void GameSimulator::step(double dt) {
  if (dt <= 0) return;
  const double t_end = state_.time + dt;
  const int n = static_cast<int>(std::ceil(dt / kMaxSubStep - 1e-9));
  for (int k = 0; k < n; ++k) subStep(dt / n);
  state_.time = t_end;
}

void GameSimulator::subStep(double dt) {
  moveRobots(dt);
  moveBalls(dt);
  state_.time += dt;
}

void GameSimulator::moveRobots(double dt) {
  const MotionConfig& m = scenario_.motion;
  const double v_max = std::min(m.robot_max_speed, kRobotSpeedCap);
  std::vector<RobotState>& robots = state_.robots;
  if (v_max <= 0) {  // static robots: no translation, no rotation
    for (RobotState& rb : robots) rb.vx = rb.vy = rb.omega = 0;
    return;
  }
  const double r = robot_radius_;
  const double contact = 2 * r + m.min_separation;
  const std::size_t n = robots.size();
  auto pos = [&](std::size_t i) { return Eigen::Vector2d(robots[i].x, robots[i].y); };

  // Steering: brake-to-arrive towards the target, pushed apart by close neighbours,
  // within the acceleration limit.
  std::vector<Eigen::Vector2d> vel(n);
  for (std::size_t i = 0; i < n; ++i) {
    RobotState& rb = robots[i];
    Eigen::Vector2d to_target(target_x_[i] - rb.x, target_y_[i] - rb.y);
    if (to_target.norm() < kArrivalDistance || state_.time > target_deadline_[i]) {
      pickTarget(i);
      to_target = Eigen::Vector2d(target_x_[i] - rb.x, target_y_[i] - rb.y);
    }
    const double dist = to_target.norm();
    const double speed = std::min(v_max, std::sqrt(2 * m.robot_max_accel * dist));
    Eigen::Vector2d desired =
        dist > 1e-9 ? Eigen::Vector2d(to_target * (speed / dist)) : Eigen::Vector2d::Zero();
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const Eigen::Vector2d away = pos(i) - pos(j);
      const double d = away.norm();
      const double gap = d - contact;
      if (gap < kAvoidRange && d > 1e-9) desired += away / d * v_max * (1 - gap / kAvoidRange);
    }
    desired = clampNorm(desired, v_max);
    const Eigen::Vector2d v(rb.vx, rb.vy);
    vel[i] = clampNorm(v + clampNorm(desired - v, m.robot_max_accel * dt), v_max);

    const double heading_error = wrapToPi(target_theta_[i] - rb.theta);
    rb.omega = std::clamp(heading_error / kHeadingTime, -m.robot_max_omega, m.robot_max_omega);
  }

  // Hard constraints, so bodies never overlap and never leave the area: within `band` of
  // a contact (farther than any one step can close), a robot may not move towards it.
  // Each removal is a projection, so speeds only shrink; a robot left in conflict stops.
  const double band = 2 * v_max * dt + 1e-9;
  auto violates = [&](std::size_t i, bool fix) {
    bool bad = false;
    Eigen::Vector2d& v = vel[i];
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const Eigen::Vector2d d = pos(j) - pos(i);
      const double dist = d.norm();
      if (dist >= contact + band) continue;
      const Eigen::Vector2d normal = dist > 1e-9 ? Eigen::Vector2d(d / dist) : Eigen::Vector2d(1, 0);
      const double towards = v.dot(normal);
      if (towards > 0) {
        bad = true;
        if (fix) v -= towards * normal;
      }
    }
    auto wall = [&](double gap, double& component, double sign) {
      if (gap < band && component * sign > 0) {
        bad = true;
        if (fix) component = 0;
      }
    };
    wall(robots[i].x - r - m.area_x_min, v.x(), -1);
    wall(m.area_x_max - r - robots[i].x, v.x(), +1);
    wall(robots[i].y - r - m.area_y_min, v.y(), -1);
    wall(m.area_y_max - r - robots[i].y, v.y(), +1);
    return bad;
  };
  for (std::size_t i = 0; i < n; ++i) {
    for (int iteration = 0; iteration < 4; ++iteration)
      if (!violates(i, true)) break;
    if (violates(i, false)) vel[i].setZero();
  }

  for (std::size_t i = 0; i < n; ++i) {
    RobotState& rb = robots[i];
    rb.vx = vel[i].x();
    rb.vy = vel[i].y();
    rb.x += rb.vx * dt;
    rb.y += rb.vy * dt;
    rb.theta = wrapToPi(rb.theta + rb.omega * dt);
  }
}

void GameSimulator::kickBall() {
  const MotionConfig& m = scenario_.motion;
  BallState& ball =
      state_.balls[static_cast<std::size_t>(uniform(0, static_cast<double>(state_.balls.size()) - 1e-9))];
  const double aim_x = uniform(m.area_x_min, m.area_x_max);
  const double aim_y = uniform(m.area_y_min, m.area_y_max);
  double angle = std::atan2(aim_y - ball.y, aim_x - ball.x);
  if (!std::isfinite(angle)) angle = 0;
  const double speed = std::min(m.ball_max_speed, kBallSpeedCap) * uniform(0.4, 1.0);
  ball.vx = speed * std::cos(angle);
  ball.vy = speed * std::sin(angle);
}

void GameSimulator::moveBalls(double dt) {
  const MotionConfig& m = scenario_.motion;
  const double v_max = std::max(0.0, std::min(m.ball_max_speed, kBallSpeedCap));
  if (state_.balls.empty()) return;
  if (v_max > 0 && m.kick_interval > 0 && state_.time >= next_kick_) {
    kickBall();
    next_kick_ += m.kick_interval * uniform(0.5, 1.5);
  }

  const double x_lim = field_.carpetHalfLength() - kBallRadius;
  const double y_lim = field_.carpetHalfWidth() - kBallRadius;
  const double contact = robot_radius_ + kBallRadius;
  for (BallState& ball : state_.balls) {
    Eigen::Vector2d p(ball.x, ball.y), v(ball.vx, ball.vy);
    const double speed = v.norm();
    if (speed > 0) v *= std::max(0.0, speed - m.ball_friction * dt) / speed;
    p += v * dt;

    // Off a robot: out of its body, velocity reflected in the robot's frame.
    for (const RobotState& rb : state_.robots) {
      const Eigen::Vector2d centre(rb.x, rb.y), robot_v(rb.vx, rb.vy);
      const Eigen::Vector2d d = p - centre;
      const double dist = d.norm();
      if (dist >= contact) continue;
      const Eigen::Vector2d normal = dist > 1e-9 ? Eigen::Vector2d(d / dist) : Eigen::Vector2d(1, 0);
      p = centre + normal * contact;
      Eigen::Vector2d relative = v - robot_v;
      const double approach = relative.dot(normal);
      if (approach < 0) relative -= 2 * approach * normal;
      v = clampNorm(robot_v + relative, v_max);
    }

    // Off the carpet edge (mirror the overshoot, reverse the normal velocity).
    auto bounce = [](double& x, double& vx, double lim) {
      if (x > lim) {
        x = std::max(-lim, 2 * lim - x);
        vx = -std::abs(vx);
      } else if (x < -lim) {
        x = std::min(lim, -2 * lim - x);
        vx = std::abs(vx);
      }
    };
    bounce(p.x(), v.x(), x_lim);
    bounce(p.y(), v.y(), y_lim);

    ball.x = p.x();
    ball.y = p.y();
    ball.vx = v.x();
    ball.vy = v.y();
  }
}

}  // namespace soccer_vision
