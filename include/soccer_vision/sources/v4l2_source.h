// The `v4l2` frame source: USB/UVC (and other V4L2 capture) cameras through the Linux V4L2
// API directly: VIDIOC_QUERYCAP, format negotiation over VIDIOC_ENUM_FMT /
// ENUM_FRAMESIZES / ENUM_FRAMEINTERVALS (negotiateV4l2Format), memory-mapped streaming.
//
// Settings: device (default /dev/video0); pixel_format (YUYV, MJPG, RGB3, GREY, RGGB, ...;
// empty = negotiated, see negotiateV4l2Format); buffers (mmap buffers, 4); stamp_delay [s]
// (subtracted from the driver's end-of-frame stamps, or from the receive time when the
// driver gives none; 0). options.width/height/fps are the request (0 = largest/fastest).
// YUYV/UYVY/RGB3/MJPEG frames are converted to bgr8 into the caller's buffer, GREY and Bayer
// are copied as they are (Bayer published as Bayer). Stamps: the driver's buffer timestamp
// (CLOCK_MONOTONIC) converted to the wall clock.
// Controls: "exposure" [µs] (V4L2_CID_EXPOSURE_ABSOLUTE, auto exposure switched to manual)
// and "gain" (V4L2_CID_GAIN, the driver's units), when the device has them. setFps
// restarts streaming with the new VIDIOC_S_PARM frame interval.
// A device that is missing or vanishes (ENODEV) is an open()/grab() error; the caller
// re-opens.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "soccer_vision/sources/frame_source.h"
#include "soccer_vision/sources/v4l2_formats.h"

namespace soccer_vision {

class V4l2Source : public FrameSource {
 public:
  V4l2Source();
  ~V4l2Source() override;

  std::string name() const override { return "v4l2"; }
  OpenResult open(const FrameSourceOptions& options) override;
  void close() override;
  bool isOpen() const override;
  FrameFormat format() const override;
  double fps() const override;
  GrabStatus grab(cv::Mat& image, FrameInfo& info, double timeout_s, std::string& error) override;
  void interrupt() override;
  bool setFps(double fps, std::string& error) override;
  std::vector<std::string> controls() const override;
  std::optional<double> control(const std::string& name) const override;
  bool setControl(const std::string& name, double value, std::string& error) override;
  std::vector<std::pair<std::string, std::string>> statistics() const override;

 private:
  struct Buffer {
    void* start = nullptr;
    std::size_t length = 0;
  };
  struct Control {
    std::uint32_t id = 0;
    double scale = 1;  // control units per API unit (exposure: 1/100 µs)
    double min = 0, max = 0;
  };

  bool startStreaming(std::string& error);
  void stopStreaming();
  void releaseBuffers();
  bool applyFps(double fps, std::string& error);  // VIDIOC_S_PARM, reads back fps_
  std::vector<V4l2Mode> enumerateModes(const V4l2Request& request) const;
  void findControls();

  int fd_ = -1;
  int wake_fd_ = -1;  // eventfd: interrupt() wakes a poll()
  std::string device_;
  std::vector<Buffer> buffers_;
  int buffer_count_ = 4;
  double stamp_delay_ = 0;
  std::uint32_t fourcc_ = 0;
  std::size_t bytes_per_line_ = 0;
  bool streaming_ = false;
  std::string card_, driver_;

  mutable std::mutex mutex_;  // guards everything below and fd_ use from other threads
  bool open_ = false;
  FrameFormat format_;
  double fps_ = 0;
  std::optional<double> pending_fps_;
  std::map<std::string, Control> controls_;
  std::uint64_t frames_ = 0, driver_drops_ = 0, errors_ = 0;
  std::int64_t last_driver_sequence_ = -1;
  std::atomic<bool> interrupted_{false};
};

}  // namespace soccer_vision
