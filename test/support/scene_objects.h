// Robots as the tests write them down: a simulated robot at a pose, a ground-truth record.
#pragma once

#include "soccer_vision/common/exchange_formats.h"
#include "soccer_vision/simulation/scene.h"

namespace soccer_vision::test {

inline RobotState robotState(Team team, int id, double x, double y, double theta) {
  RobotState r;
  r.team = team;
  r.id = id;
  r.x = x;
  r.y = y;
  r.theta = theta;
  return r;
}

inline RobotRecord robotRecord(Team team, int id, double x, double y, bool visible = true) {
  RobotRecord r;
  r.team = team;
  r.id = id;
  r.x = x;
  r.y = y;
  r.visible = visible;
  return r;
}

}  // namespace soccer_vision::test
