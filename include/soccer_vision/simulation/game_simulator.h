// Moves robots and ball like a real game, deterministically for a seed: robots steer to
// random targets within speed/acceleration limits and avoid each other, the ball rolls
// with friction, is kicked now and then and bounces off the field boundary and robots.
#pragma once

#include <random>

#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/simulation/scenario.h"
#include "soccer_vision/simulation/scene.h"

namespace soccer_vision {

class GameSimulator {
 public:
  GameSimulator(const ScenarioConfig& scenario, const FieldGeometry& field, int max_ids);

  const SceneState& state() const { return state_; }
  // Advances the world by dt seconds (internally in sub-steps of at most 2 ms).
  void step(double dt);

 private:
  void subStep(double dt);
  void moveRobots(double dt);
  void moveBalls(double dt);
  void kickBall();
  void pickTarget(std::size_t robot_index);
  double uniform(double lo, double hi);

  ScenarioConfig scenario_;
  FieldGeometry field_;
  double robot_radius_ = 0.09;
  std::mt19937_64 rng_;
  SceneState state_;
  std::vector<double> target_x_, target_y_, target_theta_;
  std::vector<double> target_deadline_;  // s: a blocked robot gives up its target then
  double next_kick_ = 0;
};

}  // namespace soccer_vision
