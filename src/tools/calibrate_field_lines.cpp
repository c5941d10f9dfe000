#include "calibrate_field_lines.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>

#include "soccer_vision/calibration/field_line_calibration.h"
#include "soccer_vision/common/camera_info_yaml.h"
#include "soccer_vision/common/camera_pose_file.h"
#include "soccer_vision/common/exchange_formats.h"

namespace soccer_vision {

namespace {

std::vector<Eigen::Vector2d> cornerPixels(const std::vector<double>& uv) {
  std::vector<Eigen::Vector2d> out;
  for (std::size_t i = 0; i + 1 < uv.size(); i += 2) out.emplace_back(uv[i], uv[i + 1]);
  return out;
}

}  // namespace

int calibrateFromFieldLines(const FieldLineCalibrationOptions& o) {
  if (o.corners.empty() == o.points.empty())
    throw std::invalid_argument(
        "give the start: --corners (4 clicked corners) or --points (field_points.yaml)");
  if (o.fix_focal_length && o.camera_info.empty())
    throw std::invalid_argument("--fix-focal-length keeps the focal length of --camera-info: give it");
  if (o.camera_info.empty() && !o.estimate_intrinsics)
    throw std::invalid_argument(
        "without --camera-info the intrinsics must be estimated: add --estimate-intrinsics");
  const cv::Mat image = cv::imread(o.image, cv::IMREAD_COLOR);
  if (image.empty()) throw std::runtime_error(o.image + ": not a readable image");
  const FieldGeometry field = fieldGeometryByName(o.field);
  CameraIntrinsics k;
  if (!o.camera_info.empty()) {
    k = loadCameraInfoYaml(o.camera_info);
    if (k.width != image.cols || k.height != image.rows)
      throw std::runtime_error(o.camera_info + ": camera is " + std::to_string(k.width) + "x" +
                               std::to_string(k.height) + ", " + o.image + " is " +
                               std::to_string(image.cols) + "x" + std::to_string(image.rows));
  } else {
    // A start only: a lens of about 70° horizontal field of view; the fit finds the focal length.
    k.width = image.cols;
    k.height = image.rows;
    k.fx = k.fy = 0.7 * image.cols;
    k.cx = (image.cols - 1) / 2.0;
    k.cy = (image.rows - 1) / 2.0;
  }
  const auto pixels = detectFieldLinePixels(image);
  std::printf("%zu line pixels found in %s\n", pixels.size(), o.image.c_str());
  const CameraModel start =
      o.corners.empty()
          ? initialModelFromPoints(k, loadFieldCorrespondences(o.points), o.estimate_intrinsics)
          : initialModelFromCorners(k, cornerPixels(o.corners), field, pixels, o.estimate_intrinsics);
  FieldLineFitParams params;
  params.estimate_intrinsics = o.estimate_intrinsics;
  params.estimate_principal_point = o.principal_point;
  params.estimate_focal_length = !o.fix_focal_length;
  const FieldLineFit fit = fitCameraToFieldLines(pixels, field, start, params);
  const CameraIntrinsics& fk = fit.camera.intrinsics();
  const Eigen::Vector3d t = fit.camera.cameraCentre();
  const Eigen::Quaterniond q(fit.camera.fieldTCamera().linear());
  std::printf("paired %d line pixels, %d within 3 px; line coverage %.0f %%\n", fit.pixels_paired,
              fit.pixels_within_3px, 100 * fit.coverage);
  std::printf("across-line RMS %.3f px\n", fit.rms_px);
  std::printf("camera centre in field: (%.4f, %.4f, %.4f) m, rotation xyzw (%.6f, %.6f, %.6f, %.6f)\n", t.x(),
              t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
  std::printf("intrinsics: fx %.2f fy %.2f cx %.2f cy %.2f k1 %.5f k2 %.5f%s\n", fk.fx, fk.fy, fk.cx, fk.cy,
              fk.dist[0], fk.dist[1], o.estimate_intrinsics ? " (estimated)" : "");
  const std::string advice = fieldLineFitAdvice(fit, o.estimate_intrinsics, o.max_rms);
  if (fit.rms_px > o.max_rms) {
    std::cerr << "calibrate_field: " << advice << "; not writing " << o.out << "\n";
    return 3;
  }
  if (!advice.empty()) std::cerr << "calibrate_field: warning: " << advice << "\n";
  CameraPoseFile file;
  file.camera_id = o.camera_id;
  file.child_frame_id = o.child_frame_id;
  file.field_T_camera = fit.camera.fieldTCamera();
  file.rms_error_px = fit.rms_px;
  file.points = fit.pixels_within_3px;
  file.intrinsics = fk;
  saveCameraPoseFile(o.out, file);
  std::printf("wrote %s\n", o.out.c_str());
  if (o.estimate_intrinsics) {
    std::string info_path = o.out_camera_info;
    if (info_path.empty()) {
      const std::size_t dot = o.out.rfind(".yaml");
      info_path = (dot == std::string::npos ? o.out : o.out.substr(0, dot)) + ".camera_info.yaml";
    }
    saveCameraInfoYaml(info_path, fk, o.camera_id ? "camera_" + std::to_string(*o.camera_id) : "camera");
    std::printf("wrote %s (use it as the camera's camera_info: the pose belongs to these intrinsics)\n",
                info_path.c_str());
  }
  return 0;
}

}  // namespace soccer_vision
