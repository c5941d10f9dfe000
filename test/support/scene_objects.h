// Robots as the tests write them down: a simulated robot at a pose, a ground-truth record,
// a detection.
#pragma once

#include "soccer_vision/common/detections.h"
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

// A detection with a heading (id -1: none, heading_valid false).
inline RobotDetection robotDetection(Team team, int id, double x, double y, double theta,
                                     double confidence = 0.9) {
  RobotDetection d;
  d.team = team;
  d.id = id;
  d.x = x;
  d.y = y;
  d.theta = theta;
  d.heading_valid = id >= 0;
  d.confidence = confidence;
  return d;
}

}  // namespace soccer_vision::test
