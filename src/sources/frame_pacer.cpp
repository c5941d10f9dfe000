#include "soccer_vision/sources/frame_pacer.h"

#include <algorithm>
#include <chrono>

namespace soccer_vision {

double systemClockNow() {
  using namespace std::chrono;
  return duration<double>(system_clock::now().time_since_epoch()).count();
}

void FramePacer::start(double fps) {
  std::lock_guard<std::mutex> lock(mutex_);
  period_ = fps > 0 ? 1.0 / fps : 0.0;
  rate_changed_ = false;
  interrupted_ = false;
  started_ = false;
  n_ = 0;
  last_ = 0;
}

bool setPacedFps(FramePacer& pacer, bool realtime, const std::string& source_name, double fps,
                 std::string& error) {
  if (!realtime) {
    error = "the " + source_name + " source runs as fast as possible (realtime false): no frame rate to set";
    return false;
  }
  if (!(fps > 0) || fps > 1000) {
    error = "fps " + std::to_string(fps) + " out of range (0, 1000]";
    return false;
  }
  pacer.setFps(fps);
  return true;
}

void FramePacer::setFps(double fps) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    period_ = fps > 0 ? 1.0 / fps : 0.0;
    rate_changed_ = true;
  }
  wake_.notify_all();
}

double FramePacer::fps() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return period_ > 0 ? 1.0 / period_ : 0.0;
}

void FramePacer::interrupt() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    interrupted_ = true;
  }
  wake_.notify_all();
}

FramePacer::Wait FramePacer::wait(double timeout_s, double& stamp) {
  std::unique_lock<std::mutex> lock(mutex_);
  const double deadline = systemClockNow() + std::max(0.0, timeout_s);
  for (;;) {
    if (interrupted_) return Wait::Interrupted;
    const double now = systemClockNow();
    if (rate_changed_) {
      rate_changed_ = false;
      if (started_) {
        base_ = last_;
        n_ = 1;
      }
    }
    if (period_ <= 0) {
      // Free-running: stamped now, kept strictly increasing.
      stamp = std::max(now, last_ + 1e-6);
      last_ = stamp;
      started_ = true;
      return Wait::Due;
    }
    if (!started_) {
      base_ = now;
      n_ = 0;
      started_ = true;
    }
    double due = base_ + static_cast<double>(n_) * period_;
    if (now >= due) {
      if (now - due > period_) {  // behind: re-base instead of bursting
        base_ = now;
        n_ = 0;
        due = now;
      }
      stamp = due;
      last_ = due;
      ++n_;
      return Wait::Due;
    }
    if (now >= deadline) return Wait::Timeout;
    wake_.wait_for(lock, std::chrono::duration<double>(std::min(due, deadline) - now));
  }
}

}  // namespace soccer_vision
