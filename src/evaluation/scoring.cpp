#include "soccer_vision/evaluation/scoring.h"

#include <cmath>
#include <vector>

#include "soccer_vision/common/angle.h"

namespace soccer_vision {
namespace {

double ratio(std::int64_t a, std::int64_t b) { return b > 0 ? static_cast<double>(a) / b : 1.0; }
double rms(double sum_sq, std::int64_t n) { return n > 0 ? std::sqrt(sum_sq / n) : 0.0; }

// The ground truth shows the robot of this team and id in view.
bool identityVisible(const FrameRecord& truth, const RobotRecord& r) {
  for (const RobotRecord& t : truth.robots) {
    if (t.team == r.team && t.id == r.id && t.visible.value_or(true)) return true;
  }
  return false;
}

}  // namespace

double Score::robotDetectionRate() const { return ratio(matched_robots, truth_robots); }
double Score::robotPrecision() const { return ratio(matched_robots, result_robots - excused_robots); }
double Score::ballDetectionRate() const { return ratio(matched_balls, truth_balls); }
double Score::ballPrecision() const { return ratio(matched_balls, result_balls - excused_balls); }
double Score::robotPositionRmse() const { return rms(robot_sq_error, matched_robots); }
double Score::robotHeadingRmse() const { return rms(robot_sq_heading, heading_samples); }
double Score::ballPositionRmse() const { return rms(ball_sq_error, matched_balls); }

void Score::add(const Score& o) {
  frames += o.frames;
  truth_robots += o.truth_robots;
  result_robots += o.result_robots;
  matched_robots += o.matched_robots;
  excused_robots += o.excused_robots;
  false_robots += o.false_robots;
  identity_errors += o.identity_errors;
  truth_balls += o.truth_balls;
  result_balls += o.result_balls;
  matched_balls += o.matched_balls;
  excused_balls += o.excused_balls;
  false_balls += o.false_balls;
  robot_sq_error += o.robot_sq_error;
  robot_sq_heading += o.robot_sq_heading;
  ball_sq_error += o.ball_sq_error;
  heading_samples += o.heading_samples;
}

Score scoreFrame(const FrameRecord& truth, const FrameRecord& result, const ScoreParams& params) {
  Score s;
  s.frames = 1;
  const double gate2 = params.max_distance * params.max_distance;
  auto d2 = [](double ax, double ay, double bx, double by) {
    return (ax - bx) * (ax - bx) + (ay - by) * (ay - by);
  };

  std::vector<bool> taken(truth.robots.size(), false);
  for (const RobotRecord& t : truth.robots) s.truth_robots += t.visible.value_or(true);
  for (const RobotRecord& r : result.robots) {
    ++s.result_robots;
    // The nearest unmatched ground-truth robot of the same identity within the gate.
    int best = -1;
    double best_d2 = gate2;
    bool near_other = false;
    for (std::size_t i = 0; i < truth.robots.size(); ++i) {
      const RobotRecord& t = truth.robots[i];
      const double e = d2(r.x, r.y, t.x, t.y);
      if (e > gate2) continue;
      if (t.team != r.team || t.id != r.id) {
        near_other = true;
        continue;
      }
      if (!taken[i] && e <= best_d2) {
        best = static_cast<int>(i);
        best_d2 = e;
      }
    }
    if (best < 0) {
      if (!r.visible.value_or(true) && !identityVisible(truth, r)) {
        ++s.excused_robots;
        continue;
      }
      ++s.false_robots;
      s.identity_errors += near_other;
      continue;
    }
    const RobotRecord& t = truth.robots[static_cast<std::size_t>(best)];
    if (!t.visible.value_or(true)) {
      ++s.excused_robots;
      continue;
    }
    taken[static_cast<std::size_t>(best)] = true;
    ++s.matched_robots;
    s.robot_sq_error += best_d2;
    if (std::isfinite(r.theta)) {
      const double e = wrapToPi(r.theta - t.theta);
      s.robot_sq_heading += e * e;
      ++s.heading_samples;
    }
  }

  for (const BallRecord& t : truth.balls) s.truth_balls += t.visible.value_or(true);
  if (!result.balls.empty()) {
    const BallRecord& r = result.balls.front();
    ++s.result_balls;
    int best = -1;
    double best_d2 = gate2;
    for (std::size_t i = 0; i < truth.balls.size(); ++i) {
      const double e = d2(r.x, r.y, truth.balls[i].x, truth.balls[i].y);
      if (e <= best_d2) {
        best = static_cast<int>(i);
        best_d2 = e;
      }
    }
    bool ball_in_view = false;
    for (const BallRecord& t : truth.balls) ball_in_view = ball_in_view || t.visible.value_or(true);
    if (best < 0 && !r.visible.value_or(true) && !ball_in_view) {
      ++s.excused_balls;  // a coasting prediction of a ball out of view
    } else if (best < 0) {
      ++s.false_balls;
    } else if (!truth.balls[static_cast<std::size_t>(best)].visible.value_or(true)) {
      ++s.excused_balls;
    } else {
      ++s.matched_balls;
      s.ball_sq_error += best_d2;
    }
  }
  return s;
}

}  // namespace soccer_vision
