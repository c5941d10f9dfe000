// The field model drawn into a camera image: the painted lines and arcs as pixel polylines
// (sampled along the field, so the lens distortion bends them as it bends the paint), and
// the landmarks (line crossings, corners, centre point) a user clicks for field calibration.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/field_geometry.h"

namespace soccer_vision {

using PixelPolyline = std::vector<Eigen::Vector2d>;

// Every line and arc of `field` through `camera`, cut into pieces where it leaves the image
// (with `margin` px) or passes behind the camera; sampled every `step` metres.
std::vector<PixelPolyline> projectFieldMarkings(const CameraModel& camera, const FieldGeometry& field,
                                                double step = 0.05, double margin = 0.0);

struct LandmarkSuggestion {
  Eigen::Vector3d field;                 // m, on the carpet
  std::optional<Eigen::Vector2d> pixel;  // where the camera sees it, when in the image
};

// The field's landmarks, with their pixels through `camera` when there is one (a first
// estimate to click near); without a camera all landmarks, without pixels.
std::vector<LandmarkSuggestion> suggestLandmarks(const FieldGeometry& field, const CameraModel* camera);

}  // namespace soccer_vision
