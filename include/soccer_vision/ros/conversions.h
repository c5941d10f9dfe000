// Conversions between the ROS-free core types and ROS messages, shared by the nodelets
// and the tools so that live topics and generated bags carry exactly the same data.
#pragma once

#include <functional>

#include <ros/time.h>
#include <sensor_msgs/CameraInfo.h>

#include "soccer_vision/BallPoseArray.h"
#include "soccer_vision/RobotPoseArray.h"
#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/exchange_formats.h"
#include "soccer_vision/simulation/scene.h"

namespace soccer_vision {

// plumb_bob camera_info of a camera model (R = identity, P = K).
sensor_msgs::CameraInfo toCameraInfo(const CameraModel& camera, const std::string& frame_id);
// Intrinsics and distortion of a camera_info (plumb_bob or rational_polynomial's first 5).
// Throws std::runtime_error for other distortion models, an empty K, or values
// checkIntrinsics refuses (NaN/Inf anywhere, a focal length <= 0, a size beyond the limit).
CameraIntrinsics intrinsicsFromCameraInfo(const sensor_msgs::CameraInfo& info);

using RobotVisibility = std::function<bool(const RobotState&)>;
using BallVisibility = std::function<bool(const BallState&)>;

// Ground truth of a scene as published on ground_truth/robots and ground_truth/balls:
// frame "field", confidence 1, `visible` = fully inside this camera's image.
RobotPoseArray toRobotPoseArray(const SceneState& scene, const ros::Time& stamp, int camera_id,
                                const RobotVisibility& visible);
BallPoseArray toBallPoseArray(const SceneState& scene, const ros::Time& stamp, int camera_id,
                              const BallVisibility& visible);

// JSON Lines record (docs/formats.md) of robot and ball messages (visible flags kept).
FrameRecord toFrameRecord(const RobotPoseArray& robots, const BallPoseArray& balls);

}  // namespace soccer_vision
