// Scoring a whole run (result frames against the ground truth of their instants), with
// the figures the offline evaluation reports beyond scoring.h's per-frame Score:
//  - failed frames (paper Table I): a scored frame fails when any ground-truth robot or
//    ball in view was not matched, or any result was a false positive;
//  - identity switches: for each ground-truth robot, the identity (team, id) of the
//    nearest result robot within max_distance, whatever its label; a switch is a change
//    of that identity from one frame where the robot had such a neighbour to the next
//    (a track that takes another robot's id, or two robots swapping ids, count here);
//  - per-frame series for plots: position errors, trajectories (truth and result of the
//    same identity), and the Kalman prediction error (prediction for a frame, before its
//    measurements, against the truth of that frame: paper Fig. 6).
// Ground truth is looked up by stamp (TruthTimeline); result frames without truth at
// their stamp are counted and not scored.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <tuple>
#include <vector>

#include "soccer_vision/common/exchange_formats.h"
#include "soccer_vision/evaluation/scoring.h"
#include "soccer_vision/tracking/tracker.h"

namespace soccer_vision {

// Ground-truth frames by stamp.
class TruthTimeline {
 public:
  explicit TruthTimeline(std::vector<FrameRecord> frames, double tolerance = 1e-4);
  // The frame whose stamp is within the tolerance of `stamp`, or nullptr.
  const FrameRecord* at(double stamp) const;
  std::size_t size() const { return frames_.size(); }
  bool empty() const { return frames_.empty(); }

 private:
  std::vector<FrameRecord> frames_;  // sorted by stamp
  double tolerance_;
};

struct RobotKey {
  Team team = Team::Blue;
  int id = 0;
  bool operator<(const RobotKey& o) const { return std::tie(team, id) < std::tie(o.team, o.id); }
  bool operator==(const RobotKey& o) const { return team == o.team && id == o.id; }
};

struct TrajectoryPoint {
  double t = 0;
  double truth_x = 0, truth_y = 0;
  std::optional<double> result_x, result_y;  // the result robot of the same identity, if any
};

// One scored frame.
struct FrameScore {
  double stamp = 0;
  Score score;
  bool failed = false;
  std::optional<double> robot_rmse;  // [m] over the matched robots of this frame
  std::optional<double> ball_error;  // [m] matched primary ball
};

class RunEvaluation {
 public:
  explicit RunEvaluation(const ScoreParams& params = {});

  // Scores `result` against `truth` (the same instant) and returns the frame's score.
  FrameScore add(const FrameRecord& truth, const FrameRecord& result);
  // A result frame for which no ground truth exists.
  void addUnscored() { ++unscored_; }
  // The tracker's prediction for a frame (before its measurements) against its truth:
  // one sample per robot with an id that is predicted and visible in the truth.
  void addPrediction(const FrameRecord& truth, const TrackerOutput& prediction);

  const Score& total() const { return total_; }
  std::int64_t failedFrames() const { return failed_; }
  std::int64_t unscoredFrames() const { return unscored_; }
  std::int64_t identitySwitches() const { return switches_; }
  const std::vector<FrameScore>& frames() const { return frames_; }
  const std::map<RobotKey, std::vector<TrajectoryPoint>>& trajectories() const { return trajectories_; }
  // Per predicted frame: (stamp, mean prediction error [m] over its robots).
  const std::vector<std::pair<double, double>>& predictionErrors() const { return prediction_errors_; }
  double predictionRmse() const;  // [m] over all prediction samples (0 without any)

 private:
  ScoreParams params_;
  Score total_;
  std::int64_t failed_ = 0, unscored_ = 0, switches_ = 0;
  std::map<RobotKey, RobotKey> last_identity_;  // truth robot -> identity last seen near it
  std::vector<FrameScore> frames_;
  std::map<RobotKey, std::vector<TrajectoryPoint>> trajectories_;
  std::vector<std::pair<double, double>> prediction_errors_;
  double prediction_sq_ = 0;
  std::int64_t prediction_samples_ = 0;
};

}  // namespace soccer_vision
