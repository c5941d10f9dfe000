// The `video` frame source: a video file decoded by OpenCV (FFmpeg back-end) straight into
// the caller's bgr8 buffer.
//
// Settings: file (path, required); realtime (bool, true: paced at the file's frame rate, or
// at options.fps when > 0; false: as fast as the consumer takes them, stamped when read);
// loop (bool, false: EndOfStream after the last frame; true: starts over, the sequence and
// stamps keep increasing). Stamps come from FramePacer: frame n of a run at start + n / fps.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include <opencv2/videoio.hpp>

#include "soccer_vision/sources/frame_pacer.h"
#include "soccer_vision/sources/frame_source.h"

namespace soccer_vision {

class VideoSource : public FrameSource {
 public:
  std::string name() const override { return "video"; }
  OpenResult open(const FrameSourceOptions& options) override;
  void close() override;
  bool isOpen() const override;
  FrameFormat format() const override;
  double fps() const override;
  GrabStatus grab(cv::Mat& image, FrameInfo& info, double timeout_s, std::string& error) override;
  void interrupt() override;
  bool setFps(double fps, std::string& error) override;
  std::vector<std::pair<std::string, std::string>> statistics() const override;

  // The file's own frame rate (0 when the container does not say).
  double fileFps() const;

 private:
  bool reopenFile(std::string& error);

  mutable std::mutex mutex_;  // guards the state read by other threads
  cv::VideoCapture capture_;
  std::string file_;
  bool open_ = false;
  bool realtime_ = true;
  bool loop_ = false;
  double file_fps_ = 0;
  FrameFormat format_;
  FramePacer pacer_;
  std::uint64_t sequence_ = 0;
  std::uint64_t loops_ = 0;
  std::int64_t file_frames_ = 0;  // frames the container announces (0 = unknown)
};

}  // namespace soccer_vision
