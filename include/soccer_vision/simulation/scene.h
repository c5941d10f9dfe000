// The true state of the field at one instant: what the simulator moves and the
// renderer draws, and what ground truth reports. Field frame, SI units.
#pragma once

#include <vector>

#include "soccer_vision/common/ball.h"
#include "soccer_vision/common/color_class.h"

namespace soccer_vision {

struct RobotState {
  Team team = Team::Blue;
  int id = 0;
  double x = 0, y = 0, theta = 0;    // m, m, rad (CCW from +x)
  double vx = 0, vy = 0, omega = 0;  // m/s, m/s, rad/s
};

struct BallState {
  double x = 0, y = 0, z = kBallRadius;  // m; z of the centre
  double vx = 0, vy = 0, vz = 0;         // m/s
};

struct SceneState {
  double time = 0;  // s since the start of the scenario
  std::vector<RobotState> robots;
  std::vector<BallState> balls;
};

// State advanced by `dt` along the current velocities (used for motion blur).
SceneState extrapolate(const SceneState& s, double dt);

}  // namespace soccer_vision
