// The tracker's output as the Tracking nodelet publishes it (robots and balls topics).
#pragma once

#include <std_msgs/Header.h>

#include "soccer_vision/BallPoseArray.h"
#include "soccer_vision/RobotPoseArray.h"
#include "soccer_vision/tracking/tracker.h"

namespace soccer_vision {

// Every tracked robot with `header` (its own and each pose's): id on the wire
// (toWireRobotId), theta NaN and omega 0 until the track has had a heading, camera id
// clamped to 0..255.
RobotPoseArray toRobotPoseArray(const TrackerOutput& out, const std_msgs::Header& header);

// Every tracked ball, primary first, likewise.
BallPoseArray toBallPoseArray(const TrackerOutput& out, const std_msgs::Header& header);

// The inverse, for a consumer of both topics (SslOutput): the robots and balls of one stamp
// as the tracker's output; the first ball is the primary one.
TrackerOutput fromTrackingMessages(const RobotPoseArray& robots, const BallPoseArray& balls);

}  // namespace soccer_vision
