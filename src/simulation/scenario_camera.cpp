#include "soccer_vision/simulation/scenario_camera.h"

#include <cmath>

#include <opencv2/core.hpp>

namespace soccer_vision {

CameraModel scenarioCamera(const FieldGeometry& field, int index, const ScenarioConfig& scenario) {
  const CameraModel built_in =
      CameraModel::defaultCamera(field, index, scenario.width, scenario.height, scenario.cameras);
  CameraIntrinsics k = built_in.intrinsics();
  k.dist[0] = scenario.lens.k1;
  k.dist[1] = scenario.lens.k2;
  Eigen::Isometry3d pose = built_in.fieldTCamera();
  if (scenario.lens.tilt_deg > 0) {
    // About a horizontal axis through the camera centre, its direction from the seed.
    cv::RNG rng(scenario.seed * 0x2545F4914F6CDD1DULL + 17 + static_cast<std::uint64_t>(index));
    const double direction = rng.uniform(-M_PI, M_PI);
    const Eigen::Vector3d axis(std::cos(direction), std::sin(direction), 0.0);
    pose.linear() =
        Eigen::AngleAxisd(scenario.lens.tilt_deg * M_PI / 180, axis).toRotationMatrix() * pose.linear();
  }
  return CameraModel(k, pose);
}

}  // namespace soccer_vision
