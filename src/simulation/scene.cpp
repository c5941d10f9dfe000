#include "soccer_vision/simulation/scene.h"

#include <cmath>

namespace soccer_vision {

namespace {

// Wraps an angle to (-pi, pi].
double wrapAngle(double a) {
  a = std::remainder(a, 2 * M_PI);
  return a <= -M_PI ? a + 2 * M_PI : a;
}

}  // namespace

SceneState extrapolate(const SceneState& s, double dt) {
  SceneState out = s;
  out.time += dt;
  for (RobotState& r : out.robots) {
    r.x += r.vx * dt;
    r.y += r.vy * dt;
    r.theta = wrapAngle(r.theta + r.omega * dt);
  }
  for (BallState& b : out.balls) {
    b.x += b.vx * dt;
    b.y += b.vy * dt;
    b.z += b.vz * dt;
  }
  return out;
}

}  // namespace soccer_vision
