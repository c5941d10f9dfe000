// What identification hands to tracking: the robots and balls found in one camera frame,
// in the `field` frame (SI units), before any filtering over time. Shared by the core
// identification (regions -> detections) and the core tracker (detections -> tracks),
// and mirrored by the CameraDetections message.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "soccer_vision/common/ball.h"
#include "soccer_vision/common/color_class.h"
#include "soccer_vision/common/rejection_counts.h"

namespace soccer_vision {

struct RobotDetection {
  Team team = Team::Blue;
  int id = -1;                  // robot id; -1 when the pattern carries none (team-only)
  double x = 0, y = 0;          // [m] robot centre on the field
  double theta = 0;             // [rad] heading in (-pi, pi]; meaningless without heading_valid
  bool heading_valid = true;    // false for patterns without a heading (team-only)
  double confidence = 0;        // [0..1]
  Eigen::Vector2d pixel{0, 0};  // raw image pixel of the robot centre at marker height
};

struct BallDetection {
  double x = 0, y = 0;          // [m] ball centre on the field
  double z = kBallRadius;       // [m] ball centre height assumed for the projection
  double confidence = 0;        // [0..1]
  Eigen::Vector2d pixel{0, 0};  // raw image pixel of the ball centre
  double area_px = 0;           // region area [px]
};

// A robot candidate identification did not report: its team-colour region's centroid (raw
// image pixels) and why (the furthest check its best hypothesis passed).
struct RejectedRobotCandidate {
  double u = 0, v = 0;
  RejectionCause cause = RejectionCause::Unpaired;
};

struct CameraFrameDetections {
  double stamp = 0;  // [s] capture stamp of the image
  int camera_id = 0;
  bool global_search = true;  // segmentation looked at the whole frame
  std::vector<RobotDetection> robots;
  std::vector<BallDetection> balls;  // candidates, best first
  RejectionCounts rejections;        // candidates not reported, by cause
  // Robots reported with reservations (RobotIdentificationResult): an id recalled from the
  // camera's last frames, a marker below its area gate.
  int recalled_ids = 0;
  int small_marker_robots = 0;
  // The robot candidates among them with a place (those off the plane have none); in-process
  // only (evaluate's misses, detect), not in the CameraDetections message.
  std::vector<RejectedRobotCandidate> rejected_robots;
};

}  // namespace soccer_vision
