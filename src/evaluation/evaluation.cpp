#include "soccer_vision/evaluation/evaluation.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace soccer_vision {

TruthTimeline::TruthTimeline(std::vector<FrameRecord> frames, double tolerance)
    : frames_(std::move(frames)), tolerance_(tolerance) {
  std::stable_sort(frames_.begin(), frames_.end(),
                   [](const FrameRecord& a, const FrameRecord& b) { return a.stamp < b.stamp; });
}

const FrameRecord* TruthTimeline::at(double stamp) const {
  const auto it = std::lower_bound(frames_.begin(), frames_.end(), stamp - tolerance_,
                                   [](const FrameRecord& f, double s) { return f.stamp < s; });
  if (it == frames_.end() || it->stamp > stamp + tolerance_) return nullptr;
  return &*it;
}

RunEvaluation::RunEvaluation(const ScoreParams& params) : params_(params) {}

FrameScore RunEvaluation::add(const FrameRecord& truth, const FrameRecord& result) {
  FrameScore f;
  f.stamp = result.stamp;
  f.score = scoreFrame(truth, result, params_);
  const Score& s = f.score;
  f.failed = s.matched_robots < s.truth_robots || s.false_robots > 0 || s.matched_balls < s.truth_balls ||
             s.false_balls > 0;
  if (s.matched_robots > 0) f.robot_rmse = std::sqrt(s.robot_sq_error / s.matched_robots);
  if (s.matched_balls > 0) f.ball_error = std::sqrt(s.ball_sq_error / s.matched_balls);
  total_.add(s);
  failed_ += f.failed;

  for (const RobotRecord& t : truth.robots) {
    if (!t.visible.value_or(true)) continue;
    const RobotKey key{t.team, t.id};
    // Identity of the nearest result within reach, whatever its label.
    const RobotRecord* nearest = nullptr;
    double best = params_.max_distance;
    for (const RobotRecord& r : result.robots) {
      const double d = std::hypot(r.x - t.x, r.y - t.y);
      if (d <= best) best = d, nearest = &r;
    }
    if (nearest) {
      const RobotKey seen{nearest->team, nearest->id};
      const auto last = last_identity_.find(key);
      if (last != last_identity_.end() && !(last->second == seen)) ++switches_;
      last_identity_[key] = seen;
    }
    TrajectoryPoint p;
    p.t = truth.stamp;
    p.truth_x = t.x;
    p.truth_y = t.y;
    for (const RobotRecord& r : result.robots) {
      if (r.team == t.team && r.id == t.id) {
        p.result_x = r.x;
        p.result_y = r.y;
        break;
      }
    }
    trajectories_[key].push_back(p);
  }
  frames_.push_back(f);
  return f;
}

void RunEvaluation::addPrediction(const FrameRecord& truth, const TrackerOutput& prediction) {
  double sum = 0;
  int n = 0;
  for (const TrackedRobot& p : prediction.robots) {
    if (p.id < 0) continue;
    for (const RobotRecord& t : truth.robots) {
      if (t.team != p.team || t.id != p.id || !t.visible.value_or(true)) continue;
      const double e = std::hypot(p.x - t.x, p.y - t.y);
      sum += e;
      prediction_sq_ += e * e;
      ++prediction_samples_;
      ++n;
      break;
    }
  }
  if (n > 0) prediction_errors_.emplace_back(truth.stamp, sum / n);
}

double RunEvaluation::predictionRmse() const {
  return prediction_samples_ > 0 ? std::sqrt(prediction_sq_ / prediction_samples_) : 0.0;
}

}  // namespace soccer_vision
