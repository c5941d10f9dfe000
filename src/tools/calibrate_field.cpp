// calibrate_field: the camera's pose in `field` from >= 4 pixel <-> field correspondences
// (field_points.yaml, raw distorted pixels) and the camera's intrinsics (the
// standard ROS camera calibration YAML, e.g. camera_info.yaml of make_scenario or of
// camera_calibration). Prints the reprojection error of every point and the RMS, and
// writes camera_pose.yaml (see include/soccer_vision/common/camera_pose_file.h) from which the
// static tf field -> camera_<n>_optical is published.
//
//   rosrun soccer_vision calibrate_field --camera-info camera_info.yaml
//       --points field_points.yaml --out camera_pose.yaml
//       [--camera-id N] [--child-frame-id camera_N_optical] [--max-rms PX]
//
// With --image, from the field lines of that image (calibrate_field_lines.h), started from
// 4 clicked corners or the --points:
//
//   rosrun soccer_vision calibrate_field --image IMG --field div_b [--camera-info C.yaml]
//       [--estimate-intrinsics [--principal-point] [--fix-focal-length]] (--corners u,v,... | --points
//       P.yaml)
//       --out camera_pose.yaml [--out-camera-info C.yaml]   (--max-rms default 1 px)
//
// Exit status: 0 on success; 2 for bad arguments, unreadable or invalid files, degenerate
// correspondences (< 4, collinear, non-finite) or an unwritable output; 3 when the RMS
// reprojection error exceeds --max-rms (default 2 px: wrong correspondences); the pose is
// not written then.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>

#include "calibrate_field_lines.h"
#include "soccer_vision/calibration/camera_pose_solver.h"
#include "soccer_vision/common/camera_info_yaml.h"
#include "soccer_vision/common/camera_pose_file.h"
#include "soccer_vision/common/exchange_formats.h"
#include "tool_command_line.h"

namespace sv = soccer_vision;

namespace {

struct Options {
  std::string camera_info, points, out, child_frame_id;
  std::optional<int> camera_id;
  std::optional<double> max_rms;          // default 2 px (points), 1 px (field lines)
  sv::FieldLineCalibrationOptions lines;  // the --image mode
};

void addOptions(CLI::App& app, Options& o) {
  app.add_option("--camera-info", o.camera_info,
                 "the camera's intrinsics (camera_info YAML); with --image: the starting intrinsics");
  app.add_option("--points", o.points,
                 "pixel <-> field correspondences (field points YAML); with --image: instead of --corners");
  app.add_option("--out", o.out, "the camera pose to write (YAML)")->required();
  app.add_option_function<int>(
         "--camera-id", [&o](const int& id) { o.camera_id = id; },
         "camera id (names the child frame camera_<id>_optical)")
      ->check(CLI::Range(0, 255));
  app.add_option("--child-frame-id", o.child_frame_id, "tf child frame of the pose");
  app.add_option_function<double>(
         "--max-rms", [&o](const double& px) { o.max_rms = px; },
         "[px] largest reprojection RMS accepted, exit status 3 beyond (default 2; 1 with --image)")
      ->check(CLI::Range(0.001, 1000.0));
  auto* image = app.add_option("--image", o.lines.image,
                               "calibrate from the field lines of this image (docs/calibration.md)");
  app.add_option("--field", o.lines.field, "field geometry: div_b, div_a or a YAML file (with --image)")
      ->needs(image);
  app.add_option("--corners", o.lines.corners,
                 "u1,v1,u2,v2,u3,v3,u4,v4: the 4 clicked field corners (with --image)")
      ->delimiter(',')
      ->expected(8)
      ->needs(image);
  auto* estimate = app.add_flag("--estimate-intrinsics", o.lines.estimate_intrinsics,
                                "also estimate focal length and distortion (with --image)")
                       ->needs(image);
  app.add_flag("--principal-point", o.lines.principal_point, "also estimate the principal point")
      ->needs(estimate);
  app.add_flag("--fix-focal-length", o.lines.fix_focal_length, "keep the focal length of --camera-info")
      ->needs(estimate);
  app.add_option("--out-camera-info", o.lines.out_camera_info,
                 "write the estimated intrinsics (camera_info YAML)")
      ->needs(image);
}

int run(const Options& o) {
  const sv::CameraIntrinsics k = sv::loadCameraInfoYaml(o.camera_info);
  const auto points = sv::loadFieldCorrespondences(o.points);
  sv::CameraPoseSolution solution;
  try {
    solution = sv::solveCameraPose(k, points);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(o.points + ": " + e.what());
  }
  std::printf("%zu correspondences, camera %dx%d (fx %.3f fy %.3f cx %.3f cy %.3f)\n", points.size(), k.width,
              k.height, k.fx, k.fy, k.cx, k.cy);
  std::printf("  #   pixel u    pixel v    field x   field y   field z   error px\n");
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    std::printf("%3zu %10.3f %10.3f %9.4f %9.4f %9.4f %10.4f\n", i, p.pixel.x(), p.pixel.y(), p.field.x(),
                p.field.y(), p.field.z(), solution.errors_px[i]);
  }
  const Eigen::Vector3d t = solution.field_T_camera.translation();
  const Eigen::Quaterniond q(solution.field_T_camera.linear());
  std::printf("reprojection error: RMS %.4f px, max %.4f px (%d LM iterations)\n", solution.rms_px,
              solution.max_px, solution.iterations);
  std::printf("camera centre in field: (%.4f, %.4f, %.4f) m, rotation xyzw (%.6f, %.6f, %.6f, %.6f)\n", t.x(),
              t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
  if (solution.rms_px > o.max_rms.value_or(2.0)) {
    std::cerr << "calibrate_field: RMS reprojection error " << solution.rms_px << " px exceeds --max-rms "
              << o.max_rms.value_or(2.0) << " px: check the correspondences (" << o.points
              << ") and the intrinsics (" << o.camera_info << "); not writing " << o.out << "\n";
    return 3;
  }
  sv::CameraPoseFile file;
  file.camera_id = o.camera_id;
  file.child_frame_id = o.child_frame_id;
  file.field_T_camera = solution.field_T_camera;
  file.rms_error_px = solution.rms_px;
  file.points = static_cast<int>(points.size());
  file.intrinsics = k;
  sv::saveCameraPoseFile(o.out, file);
  std::printf("wrote %s\n", o.out.c_str());
  // Clicks are off by a fraction of a pixel each, which moves robots by millimetres; the
  // lines of an image of the field fix the pose to a fraction of that.
  std::printf(
      "hint: add --image FIELD.png (a frame of this camera) to polish this pose on the field lines: "
      "docs/calibration.md\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{
      "calibrate_field: a camera's pose in field from pixel <-> field correspondences (docs/calibration.md)",
      "calibrate_field"};
  addOptions(app, o);
  if (const auto status = sv::parseCommandLine(app, argc, argv)) return *status;
  if (o.lines.image.empty() && (o.camera_info.empty() || o.points.empty()))
    return sv::usageError(app, "--camera-info and --points are required (or --image: from the field lines)");
  if (o.child_frame_id.empty() && o.camera_id)
    o.child_frame_id = "camera_" + std::to_string(*o.camera_id) + "_optical";
  try {
    if (!o.lines.image.empty()) {
      o.lines.camera_info = o.camera_info;
      o.lines.points = o.points;
      o.lines.out = o.out;
      o.lines.camera_id = o.camera_id;
      o.lines.child_frame_id = o.child_frame_id;
      o.lines.max_rms = o.max_rms.value_or(1.0);
      return sv::calibrateFromFieldLines(o.lines);
    }
    return run(o);
  } catch (const std::exception& e) {
    std::cerr << "calibrate_field: " << e.what() << "\n";
    return 2;
  }
}
