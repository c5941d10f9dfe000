#include "soccer_vision/tracking/result_recording.h"

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace soccer_vision {

FrameRecord toFrameRecord(const TrackerOutput& output, const RecordOptions& options) {
  FrameRecord f;
  f.stamp = output.stamp;
  for (const auto& r : output.robots) {
    if (!r.visible && !options.include_unmeasured) continue;
    RobotRecord rec;
    rec.team = r.team;
    rec.id = r.id;
    rec.x = r.x;
    rec.y = r.y;
    rec.theta = r.theta;
    rec.visible = r.visible;
    rec.confidence = r.confidence;
    f.robots.push_back(rec);
  }
  for (const auto& b : output.balls) {
    if (!b.primary && !options.all_balls) continue;
    if (!b.visible && !options.include_unmeasured) continue;
    BallRecord rec;
    rec.x = b.x;
    rec.y = b.y;
    rec.visible = b.visible;
    rec.confidence = b.confidence;
    f.balls.push_back(rec);
  }
  return f;
}

JsonLinesWriter::JsonLinesWriter(const std::string& path, bool append)
    : path_(path), out_(path, append ? std::ios::app : std::ios::trunc) {
  if (!out_) {
    throw std::runtime_error("cannot open '" + path + "' for writing: " + std::strerror(errno));
  }
}

void JsonLinesWriter::write(const FrameRecord& frame) {
  out_ << toJsonLine(frame) << '\n';
  out_.flush();
  if (!out_) throw std::runtime_error("writing '" + path_ + "' failed");
  ++written_;
}

}  // namespace soccer_vision
