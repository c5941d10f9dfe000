// Whether the tf of a frame may be published: one image stamped in 2038 once made every tf
// consumer drop the robot frames for the rest of the run (TF_OLD_DATA for every later,
// correct stamp). A stamp that jumps away from the last accepted one is held back until a
// second frame close to it confirms the new time line (a restarted bag or clock); an
// isolated jump is never published.
#pragma once

#include <optional>

namespace soccer_vision {

class StampJumpGate {
 public:
  // max_jump [s]: stamps further than this from the last accepted one (either way) jump.
  explicit StampJumpGate(double max_jump = 1.0) : max_jump_(max_jump) {}

  // True when `stamp` [s] may be published; false for a jump not yet confirmed.
  bool accept(double stamp);
  // Jumped stamps held back so far.
  unsigned long held() const { return held_; }

 private:
  double max_jump_;
  std::optional<double> last_;       // the last accepted stamp
  std::optional<double> candidate_;  // a jumped stamp waiting for confirmation
  unsigned long held_ = 0;
};

}  // namespace soccer_vision
