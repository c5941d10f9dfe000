#include "soccer_vision/simulation/scene.h"

#include <cmath>

#include "soccer_vision/common/angle.h"

namespace soccer_vision {

SceneState extrapolate(const SceneState& s, double dt) {
  SceneState out = s;
  out.time += dt;
  for (RobotState& r : out.robots) {
    r.x += r.vx * dt;
    r.y += r.vy * dt;
    r.theta = wrapToPi(r.theta + r.omega * dt);
  }
  for (BallState& b : out.balls) {
    b.x += b.vx * dt;
    b.y += b.vy * dt;
    b.z += b.vz * dt;
  }
  return out;
}

}  // namespace soccer_vision
