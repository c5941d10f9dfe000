// camera_pose.yaml: the result of field calibration (calibrate_field), read by whatever
// publishes the static tf field -> camera_<n>_optical and builds the CameraModel.
//
//   # soccer_vision camera pose: optical frame (z forward, x right, y down) in `field`
//   camera_id: 0                        # optional
//   frame_id: field                     # optional, parent frame
//   child_frame_id: camera_0_optical    # optional
//   translation: {x: -2.24, y: 0.02, z: 4.0}           # m
//   rotation: {x: 0.707, y: 0.707, z: 0.0, w: 0.0}     # unit quaternion, x y z w
//   rms_error_px: 0.012                 # reprojection RMS of the solve (raw pixels)
//   points: 25                          # correspondences used
//   intrinsics: {width: 1280, height: 1024, fx: 800, fy: 800, cx: 639.5, cy: 511.5}
//
// The intrinsics are those the pose was solved with: checkIntrinsicsMatch() rejects a
// pose used with another camera calibration (a different resolution or focal length).
#pragma once

#include <optional>
#include <string>

#include <Eigen/Geometry>

#include "soccer_vision/common/camera_model.h"

namespace soccer_vision {

struct CameraPoseFile {
  std::optional<int> camera_id;
  std::string frame_id = "field";
  std::string child_frame_id;  // empty when not given
  Eigen::Isometry3d field_T_camera = Eigen::Isometry3d::Identity();
  double rms_error_px = 0;
  int points = 0;
  CameraIntrinsics intrinsics;  // width, height, fx, fy, cx, cy (distortion not stored)
};

std::string toYaml(const CameraPoseFile& pose);
// Throws std::runtime_error naming `source_name` for invalid YAML, missing keys,
// non-finite numbers or a quaternion far from unit length (it is normalised otherwise).
CameraPoseFile parseCameraPoseFile(const std::string& yaml_text, const std::string& source_name);
CameraPoseFile loadCameraPoseFile(const std::string& path);
void saveCameraPoseFile(const std::string& path, const CameraPoseFile& pose);

// Throws std::runtime_error (naming `source_name`) when the pose was solved with other
// intrinsics: a different image size, or fx, fy, cx, cy differing by more than
// `tolerance` relative (cx, cy relative to the image size).
void checkIntrinsicsMatch(const CameraPoseFile& pose, const CameraIntrinsics& intrinsics,
                          const std::string& source_name, double tolerance = 1e-3);

// The camera model: these intrinsics (with their distortion) at the file's pose, after
// checkIntrinsicsMatch.
CameraModel cameraModelFromPose(const CameraPoseFile& pose, const CameraIntrinsics& intrinsics,
                                const std::string& source_name);

}  // namespace soccer_vision
