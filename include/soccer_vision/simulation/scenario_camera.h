// The synthetic camera `index` of a scenario: the built-in camera of its layout of
// `scenario.cameras` (CameraModel::defaultCamera; throws std::invalid_argument for an index
// outside it) with
// the scenario's lens distortion and a tilt from straight down whose direction is drawn
// from the seed. What the renderer draws through and what make_scenario publishes.
#pragma once

#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/simulation/scenario.h"

namespace soccer_vision {

CameraModel scenarioCamera(const FieldGeometry& field, int index, const ScenarioConfig& scenario);

}  // namespace soccer_vision
