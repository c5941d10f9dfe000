#include "soccer_vision/tracking/stamp_jump_gate.h"

#include <cmath>

namespace soccer_vision {

bool StampJumpGate::accept(double stamp) {
  if (!std::isfinite(stamp)) {
    ++held_;
    return false;
  }
  const bool near_last = !last_ || std::abs(stamp - *last_) <= max_jump_;
  const bool confirms = candidate_ && std::abs(stamp - *candidate_) <= max_jump_;
  if (near_last || confirms) {
    last_ = stamp;
    candidate_.reset();
    return true;
  }
  candidate_ = stamp;
  ++held_;
  return false;
}

}  // namespace soccer_vision
