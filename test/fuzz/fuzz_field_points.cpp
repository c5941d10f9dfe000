// Field points YAML -> the camera pose solver (calibrate_field's path).
#include "fuzz_target.h"
#include "soccer_vision/calibration/camera_pose_solver.h"
#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/exchange_formats.h"
#include "soccer_vision/common/field_geometry.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const soccer_vision::CameraIntrinsics intrinsics =
      soccer_vision::CameraModel::defaultCamera(soccer_vision::FieldGeometry{}, 0).intrinsics();
  try {
    const auto points =
        soccer_vision::parseFieldCorrespondences(soccer_vision_fuzz::asText(data, size), "fuzz");
    if (points.size() <= 64) soccer_vision::solveCameraPose(intrinsics, points);
  } catch (const std::exception&) {
  }
  return 0;
}
