// Camera calibration YAML -> intrinsics -> a camera model that projects a point.
#include <Eigen/Geometry>

#include "fuzz_target.h"
#include "soccer_vision/common/camera_info_yaml.h"
#include "soccer_vision/common/camera_model.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const soccer_vision::CameraIntrinsics k =
        soccer_vision::parseCameraInfoYaml(soccer_vision_fuzz::asText(data, size), "fuzz");
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = Eigen::Vector3d(0, 0, 4);
    pose.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
    const soccer_vision::CameraModel camera(k, pose);
    camera.project(Eigen::Vector3d(0.1, 0.2, 0.0));
  } catch (const std::exception&) {
  }
  return 0;
}
