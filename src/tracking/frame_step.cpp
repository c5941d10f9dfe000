#include "soccer_vision/tracking/frame_step.h"

#include <stdexcept>
#include <string>

namespace soccer_vision {

FrameStep::FrameStep(int step) { setStep(step); }

void FrameStep::setStep(int step) {
  if (step < 1) throw std::invalid_argument("frame_step must be >= 1 (got " + std::to_string(step) + ")");
  step_ = step;
  if (phase_ >= step_) phase_ = 0;
}

void FrameStep::restart() { phase_ = 0; }

bool FrameStep::process() {
  ++seen_;
  const bool take = phase_ == 0;
  phase_ = (phase_ + 1) % step_;
  if (take) ++processed_;
  return take;
}

}  // namespace soccer_vision
