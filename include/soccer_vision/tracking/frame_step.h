// `frame_step` (paper §III-C): process every n-th frame of a camera, skip the
// others. One per camera stream; n = 1 processes everything.
#pragma once

namespace soccer_vision {

class FrameStep {
 public:
  explicit FrameStep(int step = 1);  // throws std::invalid_argument for step < 1

  // Call once per incoming frame: true for frames 0, n, 2n, ... since the last restart().
  bool process();
  void restart();          // the next frame is processed
  void setStep(int step);  // takes effect from the next frame; throws for < 1
  int step() const { return step_; }
  long seen() const { return seen_; }
  long processed() const { return processed_; }

 private:
  int step_ = 1;
  int phase_ = 0;  // frames since the last processed one
  long seen_ = 0, processed_ = 0;
};

}  // namespace soccer_vision
