#include "soccer_vision/common/camera_pose_file.h"

#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "soccer_vision/common/exchange_formats.h"

namespace soccer_vision {
namespace {

[[noreturn]] void fail(const std::string& source, const std::string& what) {
  throw std::runtime_error(source + ": " + what);
}

double number(const YAML::Node& map, const char* key, const std::string& where, const std::string& source) {
  const YAML::Node n = map[key];
  if (!n) fail(source, "missing '" + where + key + "'");
  double v = 0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    fail(source, "'" + where + key + "' is not a number");
  }
  if (!std::isfinite(v)) fail(source, "'" + where + key + "' is not finite");
  return v;
}

const YAML::Node mapAt(const YAML::Node& root, const char* key, const std::string& source) {
  const YAML::Node n = root[key];
  if (!n || !n.IsMap()) fail(source, std::string("missing map '") + key + "'");
  return n;
}

}  // namespace

std::string toYaml(const CameraPoseFile& p) {
  const Eigen::Quaterniond q(p.field_T_camera.linear());
  const Eigen::Vector3d t = p.field_T_camera.translation();
  const auto& k = p.intrinsics;
  std::ostringstream out;
  out << std::setprecision(15);
  out << "# soccer_vision camera pose: optical frame (z forward, x right, y down) in `field`\n";
  if (p.camera_id) out << "camera_id: " << *p.camera_id << "\n";
  if (!p.frame_id.empty()) out << "frame_id: " << p.frame_id << "\n";
  if (!p.child_frame_id.empty()) out << "child_frame_id: " << p.child_frame_id << "\n";
  out << "translation: {x: " << t.x() << ", y: " << t.y() << ", z: " << t.z() << "}  # m\n";
  out << "rotation: {x: " << q.x() << ", y: " << q.y() << ", z: " << q.z() << ", w: " << q.w()
      << "}  # unit quaternion\n";
  out << "rms_error_px: " << p.rms_error_px << "  # reprojection RMS of the solve, raw pixels\n";
  out << "points: " << p.points << "\n";
  out << "# intrinsics the pose was solved with (checked on load)\n";
  out << "intrinsics: {width: " << k.width << ", height: " << k.height << ", fx: " << k.fx << ", fy: " << k.fy
      << ", cx: " << k.cx << ", cy: " << k.cy << "}\n";
  return out.str();
}

CameraPoseFile parseCameraPoseFile(const std::string& yaml_text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    fail(source, std::string("invalid YAML: ") + e.what());
  }
  if (!root.IsMap()) fail(source, "not a camera pose file (top level must be a map)");
  CameraPoseFile p;
  try {
    if (root["camera_id"]) p.camera_id = root["camera_id"].as<int>();
    if (root["frame_id"]) p.frame_id = root["frame_id"].as<std::string>();
    if (root["child_frame_id"]) p.child_frame_id = root["child_frame_id"].as<std::string>();
    if (root["points"]) p.points = root["points"].as<int>();
  } catch (const YAML::Exception& e) {
    fail(source, std::string("bad value: ") + e.what());
  }
  const YAML::Node t = mapAt(root, "translation", source);
  const YAML::Node r = mapAt(root, "rotation", source);
  const Eigen::Vector3d translation(number(t, "x", "translation.", source),
                                    number(t, "y", "translation.", source),
                                    number(t, "z", "translation.", source));
  Eigen::Quaterniond q(number(r, "w", "rotation.", source), number(r, "x", "rotation.", source),
                       number(r, "y", "rotation.", source), number(r, "z", "rotation.", source));
  if (std::abs(q.norm() - 1.0) > 1e-3) {
    fail(source, "rotation is not a unit quaternion (norm " + std::to_string(q.norm()) + ")");
  }
  q.normalize();
  p.field_T_camera = Eigen::Isometry3d::Identity();
  p.field_T_camera.linear() = q.toRotationMatrix();
  p.field_T_camera.translation() = translation;
  if (root["rms_error_px"]) p.rms_error_px = number(root, "rms_error_px", "", source);
  const YAML::Node k = mapAt(root, "intrinsics", source);
  // Range-checked before the cast: 1e300 as an int is undefined (float-cast-overflow).
  for (const char* key : {"width", "height"}) {
    const double v = number(k, key, "intrinsics.", source);
    if (v < 1 || v > kMaxImageSide)
      fail(source, std::string("'intrinsics.") + key + "' must be in 1.." + std::to_string(kMaxImageSide));
    (std::string(key) == "width" ? p.intrinsics.width : p.intrinsics.height) = static_cast<int>(v);
  }
  p.intrinsics.fx = number(k, "fx", "intrinsics.", source);
  p.intrinsics.fy = number(k, "fy", "intrinsics.", source);
  p.intrinsics.cx = number(k, "cx", "intrinsics.", source);
  p.intrinsics.cy = number(k, "cy", "intrinsics.", source);
  if (p.intrinsics.width <= 0 || p.intrinsics.height <= 0 || p.intrinsics.fx <= 0 || p.intrinsics.fy <= 0) {
    fail(source, "intrinsics need a positive width, height, fx and fy");
  }
  return p;
}

CameraPoseFile loadCameraPoseFile(const std::string& path) {
  return parseCameraPoseFile(readTextFile(path), path);
}

void saveCameraPoseFile(const std::string& path, const CameraPoseFile& pose) {
  writeTextFile(path, toYaml(pose));
}

void checkIntrinsicsMatch(const CameraPoseFile& pose, const CameraIntrinsics& k, const std::string& source,
                          double tolerance) {
  const auto& s = pose.intrinsics;
  if (s.width != k.width || s.height != k.height) {
    fail(source, "solved for a " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                     " camera, but the camera is " + std::to_string(k.width) + "x" +
                     std::to_string(k.height));
  }
  auto off = [&](double a, double b, double scale) { return std::abs(a - b) > tolerance * scale; };
  if (off(s.fx, k.fx, k.fx) || off(s.fy, k.fy, k.fy) || off(s.cx, k.cx, k.width) ||
      off(s.cy, k.cy, k.height)) {
    std::ostringstream m;
    m << "solved with other intrinsics (fx " << s.fx << " fy " << s.fy << " cx " << s.cx << " cy " << s.cy
      << ", camera has fx " << k.fx << " fy " << k.fy << " cx " << k.cx << " cy " << k.cy
      << "): calibrate the field again";
    fail(source, m.str());
  }
}

CameraModel cameraModelFromPose(const CameraPoseFile& pose, const CameraIntrinsics& intrinsics,
                                const std::string& source) {
  checkIntrinsicsMatch(pose, intrinsics, source);
  return CameraModel(intrinsics, pose.field_T_camera);
}

}  // namespace soccer_vision
