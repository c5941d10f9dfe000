// Messages between segmentation, identification and tracking <-> core types, shared by
// the nodelets and the offline tools so that both see exactly the same data.
#pragma once

#include <cstdint>
#include <vector>

#include <std_msgs/Header.h>

#include "soccer_vision/BlobArray.h"
#include "soccer_vision/CameraDetections.h"
#include "soccer_vision/RobotPose.h"
#include "soccer_vision/common/detections.h"
#include "soccer_vision/segmentation/region_extractor.h"

namespace soccer_vision {

// RobotPose.id on the wire: 0..254; kNoRobotId for robots without an id (team-only
// patterns), the core's id -1.
constexpr std::uint8_t kNoRobotId = 255;
inline std::uint8_t toWireRobotId(int id) {
  return id < 0 ? kNoRobotId : static_cast<std::uint8_t>(id < 254 ? id : 254);
}
inline int fromWireRobotId(std::uint8_t id) { return id == kNoRobotId ? -1 : id; }
// RobotPose.team on the wire: TEAM_BLUE 0, TEAM_YELLOW 1; any other value reads as blue.
inline std::uint8_t toWireTeam(Team team) {
  return team == Team::Yellow ? RobotPose::TEAM_YELLOW : RobotPose::TEAM_BLUE;
}
inline Team fromWireTeam(std::uint8_t team) {
  return team == RobotPose::TEAM_YELLOW ? Team::Yellow : Team::Blue;
}

// A Blob back as the Region it was made from (toBlob in blob_conversions.h); colours
// outside the ColorClass range become ColorClass::None.
Region fromBlob(const Blob& blob);
// Blobs with NaN or Inf geometry or no area are left out (they come from no segmentation).
std::vector<Region> fromBlobArray(const BlobArray& blobs);

// One camera frame's detections as a message (header: capture stamp, frame "field";
// velocities 0, `visible` true) and back (stamp and camera id from the message).
void toCameraDetections(const CameraFrameDetections& detections, const std_msgs::Header& header,
                        CameraDetections& out);
CameraFrameDetections fromCameraDetections(const CameraDetections& msg);

}  // namespace soccer_vision
