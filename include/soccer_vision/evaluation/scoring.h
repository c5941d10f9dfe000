// Scoring per-frame results against ground truth (both FrameRecords), the
// definitions every figure of the project uses:
//  - a result robot *matches* a ground-truth robot of the same team and id whose centre is
//    within max_distance (50 mm) of it; each ground-truth robot is matched at most once;
//  - detection rate = matched / ground-truth robots with visible != false;
//  - precision = matched / result robots that are not excused. A result is excused when
//    it lies within max_distance of a ground-truth robot of the same team and id that is
//    not visible, or when it says it was not measured in this frame (visible false: a
//    track coasting on its prediction) and that robot is not visible in the ground truth:
//    a prediction of a robot out of view claims nothing that could be seen;
//  - an identity error is a result that matches nothing but lies within max_distance of a
//    ground-truth robot of another team or id (also a false positive);
//  - position and heading errors over matched robots (heading: wrapped difference,
//    results without a finite theta left out); balls likewise, without team and id, the
//    first result ball (the primary) only; a coasting ball (visible false) while no
//    ground-truth ball is visible is excused.
#pragma once

#include <cstdint>

#include "soccer_vision/common/exchange_formats.h"

namespace soccer_vision {

struct ScoreParams {
  double max_distance = 0.050;  // [m]
};

struct Score {
  std::int64_t frames = 0;
  std::int64_t truth_robots = 0, result_robots = 0, matched_robots = 0, excused_robots = 0;
  std::int64_t false_robots = 0, identity_errors = 0;
  std::int64_t truth_balls = 0, result_balls = 0, matched_balls = 0, excused_balls = 0, false_balls = 0;
  double robot_sq_error = 0, robot_sq_heading = 0, ball_sq_error = 0;  // [m²], [rad²]
  std::int64_t heading_samples = 0;

  double robotDetectionRate() const;  // 1 when nothing was to be found
  double robotPrecision() const;      // 1 when nothing was reported
  double ballDetectionRate() const;
  double ballPrecision() const;
  double robotPositionRmse() const;  // [m]
  double robotHeadingRmse() const;   // [rad]
  double ballPositionRmse() const;   // [m]
  void add(const Score& other);
};

// The score of one frame.
Score scoreFrame(const FrameRecord& truth, const FrameRecord& result, const ScoreParams& params = {});

}  // namespace soccer_vision
