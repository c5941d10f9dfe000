#include "soccer_vision/ros/conversions.h"

#include <stdexcept>

#include <sensor_msgs/distortion_models.h>

#include "soccer_vision/ros/detection_conversions.h"

namespace soccer_vision {

sensor_msgs::CameraInfo toCameraInfo(const CameraModel& camera, const std::string& frame_id) {
  const auto& k = camera.intrinsics();
  sensor_msgs::CameraInfo info;
  info.header.frame_id = frame_id;
  info.width = k.width;
  info.height = k.height;
  info.distortion_model = sensor_msgs::distortion_models::PLUMB_BOB;
  info.D.assign(k.dist.begin(), k.dist.end());
  info.K = {k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1};
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {k.fx, 0, k.cx, 0, 0, k.fy, k.cy, 0, 0, 0, 1, 0};
  return info;
}

CameraIntrinsics intrinsicsFromCameraInfo(const sensor_msgs::CameraInfo& info) {
  if (info.K[0] == 0 && info.K[4] == 0) throw std::runtime_error("camera_info has no intrinsics (K)");
  const bool plumb = info.distortion_model == sensor_msgs::distortion_models::PLUMB_BOB;
  const bool rational = info.distortion_model == sensor_msgs::distortion_models::RATIONAL_POLYNOMIAL;
  if (!info.D.empty() && !plumb && !rational) {
    throw std::runtime_error("unsupported distortion model '" + info.distortion_model + "'");
  }
  if (rational && info.D.size() > 5 && (info.D[5] != 0 || info.D[6] != 0 || info.D[7] != 0)) {
    throw std::runtime_error("rational_polynomial with k4..k6 != 0 is not supported");
  }
  CameraIntrinsics k;
  k.width = static_cast<int>(info.width);
  k.height = static_cast<int>(info.height);
  k.fx = info.K[0];
  k.fy = info.K[4];
  k.cx = info.K[2];
  k.cy = info.K[5];
  for (std::size_t i = 0; i < 5 && i < info.D.size(); ++i) k.dist[i] = info.D[i];
  if (info.width > static_cast<std::uint32_t>(kMaxImageSide) ||
      info.height > static_cast<std::uint32_t>(kMaxImageSide))
    k.width = k.height = kMaxImageSide + 1;  // refused below, not wrapped to a negative int
  try {
    checkIntrinsics(k);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("camera_info: ") + e.what());
  }
  return k;
}

RobotPoseArray toRobotPoseArray(const SceneState& scene, const ros::Time& stamp, int camera_id,
                                const RobotVisibility& visible) {
  RobotPoseArray out;
  out.header.stamp = stamp;
  out.header.frame_id = "field";
  for (const auto& r : scene.robots) {
    RobotPose p;
    p.header = out.header;
    p.team = toWireTeam(r.team);
    p.id = static_cast<std::uint8_t>(r.id);
    p.x = r.x;
    p.y = r.y;
    p.theta = r.theta;
    p.vx = r.vx;
    p.vy = r.vy;
    p.omega = r.omega;
    p.confidence = 1.0f;
    p.camera_id = static_cast<std::uint8_t>(camera_id);
    p.visible = visible(r);
    out.robots.push_back(p);
  }
  return out;
}

BallPoseArray toBallPoseArray(const SceneState& scene, const ros::Time& stamp, int camera_id,
                              const BallVisibility& visible) {
  BallPoseArray out;
  out.header.stamp = stamp;
  out.header.frame_id = "field";
  for (const auto& b : scene.balls) {
    BallPose p;
    p.header = out.header;
    p.x = b.x;
    p.y = b.y;
    p.z = b.z;
    p.vx = b.vx;
    p.vy = b.vy;
    p.vz = b.vz;
    p.confidence = 1.0f;
    p.camera_id = static_cast<std::uint8_t>(camera_id);
    p.visible = visible(b);
    out.balls.push_back(p);
  }
  return out;
}

FrameRecord toFrameRecord(const RobotPoseArray& robots, const BallPoseArray& balls) {
  FrameRecord f;
  f.stamp = robots.header.stamp.toSec();
  for (const auto& p : robots.robots) {
    RobotRecord r;
    r.team = fromWireTeam(p.team);
    r.id = p.id;
    r.x = p.x;
    r.y = p.y;
    r.theta = p.theta;
    r.visible = p.visible;
    f.robots.push_back(r);
  }
  for (const auto& p : balls.balls) {
    BallRecord b;
    b.x = p.x;
    b.y = p.y;
    b.visible = p.visible;
    f.balls.push_back(b);
  }
  return f;
}

}  // namespace soccer_vision
