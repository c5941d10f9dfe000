#include "soccer_vision/ros/tracking_conversions.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "soccer_vision/ros/detection_conversions.h"

namespace soccer_vision {

RobotPoseArray toRobotPoseArray(const TrackerOutput& out, const std_msgs::Header& header) {
  RobotPoseArray msg;
  msg.header = header;
  msg.robots.reserve(out.robots.size());
  for (const TrackedRobot& t : out.robots) {
    RobotPose p;
    p.header = header;
    p.team = toWireTeam(t.team);
    p.id = toWireRobotId(t.id);
    p.x = t.x;
    p.y = t.y;
    p.theta = t.heading_valid ? t.theta : std::nan("");
    p.vx = t.vx;
    p.vy = t.vy;
    p.omega = t.heading_valid ? t.omega : 0.0;
    p.confidence = static_cast<float>(t.confidence);
    p.camera_id = static_cast<std::uint8_t>(std::clamp(t.camera_id, 0, 255));
    p.visible = t.visible;
    msg.robots.push_back(p);
  }
  return msg;
}

BallPoseArray toBallPoseArray(const TrackerOutput& out, const std_msgs::Header& header) {
  BallPoseArray msg;
  msg.header = header;
  for (const TrackedBall& t : out.balls) {
    BallPose b;
    b.header = header;
    b.x = t.x;
    b.y = t.y;
    b.z = t.z;
    b.vx = t.vx;
    b.vy = t.vy;
    b.confidence = static_cast<float>(t.confidence);
    b.camera_id = static_cast<std::uint8_t>(std::clamp(t.camera_id, 0, 255));
    b.visible = t.visible;
    msg.balls.push_back(b);
  }
  return msg;
}

TrackerOutput fromTrackingMessages(const RobotPoseArray& robots, const BallPoseArray& balls) {
  TrackerOutput out;
  out.stamp = robots.header.stamp.toSec();
  for (const RobotPose& p : robots.robots) {
    TrackedRobot r;
    r.team = fromWireTeam(p.team);
    r.id = fromWireRobotId(p.id);
    r.x = p.x;
    r.y = p.y;
    r.heading_valid = std::isfinite(p.theta);
    r.theta = r.heading_valid ? p.theta : 0.0;
    r.vx = p.vx;
    r.vy = p.vy;
    r.omega = p.omega;
    r.confidence = p.confidence;
    r.camera_id = p.camera_id;
    r.visible = p.visible;
    out.robots.push_back(r);
  }
  for (const BallPose& p : balls.balls) {
    TrackedBall b;
    b.primary = out.balls.empty();  // best first: the tracker's primary ball leads
    b.x = p.x;
    b.y = p.y;
    b.z = p.z;
    b.vx = p.vx;
    b.vy = p.vy;
    b.confidence = p.confidence;
    b.camera_id = p.camera_id;
    b.visible = p.visible;
    out.balls.push_back(b);
  }
  return out;
}

}  // namespace soccer_vision
