// Real-time pacing for file sources (video, images): frame n of a run is due at
// base + n / fps on the system clock, and that due time is the frame's stamp, so stamps are
// evenly spaced and strictly increasing. Falling behind by more than one period re-bases the
// timeline at "now" (no burst to catch up; every file frame is still delivered). fps <= 0
// is free-running: each frame is due at once and stamped with the time it is handed out.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>

namespace soccer_vision {

class FramePacer {
 public:
  enum class Wait { Due, Timeout, Interrupted };

  // Starts a new timeline (the first frame is due at the first wait()). Clears interrupt().
  void start(double fps);
  // New rate from the next frame on: the next frame is due one new period after the last.
  // Thread-safe.
  void setFps(double fps);
  double fps() const;
  // Waits until the next frame is due (at most timeout_s): Due with its stamp (Unix s), or
  // Timeout (the frame stays due), or Interrupted.
  Wait wait(double timeout_s, double& stamp);
  // Makes a waiting and every later wait() return Interrupted until start(). Thread-safe.
  void interrupt();

 private:
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  double period_ = 0;  // 0: free-running
  bool rate_changed_ = false;
  bool interrupted_ = false;
  bool started_ = false;
  double base_ = 0;
  std::int64_t n_ = 0;
  double last_ = 0;
};

double systemClockNow();  // Unix seconds

// FrameSource::setFps of the file sources: refused (false, `error`) when the source runs
// as fast as possible (realtime false) or fps is outside (0, 1000]; else pacer.setFps.
bool setPacedFps(FramePacer& pacer, bool realtime, const std::string& source_name, double fps,
                 std::string& error);

}  // namespace soccer_vision
