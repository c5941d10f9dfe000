#include "soccer_vision/ssl/kicked_ball.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace soccer_vision::ssl {

void validate(const KickedBallParams& p) {
  auto require = [](bool ok, const char* name) {
    if (!ok) throw std::invalid_argument(std::string("kicked ball parameter ") + name + " out of range");
  };
  require(std::isfinite(p.min_speed) && p.min_speed > 0, "min_speed");
  require(std::isfinite(p.min_speed_gain) && p.min_speed_gain > 0, "min_speed_gain");
  require(std::isfinite(p.max_output_gap) && p.max_output_gap > 0, "max_output_gap");
  require(std::isfinite(p.stop_speed) && p.stop_speed >= 0 && p.stop_speed < p.min_speed, "stop_speed");
  require(std::isfinite(p.rolling_deceleration) && p.rolling_deceleration > 0, "rolling_deceleration");
  require(std::isfinite(p.kicker_reach) && p.kicker_reach >= 0, "kicker_reach");
}

KickedBallEstimator::KickedBallEstimator(const KickedBallParams& params) : p_(params) { validate(p_); }

const std::optional<KickedBallEstimate>& KickedBallEstimator::update(const TrackerOutput& output) {
  const TrackedBall* ball = output.primaryBall();
  if (!ball) {
    last_.reset();
    kick_.reset();
    return kick_;
  }
  const BallState now{output.stamp, {ball->x, ball->y}, {ball->vx, ball->vy}};
  const double speed = now.velocity.norm();
  const bool comparable = last_ && now.stamp > last_->stamp && now.stamp - last_->stamp <= p_.max_output_gap;
  if (comparable && speed >= p_.min_speed && speed - last_->velocity.norm() >= p_.min_speed_gain) {
    KickedBallEstimate k;
    k.start_position = last_->position;
    k.start_time = last_->stamp;
    k.velocity = {now.velocity.x(), now.velocity.y(), 0.0};
    double nearest = std::numeric_limits<double>::infinity();
    for (const TrackedRobot& r : output.robots) {
      const double d = (Eigen::Vector2d(r.x, r.y) - k.start_position).norm();
      if (r.id >= 0 && d <= p_.kicker_reach && d < nearest) {
        nearest = d;
        k.kicker_team = r.team;
        k.kicker_id = r.id;
      }
    }
    kick_ = k;
  }
  if (kick_ && speed < p_.stop_speed) kick_.reset();
  if (kick_) {
    // Constant deceleration from the current state: stops after v / a, v² / 2a further on.
    const double to_stop = speed / p_.rolling_deceleration;
    kick_->stop_time = now.stamp + to_stop;
    kick_->stop_position =
        now.position + (speed > 0 ? Eigen::Vector2d(now.velocity / speed) : Eigen::Vector2d::Zero()) *
                           (speed * speed / (2 * p_.rolling_deceleration));
  }
  last_ = now;
  return kick_;
}

}  // namespace soccer_vision::ssl
