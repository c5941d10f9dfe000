// The `aravis` frame source: GigE Vision and USB3 Vision industrial cameras through Aravis
// 0.8 (Debian libaravis-dev). Tested against Aravis's fake GigE camera
// (arv-fake-gv-camera-0.8 -i 127.0.0.1), so the real code path runs in CI.
//
// Settings: camera (IP address: opened directly, no discovery; or Aravis device id such as
// "Aravis-Fake-GV01" / serial: found by a GigE discovery broadcast on every interface;
// empty = the first camera found, also by discovery); pixel_format (GenICam name: Mono8, BayerRG8, BayerGR8,
// BayerGB8, BayerBG8, RGB8, BGR8, Mono16, BayerRG16, ...; empty = the camera's current);
// packet_size (GigE bytes; 0 = negotiate the largest that gets through, -1 = leave as is);
// buffers (stream buffers, 8); stamp_delay [s] (subtracted from stamps; 0); frame_timeout
// [s] (no frame for this long is an error, so the caller re-opens; 5, 0 = never).
// options.width/height set the region of interest from the sensor's top-left corner (0 =
// the camera's current), options.fps the frame rate (0 = the camera's current).
// Controls: "exposure" [µs] and "gain" (the camera's Gain, usually dB), auto modes switched
// off when set; applied by the capture thread at the next frame and read back (control()
// gives the queued value until then, the camera's afterwards).
// Stamps: the camera's timestamp (ns) mapped to the wall clock by the smallest
// (receive - camera) offset of the recent frames (transfer latency and clock offset), or,
// without camera stamps, the receive time; minus stamp_delay. A camera whose control
// channel is lost (unplugged, powered off: Aravis "control-lost") makes grab() fail; the
// caller re-opens it when it is back.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "soccer_vision/sources/frame_source.h"

namespace soccer_vision {

// ROS encoding of a GenICam pixel format name ("BayerRG8" -> "bayer_rggb8"); empty when the
// format cannot be published as it is.
std::string encodingForGenicamPixelFormat(const std::string& pixel_format);

// Maps device timestamps to the wall clock by the smallest (receive - device) offset over
// the last `window` frames; a jump of the offset by more than `reset_s` (camera restarted,
// clock set) starts over.
class DeviceClockMapper {
 public:
  explicit DeviceClockMapper(std::size_t window = 64, double reset_s = 1.0)
      : window_(window), reset_s_(reset_s) {}
  void reset() { offsets_.clear(); }
  // Wall time of a frame stamped `device_s` by the device and received at `receive_s`.
  double map(double device_s, double receive_s);

 private:
  std::size_t window_;
  double reset_s_;
  std::vector<double> offsets_;  // oldest first
};

class AravisSource : public FrameSource {
 public:
  AravisSource();
  ~AravisSource() override;

  std::string name() const override { return "aravis"; }
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
  struct Impl;  // Aravis/GLib objects stay out of this header
  std::unique_ptr<Impl> impl_;
};

}  // namespace soccer_vision
