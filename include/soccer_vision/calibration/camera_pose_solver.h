// Camera pose in `field` from >= 4 pixel <-> field correspondences (docs/formats.md
// field_points.yaml): the pixels are undistorted through the intrinsics, an initial pose
// comes from OpenCV (IPPE for coplanar points, which gives both planar solutions; SQPnP
// otherwise), and every candidate is refined by Levenberg-Marquardt on the reprojection
// error in RAW pixels through CameraModel::project, so the distortion model is the one
// the rest of the pipeline uses. The candidate with the smallest error wins.
#pragma once

#include <vector>

#include <Eigen/Geometry>

#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/exchange_formats.h"

namespace soccer_vision {

struct CameraPoseSolverParams {
  int max_iterations = 100;       // Levenberg-Marquardt iterations
  double convergence = 1e-12;     // stop when the relative cost decrease is below this
  double min_spread = 0.01;       // m: field points closer to a line than this are collinear
  double min_pixel_spread = 2.0;  // px: the same for the pixels (camera in the points' plane)
};

struct CameraPoseSolution {
  Eigen::Isometry3d field_T_camera = Eigen::Isometry3d::Identity();  // optical frame in `field`
  std::vector<double> errors_px;  // reprojection error per correspondence (raw pixels)
  double rms_px = 0;              // root mean square of errors_px
  double max_px = 0;
  int iterations = 0;           // LM iterations of the winning candidate
  CameraIntrinsics intrinsics;  // what it was solved with

  CameraModel model() const { return CameraModel(intrinsics, field_T_camera); }
};

// Throws std::invalid_argument for < 4 correspondences, non-finite values, intrinsics
// without a focal length, field points (or pixels) on one line, or when no pose puts the
// points in front of the camera.
CameraPoseSolution solveCameraPose(const CameraIntrinsics& intrinsics,
                                   const std::vector<FieldCorrespondence>& points,
                                   const CameraPoseSolverParams& params = {});

// Reprojection error of each correspondence for a given camera (raw pixels; +inf when
// a point is behind the camera).
std::vector<double> reprojectionErrors(const CameraModel& camera,
                                       const std::vector<FieldCorrespondence>& points);

}  // namespace soccer_vision
