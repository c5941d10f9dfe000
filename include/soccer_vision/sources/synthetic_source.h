// The `synthetic` frame source: a simulated game (GameSimulator) seen by one of the two
// built-in overhead cameras (CameraModel::defaultCamera) through the FieldRenderer, with
// the true scene as ground truth.
//
// Timing is deterministic: frame k (sequence k) is captured at epoch + k / fps and shows
// scene time k / fps, the simulator always advancing in whole frame periods. grab() sleeps
// until a frame's capture time (real-time pacing); when rendering falls behind by more
// than one period it skips to the newest due frame, like a camera dropping frames. So two
// sources with the same scenario, fps and epoch (cameras 0 and 1) show the same game at
// the same stamps. Changing fps at run time continues the game from the last frame.
//
// Setting `replay_frames` N (0: off): the first N frames are rendered once, before the
// first grab() returns, and then shown forth and back (0, 1, .., N-1, N-2, .., 1, 0, 1, ..),
// each grab() only copying one, just before the frame's capture time (as a camera's DMA).
// A camera whose frames cost a copy, for measuring the vision system at rates the renderer
// cannot reach (2 x 2448x2048 at 75 Hz): positions stay continuous at the turns, where the
// true velocities change sign. The ground truth is the frame's; at most kMaxReplayBytes of
// frames. A fps or control change renders them anew.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/common/robot_pattern.h"
#include "soccer_vision/simulation/scenario.h"
#include "soccer_vision/sources/frame_source.h"

namespace soccer_vision {

class FieldRenderer;
class GameSimulator;

class SyntheticSource : public FrameSource {
 public:
  static constexpr std::size_t kMaxReplayBytes = std::size_t{8} << 30;

  SyntheticSource();
  ~SyntheticSource() override;

  std::string name() const override { return "synthetic"; }
  // Scenario from options.scenario (YAML preset; a file that fails to load is replaced by
  // the embedded default with a warning), fps/width/height overridden when > 0, camera
  // options.camera_index (0 .. the scenario's cameras - 1). Errors: bad camera index, fps, or resolution.
  OpenResult open(const FrameSourceOptions& options) override;
  void close() override;
  bool isOpen() const override;
  FrameFormat format() const override;
  double fps() const override;
  GrabStatus grab(cv::Mat& image, FrameInfo& info, double timeout_s, std::string& error) override;
  void interrupt() override;
  bool setFps(double fps, std::string& error) override;

  // "brightness" (LightingConfig::brightness, 0..10), "noise_sigma" (SensorConfig, 8-bit
  // units, 0..100), "flicker" (LightingConfig, relative std-dev, 0..1).
  std::vector<std::string> controls() const override;
  std::optional<double> control(const std::string& name) const override;
  bool setControl(const std::string& name, double value, std::string& error) override;

  std::optional<CameraIntrinsics> trueIntrinsics() const override;
  std::optional<Eigen::Isometry3d> trueFieldTCamera() const override;

  // The effective scenario (after fallback, overrides and controls) and camera.
  ScenarioConfig scenario() const;
  CameraModel camera() const;
  // Frames skipped because rendering fell behind, since open().
  std::uint64_t droppedFrames() const;

 private:
  struct Pending;
  bool applyPending(std::string& error);  // capture thread only
  // Waits until the system clock reaches `t` (Unix s) or interrupt(); false if interrupted.
  bool waitUntil(double t);
  // Renders the replay's frames from the game's start (capture thread); false if interrupted.
  bool renderReplay(std::string& error);

  // Renders `scene` into `image` (its buffer kept) and sets `encoding` and which robots and
  // balls the frame shows whole; throws what the renderer throws.
  void renderInto(const SceneState& scene, std::int64_t index, cv::Mat& image, std::string& encoding,
                  std::vector<bool>& robot_visible, std::vector<bool>& ball_visible) const;

  struct ReplayFrame {
    cv::Mat image;
    std::string encoding;
    SceneState scene;
    std::vector<bool> robot_visible, ball_visible;
  };
  // Where absolute frame `index` is in the replay: which frame, and whether on the way back.
  struct ReplayPosition {
    const ReplayFrame& frame;
    bool backwards;
  };
  ReplayPosition replayPosition(std::int64_t index) const;

  FieldGeometry field_;
  PatternSet patterns_;
  CameraModel camera_;
  std::unique_ptr<GameSimulator> sim_;
  std::unique_ptr<FieldRenderer> renderer_;
  FrameFormat format_;

  // Timeline: frame n (relative to the base) is captured at base_stamp_ + n * period_,
  // shows scene time base_scene_time_ + n * period_, its absolute index (sequence) is
  // base_index_ + n, and the simulator has been stepped sim_n_ periods since the base.
  double base_stamp_ = 0;
  double base_scene_time_ = 0;
  std::int64_t base_index_ = 0;
  std::int64_t next_n_ = 0;
  std::int64_t sim_n_ = 0;
  bool started_ = false;
  bool produced_ = false;
  double last_stamp_ = 0;
  double last_scene_time_ = 0;
  std::int64_t replay_frames_ = 0;
  std::vector<ReplayFrame> replay_;  // empty until rendered (again after a change)
  double replay_lead_ = 2e-3;        // [s] a copy starts this long before the capture time

  mutable std::mutex mutex_;  // guards everything below
  std::condition_variable wake_;
  bool open_ = false;
  bool interrupted_ = false;
  double period_ = 1.0 / 60.0;
  ScenarioConfig scenario_;
  std::unique_ptr<Pending> pending_;
  std::uint64_t dropped_ = 0;
};

}  // namespace soccer_vision
