// Kicked-ball estimation for the tracked packets, from the tracker's outputs. Our tracker
// restarts its ball filter on a kick (docs/tracking.md) but models no flight and no friction:
// a kick is a jump of the primary ball's speed between two outputs; its start is the last
// output before the jump (where and when the ball lay or rolled slowly), the kicker the
// nearest robot there; stop time and place are predicted with a constant rolling
// deceleration. The estimate lasts while the ball rolls faster than stop_speed.
#pragma once

#include <optional>

#include <Eigen/Core>

#include "soccer_vision/common/color_class.h"
#include "soccer_vision/tracking/tracker.h"

namespace soccer_vision::ssl {

struct KickedBallParams {
  double min_speed = 1.0;             // [m/s] a kick leaves the ball at least this fast
  double min_speed_gain = 1.0;        // [m/s] and this much faster than one output before
  double max_output_gap = 0.1;        // [s] outputs further apart are not compared
  double stop_speed = 0.1;            // [m/s] slower: the kicked ball has stopped
  double rolling_deceleration = 0.3;  // [m/s²] of a rolling ball on the carpet (> 0)
  double kicker_reach = 0.15;         // [m] robot centre to the ball at the kick, at most
};

void validate(const KickedBallParams& p);  // throws std::invalid_argument naming the parameter

struct KickedBallEstimate {
  Eigen::Vector2d start_position{0, 0};  // [m]
  double start_time = 0;                 // [s]
  Eigen::Vector3d velocity{0, 0, 0};     // [m/s] just after the kick (z: 0, flight is not modelled)
  double stop_time = 0;                  // [s] predicted
  Eigen::Vector2d stop_position{0, 0};   // [m] predicted
  std::optional<Team> kicker_team;       // the kicker, when a robot with an id was within reach
  int kicker_id = -1;
};

class KickedBallEstimator {
 public:
  explicit KickedBallEstimator(const KickedBallParams& params = {});

  // Feeds one tracker output (in time order); returns the current kick, if the ball is rolling
  // from one.
  const std::optional<KickedBallEstimate>& update(const TrackerOutput& output);
  const std::optional<KickedBallEstimate>& current() const { return kick_; }

 private:
  struct BallState {
    double stamp;
    Eigen::Vector2d position, velocity;
  };
  KickedBallParams p_;
  std::optional<BallState> last_;
  std::optional<KickedBallEstimate> kick_;
};

}  // namespace soccer_vision::ssl
