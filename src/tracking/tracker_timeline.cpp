#include "soccer_vision/tracking/tracker_timeline.h"

#include <cmath>
#include <stdexcept>

namespace soccer_vision {

void validate(const TimelineParams& p) {
  if (!(p.late_tolerance >= 0) || !std::isfinite(p.late_tolerance)) {
    throw std::invalid_argument("tracker timeline: late_tolerance must be >= 0");
  }
  if (!(p.max_forward_jump > p.late_tolerance) || !std::isfinite(p.max_forward_jump)) {
    throw std::invalid_argument("tracker timeline: max_forward_jump must be > late_tolerance");
  }
}

const char* timeEventName(TimeEvent e) {
  switch (e) {
    case TimeEvent::Start:
      return "start";
    case TimeEvent::InOrder:
      return "in_order";
    case TimeEvent::SameTime:
      return "same_time";
    case TimeEvent::BackwardJump:
      return "backward_jump";
    case TimeEvent::ForwardJump:
      return "forward_jump";
    case TimeEvent::Late:
      return "late";
    case TimeEvent::Stale:
      return "stale";
    case TimeEvent::InvalidStamp:
      return "invalid_stamp";
  }
  return "?";
}

TrackerTimeline::TrackerTimeline(const TimelineParams& params) : p_(params) { validate(p_); }

void TrackerTimeline::clear() {
  cameras_.clear();
  started_ = false;
  now_ = 0;
  backward_reset_ = false;
}

TimeDecision TrackerTimeline::accept(double stamp, int camera_id) {
  TimeDecision d;
  if (!std::isfinite(stamp)) {
    d.action = TimeAction::Drop;
    d.event = TimeEvent::InvalidStamp;
    return d;
  }
  auto commit = [&](const TimeDecision& decision) {
    cameras_[camera_id] = CameraClock{stamp, epoch_};
    return decision;
  };
  if (!started_) {
    started_ = true;
    now_ = stamp;
    d.event = TimeEvent::Start;
    return commit(d);
  }
  const auto it = cameras_.find(camera_id);
  const bool known = it != cameras_.end();
  const bool current = known && it->second.epoch == epoch_;
  auto reset = [&](TimeEvent why) {
    before_reset_newest_ = now_;
    backward_reset_ = why == TimeEvent::BackwardJump;
    ++epoch_;
    now_ = stamp;
    TimeDecision r;
    r.action = TimeAction::Reset;
    r.event = why;
    return commit(r);
  };

  if (current && stamp < it->second.last) return reset(TimeEvent::BackwardJump);
  // A camera that has not spoken since a backward reset may still send its old time line.
  if (known && !current && backward_reset_ && stamp > now_ + p_.late_tolerance &&
      stamp <= before_reset_newest_ + p_.late_tolerance) {
    d.action = TimeAction::Drop;
    d.event = TimeEvent::Stale;
    return d;
  }
  if (stamp > now_ + p_.max_forward_jump) return reset(TimeEvent::ForwardJump);
  if (stamp < now_ - p_.late_tolerance) {
    d.action = TimeAction::Drop;
    d.event = TimeEvent::Late;
    return d;
  }
  if (stamp <= now_) {
    d.event = TimeEvent::SameTime;
    d.lag = now_ - stamp;
    return commit(d);
  }
  d.dt = stamp - now_;
  now_ = stamp;
  return commit(d);
}

}  // namespace soccer_vision
