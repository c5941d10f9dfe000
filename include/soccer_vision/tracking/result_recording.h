// Tracker output as the per-frame JSON Lines results (docs/formats.md), so any run (live or from a
// bag) can be scored against ground truth: one FrameRecord per processed frame.
#pragma once

#include <cstddef>
#include <fstream>
#include <string>

#include "soccer_vision/common/exchange_formats.h"
#include "soccer_vision/tracking/tracker.h"

namespace soccer_vision {

struct RecordOptions {
  bool include_unmeasured = true;  // also tracks only predicted in this frame (visible = false)
  bool all_balls = false;          // also the alternative ball tracks (default: the primary only)
};

// Robots (team, id, x, y, theta, confidence, visible) and ball(s) (x, y, confidence,
// visible) at the output's stamp. Team-only tracks keep id -1.
FrameRecord toFrameRecord(const TrackerOutput& output, const RecordOptions& options = {});

// Appends one line per frame and flushes it, so a killed run leaves a readable file.
class JsonLinesWriter {
 public:
  // Truncates (or, with append, extends) `path`; throws std::runtime_error naming it.
  explicit JsonLinesWriter(const std::string& path, bool append = false);
  void write(const FrameRecord& frame);  // throws std::runtime_error when the write fails
  std::size_t written() const { return written_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::ofstream out_;
  std::size_t written_ = 0;
};

}  // namespace soccer_vision
