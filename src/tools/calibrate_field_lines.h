// calibrate_field's second mode: the camera from the field lines of one image
// (--image), started from 4 clicked corners (--corners) or approximate correspondences
// (--points); see field_line_calibration.h. Kept apart from calibrate_field.cpp's
// correspondence mode.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace soccer_vision {

struct FieldLineCalibrationOptions {
  std::string image, field = "div_b", camera_info, points, out, out_camera_info, child_frame_id;
  std::vector<double> corners;  // u1, v1, ..., u4, v4
  std::optional<int> camera_id;
  bool estimate_intrinsics = false, principal_point = false, fix_focal_length = false;
  double max_rms = 1.0;
};

// Exit status as calibrate_field's: 0 written, 2 bad input, 3 fit not good enough (advice printed).
int calibrateFromFieldLines(const FieldLineCalibrationOptions& o);

}  // namespace soccer_vision
