// Renders what a calibrated overhead camera sees of a SceneState: carpet, lines, robots
// (cylinders with their marker pattern on top at 150 mm) and balls, anti-aliased by
// analytic pixel coverage, under uneven/drifting/flickering light, with sensor noise,
// motion blur, optional Bayer mosaic and JPEG artefacts. Also renders the per-pixel
// ground-truth class label image. Deterministic for a seed and frame index.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/class_colors.h"
#include "soccer_vision/common/color_class.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/common/robot_pattern.h"
#include "soccer_vision/simulation/calibration_samples.h"
#include "soccer_vision/simulation/scenario.h"
#include "soccer_vision/simulation/scene.h"

namespace soccer_vision {

// Illumination over the field: a smooth spatial gain whose max/min ratio over the
// carpet equals LightingConfig::uneven_ratio, times a slow drift and per-frame flicker.
class IlluminationModel {
 public:
  IlluminationModel(const LightingConfig& config, const FieldGeometry& field, std::uint64_t seed);
  // Spatial part only, at a field point (mean 1 over the field when brightness is 1).
  double spatialGain(double x, double y) const;
  // Global (time) part: drift at time t and flicker of frame `frame_index`.
  double globalGain(double t, std::int64_t frame_index) const;

 private:
  // Unnormalised shape: 1 + a x + b y + a broad Gaussian spot (all drawn from the seed).
  double shape(double x, double y) const;

  LightingConfig config_;
  std::uint64_t seed_;
  double a_ = 0, b_ = 0, spot_x_ = 0, spot_y_ = 0, spot_sigma_ = 1, spot_weight_ = 0;
  // gain = norm_ * uneven_ratio ^ ((shape - shape_min_) / shape_range_), so that the
  // carpet spans exactly [min, uneven_ratio * min].
  double shape_min_ = 0, shape_range_ = 1, norm_ = 1;
  double drift_phase_ = 0;
};

// When, after its capture stamp (the start of the exposure), the scene is that a frame
// shows on average: exposure / 2 with motion blur (sub-exposures spread evenly over the
// exposure), 0 without (the scene at the stamp). What a measurement from that frame
// describes; the tracker's measurement_offset for the synthetic camera.
double shownTimeAfterStamp(const SensorConfig& sensor);

struct RenderedFrame {
  // Output image: CV_8UC3 BGR, or CV_8UC1 Bayer mosaic when SensorConfig::bayer is set.
  // If the caller passes a pre-allocated matrix of the right size and type (e.g. wrapping
  // a message buffer), the renderer draws into it without reallocating.
  cv::Mat image;
  std::string encoding;  // "bgr8" or "bayer_rggb8", ...
};

class FieldRenderer {
 public:
  FieldRenderer(const CameraModel& camera, const FieldGeometry& field, const PatternSet& patterns,
                const ScenarioConfig& scenario);
  ~FieldRenderer();
  FieldRenderer(const FieldRenderer&) = delete;
  FieldRenderer& operator=(const FieldRenderer&) = delete;

  // Renders the frame whose exposure starts at scene.time (the capture stamp).
  void render(const SceneState& scene, std::int64_t frame_index, RenderedFrame& out) const;
  // Per-pixel class of the dominant surface (CV_8UC1 of ColorClass values), noise-free.
  cv::Mat renderLabels(const SceneState& scene) const;

  // Encoding of the images render() produces.
  std::string encoding() const;
  const CameraModel& camera() const;
  // Robot fully in the image (all its markers).
  bool robotVisible(const RobotState& robot) const;
  // The share of the ball's image not hidden behind `robots`; 0 unless it is wholly in the image.
  double ballShown(const BallState& ball, const std::vector<RobotState>& robots) const;
  // Ball fully in the image and at least half of its image not hidden behind `robots`.
  bool ballVisible(const BallState& ball, const std::vector<RobotState>& robots) const;
  // The scene with only the balls nothing hides: what a person calibrating paints (a polygon
  // inside a ball partly behind a robot would take in the robot's side or top).
  SceneState withWhollyVisibleBalls(const SceneState& scene) const;
  // What a person calibrating paints on `scene`: calibrationSamples of this camera, field and
  // patterns, on withWhollyVisibleBalls(scene). The held-out protocol's one painter.
  ColorSamples paintedSamples(const SceneState& scene, const SampleOptions& options = {}) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace soccer_vision
