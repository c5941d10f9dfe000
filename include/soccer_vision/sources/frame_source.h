// Camera back-ends behind one ROS-free interface (docs/cameras.md): the
// CameraDriver nodelet opens a source by name (parameter `source`), asks for the frame
// format, allocates the message buffer itself and lets the source write each frame into a
// cv::Mat that wraps that buffer (allocate-then-wrap: zero copy from back-end to topic).
//
// Threading: open/close/grab/format are called from one capture thread. interrupt(),
// setFps() and setControl() may be called from any thread at any time; settings take
// effect at the next frame.
//
// Time: FrameInfo::stamp is the capture time (start of exposure) in seconds on the system
// (Unix, wall) clock, which is what ROS wall time uses. Back-ends whose hardware stamps use
// another clock (v4l2: CLOCK_MONOTONIC, aravis: camera ticks) convert before returning.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/simulation/scene.h"

namespace soccer_vision {

// What the caller needs to allocate a frame buffer. A buffer of `step * height` bytes,
// wrapped as cv::Mat(height, width, cv_type, data, step), receives one frame.
struct FrameFormat {
  int width = 0;
  int height = 0;
  std::string encoding;  // ROS sensor_msgs/image_encodings name: "bgr8", "bayer_rggb8", ...
  int cv_type = -1;      // OpenCV type of one pixel row element, e.g. CV_8UC3
  std::size_t step = 0;  // bytes per row (>= width * bytes per pixel)

  std::size_t bytes() const { return step * static_cast<std::size_t>(height); }
  bool valid() const { return width > 0 && height > 0 && cv_type >= 0 && step > 0; }
};

// Everything needed to open a back-end. Fields a back-end does not use are ignored.
struct FrameSourceOptions {
  int camera_index = 0;  // which camera (synthetic: of the scenario's layout, CameraModel::defaultCamera)
  double fps = 0;        // requested frame rate [Hz]; 0 = the back-end's native rate
  int width = 0;         // requested resolution [px]; 0 = the back-end's native size
  int height = 0;
  // Synthetic: scenario preset YAML path; empty = the embedded default scenario.
  std::string scenario;
  // Synthetic: time origin (Unix s) of frame 0; frame k is captured at epoch + k / fps and
  // shows scene time k / fps. 0 = now. Two sources with the same epoch, scenario and fps
  // show the same game at the same stamps (e.g. cameras 0 and 1 of one field).
  double epoch = 0;
  // Back-end specific settings (device path, URL, file name, camera serial, ...).
  std::map<std::string, std::string> settings;
};

// Outcome of open(): ok, or not with `error` saying why in one sentence. `warnings` lists
// what was degraded but still works (e.g. a bad scenario path replaced by the default).
struct OpenResult {
  bool ok = false;
  std::string error;
  std::vector<std::string> warnings;
};

// Metadata of one grabbed frame.
struct FrameInfo {
  double stamp = 0;                        // capture time (start of exposure), Unix seconds
  std::uint64_t sequence = 0;              // frame counter of the back-end; gaps = dropped frames
  std::string encoding;                    // encoding of this frame (equals format().encoding)
  std::optional<SceneState> ground_truth;  // true scene at `stamp` (synthetic sources)
  // Per ground-truth robot / ball (same order): fully inside this frame (all markers /
  // the whole ball), as FieldRenderer::robotVisible / ballVisible.
  std::vector<bool> robot_visible;
  std::vector<bool> ball_visible;
};

enum class GrabStatus {
  Ok,           // a frame was written into the buffer, `info` is filled
  Timeout,      // no frame this time (try again)
  Interrupted,  // interrupt() was called
  EndOfStream,  // file back-ends: nothing more to read
  Error,        // `error` says what went wrong; the caller may close() and re-open()
};

const char* grabStatusName(GrabStatus s);

class FrameSource {
 public:
  virtual ~FrameSource() = default;

  // Back-end name as used by the factory ("synthetic", ...).
  virtual std::string name() const = 0;

  // Opens the device/file/simulation. May block for a while (hardware), so call it from the
  // capture thread. Opening an open source re-opens it.
  virtual OpenResult open(const FrameSourceOptions& options) = 0;
  virtual void close() = 0;
  virtual bool isOpen() const = 0;

  // Format of the frames grab() writes; valid while open.
  virtual FrameFormat format() const = 0;
  // Current frame rate [Hz] (0 when free-running or unknown).
  virtual double fps() const = 0;

  // Waits for the next frame (at most `timeout_s`), writes it into `image` and fills
  // `info`. `image` must wrap a caller-owned buffer of format(): the source writes into
  // that memory and never reallocates it. Returns why it did not deliver a frame otherwise.
  virtual GrabStatus grab(cv::Mat& image, FrameInfo& info, double timeout_s, std::string& error) = 0;

  // Makes a blocked or the next grab() return Interrupted promptly (shutdown).
  virtual void interrupt() = 0;

  // Changes the frame rate at the next frame. False (and `error`) when not supported.
  virtual bool setFps(double fps, std::string& error) = 0;

  // Named controls (synthetic: "brightness", "noise_sigma", "flicker"), applied at the next
  // frame. controls() lists the supported names; setControl() returns false with `error`
  // for unknown names or out-of-range values.
  virtual std::vector<std::string> controls() const { return {}; }
  virtual std::optional<double> control(const std::string& /*name*/) const { return std::nullopt; }
  virtual bool setControl(const std::string& name, double /*value*/, std::string& error) {
    error = "source '" + this->name() + "' has no control '" + name + "'";
    return false;
  }

  // Back-end counters and facts for diagnostics (e.g. aravis stream statistics), as
  // name/value pairs. Thread-safe.
  virtual std::vector<std::pair<std::string, std::string>> statistics() const { return {}; }

  // True intrinsics/distortion and pose (field_T_optical) when the back-end knows them
  // (synthetic); real cameras return nullopt and rely on calibration files.
  virtual std::optional<CameraIntrinsics> trueIntrinsics() const { return std::nullopt; }
  virtual std::optional<Eigen::Isometry3d> trueFieldTCamera() const { return std::nullopt; }
};

using FrameSourceFactory = std::function<std::unique_ptr<FrameSource>()>;

// Creates a source by name; nullptr with `error` (listing the known names) if unknown.
std::unique_ptr<FrameSource> createFrameSource(const std::string& name, std::string& error);
// Names createFrameSource() knows, sorted.
std::vector<std::string> frameSourceNames();
// Adds or replaces a back-end (plugins, tests). Thread-safe.
void registerFrameSource(const std::string& name, FrameSourceFactory factory);

// Encoding helpers (ROS encoding names, no ROS dependency).
// OpenCV type of an encoding, or -1 when unknown.
int cvTypeForEncoding(const std::string& encoding);

}  // namespace soccer_vision
