// The standard ROS camera calibration YAML (as written by camera_calibration_parsers /
// camera_calibration and by make_scenario: image_width, image_height, camera_matrix,
// distortion_model, distortion_coefficients, ...) read without ROS, so that core tools
// such as calibrate_field need no ROS libraries.
#pragma once

#include <string>

#include "soccer_vision/common/camera_model.h"

namespace soccer_vision {

// Intrinsics from the YAML text. Accepted distortion models: plumb_bob (5 coefficients,
// fewer are zero-padded), rational_polynomial with k4..k6 = 0, or none/empty. Throws
// std::runtime_error naming `source_name` and the offending key on bad input.
CameraIntrinsics parseCameraInfoYaml(const std::string& yaml_text, const std::string& source_name);
CameraIntrinsics loadCameraInfoYaml(const std::string& path);

// The YAML of these intrinsics (plumb_bob, no rectification) as camera_calibration writes
// it, e.g. intrinsics estimated from the field lines; parseCameraInfoYaml reads it back.
std::string toCameraInfoYaml(const CameraIntrinsics& k, const std::string& camera_name);
void saveCameraInfoYaml(const std::string& path, const CameraIntrinsics& k, const std::string& camera_name);

}  // namespace soccer_vision
