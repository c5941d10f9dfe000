// The tracker's clock: decides, for each camera frame, whether it moves time forward, is
// treated as simultaneous with the newest frame, is dropped, or starts a new time line.
//
// Rules (frame of camera c with capture stamp s; `now` = newest stamp processed):
//  - s not finite                                  -> Drop (InvalidStamp)
//  - s older than c's previous frame               -> Reset (BackwardJump: looped bag, restart)
//  - s > now + max_forward_jump                    -> Reset (ForwardJump: bag skipped, paused)
//  - s in [now - late_tolerance, now]              -> Process at `now` (SameTime; lag = now - s)
//  - s < now - late_tolerance                      -> Drop (Late: another camera ran ahead)
//  - otherwise                                     -> Process, time advances by s - now
// Filters are only ever predicted forward: a slightly older frame (cameras are not
// synchronised: up to half a frame apart) is applied at `now`, its positions moved
// forward by the track's velocity × lag by the tracker, and the filters add the velocity's
// uncertainty and the accelerations over the lag to its noise. So a camera whose frame was
// delayed by a busy machine (a scheduling hiccup of tens of ms) still counts; only frames
// older than late_tolerance are dropped. After a backward reset, frames
// of the other cameras from the old time line (not newer than the newest stamp seen before
// the reset) are dropped as Stale instead of resetting again, until that camera too
// delivers a frame of the new time line.
#pragma once

#include <map>

namespace soccer_vision {

struct TimelineParams {
  double late_tolerance = 0.1;    // [s] frames at most this much older than `now` are fused
  double max_forward_jump = 1.0;  // [s] larger forward steps reset all tracks
};

void validate(const TimelineParams& p);  // throws std::invalid_argument

enum class TimeAction { Process, Reset, Drop };
enum class TimeEvent { Start, InOrder, SameTime, BackwardJump, ForwardJump, Late, Stale, InvalidStamp };
const char* timeEventName(TimeEvent e);

struct TimeDecision {
  TimeAction action = TimeAction::Process;
  TimeEvent event = TimeEvent::InOrder;
  double dt = 0;   // [s] how far `now` advanced (0 for SameTime, Reset, Drop)
  double lag = 0;  // [s] now - stamp for SameTime frames (>= 0), else 0
};

class TrackerTimeline {
 public:
  explicit TrackerTimeline(const TimelineParams& params = {});

  // Decides and commits (the clock moves on Process/Reset).
  TimeDecision accept(double stamp, int camera_id);
  void clear();  // forget everything: the next frame is a Start

  bool started() const { return started_; }
  double now() const { return now_; }
  int resets() const { return epoch_; }
  const TimelineParams& params() const { return p_; }
  void setParams(const TimelineParams& p) { p_ = p; }

 private:
  struct CameraClock {
    double last = 0;
    int epoch = 0;
  };
  TimelineParams p_;
  std::map<int, CameraClock> cameras_;
  bool started_ = false;
  double now_ = 0;
  int epoch_ = 0;
  double before_reset_newest_ = 0;
  bool backward_reset_ = false;
};

}  // namespace soccer_vision
