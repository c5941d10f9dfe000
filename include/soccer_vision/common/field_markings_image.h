// The field's painted lines and arcs (FieldGeometry) as seen through a camera model: points
// along every marking, each with its image pixel, for drawing the field model back into an
// image (detect's overlay) and for fitting a camera to the line pixels of an image
// (calibration from the field lines).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/field_geometry.h"

namespace soccer_vision {

// Points on the centre lines of all markings (z = 0), about `step` metres apart, one
// polyline per line or arc (both end points included).
std::vector<std::vector<Eigen::Vector2d>> fieldMarkingPolylines(const FieldGeometry& field, double step);

// The polylines projected into the image (raw, distorted pixels) and cut where a point does
// not project or lies outside the image by more than `margin` pixels.
std::vector<std::vector<Eigen::Vector2d>> projectFieldMarkings(const CameraModel& camera,
                                                               const FieldGeometry& field, double step = 0.02,
                                                               double margin = 0.0);

}  // namespace soccer_vision
