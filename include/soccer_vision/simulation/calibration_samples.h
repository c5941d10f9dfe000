// What a person would click for calibration, derived from the simulator's ground truth:
// colour sample polygons inside each visible marker, the ball, the robot tops, the
// carpet and the lines; and pixel <-> field correspondences of the field's landmarks.
#pragma once

#include <cstdint>
#include <vector>

#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/exchange_formats.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/common/robot_pattern.h"
#include "soccer_vision/simulation/scene.h"

namespace soccer_vision {

struct SampleOptions {
  double shrink = 0.6;  // polygons cover this fraction of each marker's size
  // > 0: marker and ball polygons lie this many pixels inside the outline instead (as a
  // user draws them: the held-out protocol, docs/evaluation.md). A marker thinner than
  // twice that gets a 1 px stroke along its middle (a dot or the ball: its centre pixel); one under
  // 2 px across is skipped.
  double inset_px = 0.0;
  double image_margin = 8.0;  // px; polygons closer to the image border are skipped
  int carpet_patches = 8;     // carpet squares to sample

  // As a user draws them (the held-out protocol): polygons `inset_px` inside each marker.
  static SampleOptions drawnByUser(double inset_px) {
    SampleOptions o;
    o.inset_px = inset_px;
    return o;
  }
};

// Polygons in raw pixel coordinates of `camera` for the scene at this instant.
ColorSamples calibrationSamples(const SceneState& scene, const CameraModel& camera,
                                const FieldGeometry& field, const PatternSet& patterns,
                                const SampleOptions& options = {});

// Landmarks of the field (z = 0) that project inside the image, with exact pixels.
std::vector<FieldCorrespondence> fieldCorrespondences(const CameraModel& camera, const FieldGeometry& field,
                                                      double image_margin = 5.0);

// As a user clicks them: each pixel moved by Gaussian noise of `sigma_px` per axis (seeded).
void addClickNoise(std::vector<FieldCorrespondence>& points, double sigma_px, std::uint64_t seed);

}  // namespace soccer_vision
