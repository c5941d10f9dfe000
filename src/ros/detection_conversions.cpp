#include "soccer_vision/ros/detection_conversions.h"

#include <algorithm>
#include <cmath>

#include "soccer_vision/RobotPose.h"

namespace soccer_vision {

Region fromBlob(const Blob& blob) {
  Region r;
  r.color = blob.color < kNumColorClasses ? static_cast<ColorClass>(blob.color) : ColorClass::None;
  r.area = blob.area;
  r.cx = blob.cx;
  r.cy = blob.cy;
  r.mu20 = blob.mu20;
  r.mu11 = blob.mu11;
  r.mu02 = blob.mu02;
  r.orientation = blob.orientation;
  r.bbox = cv::Rect(blob.x0, blob.y0, blob.width, blob.height);
  return r;
}

std::vector<Region> fromBlobArray(const BlobArray& blobs) {
  std::vector<Region> regions;
  regions.reserve(blobs.blobs.size());
  for (const Blob& b : blobs.blobs) {
    // A blob with NaN or Inf geometry comes from no segmentation: left out, as identification
    // would cast its centroid to pixels.
    const bool finite = std::isfinite(b.cx) && std::isfinite(b.cy) && std::isfinite(b.mu20) &&
                        std::isfinite(b.mu11) && std::isfinite(b.mu02) && std::isfinite(b.orientation);
    if (finite && b.area > 0) regions.push_back(fromBlob(b));
  }
  return regions;
}

void toCameraDetections(const CameraFrameDetections& detections, const std_msgs::Header& header,
                        CameraDetections& out) {
  out.header = header;
  out.header.frame_id = "field";
  out.camera_id = static_cast<std::uint8_t>(std::clamp(detections.camera_id, 0, 255));
  out.global_search = detections.global_search;
  out.robots.clear();
  out.robots.reserve(detections.robots.size());
  for (const RobotDetection& d : detections.robots) {
    RobotPose p;
    p.header = out.header;
    p.team = toWireTeam(d.team);
    p.id = toWireRobotId(d.id);
    p.x = d.x;
    p.y = d.y;
    p.theta = d.heading_valid ? d.theta : std::nan("");
    p.confidence = static_cast<float>(d.confidence);
    p.camera_id = out.camera_id;
    p.visible = true;
    out.robots.push_back(p);
  }
  out.balls.clear();
  out.balls.reserve(detections.balls.size());
  for (const BallDetection& d : detections.balls) {
    BallPose b;
    b.header = out.header;
    b.x = d.x;
    b.y = d.y;
    b.z = d.z;
    b.confidence = static_cast<float>(d.confidence);
    b.camera_id = out.camera_id;
    b.visible = true;
    out.balls.push_back(b);
  }
  out.rejected_robots.clear();
  out.rejected_robots.reserve(detections.rejected_robots.size());
  for (const RejectedRobotCandidate& r : detections.rejected_robots) {
    RobotCandidate c;
    c.u = static_cast<float>(r.u);
    c.v = static_cast<float>(r.v);
    c.cause = rejectionCauseName(r.cause);
    out.rejected_robots.push_back(c);
  }
}

CameraFrameDetections fromCameraDetections(const CameraDetections& msg) {
  CameraFrameDetections d;
  d.stamp = msg.header.stamp.toSec();
  d.camera_id = msg.camera_id;
  d.global_search = msg.global_search;
  for (const RobotPose& p : msg.robots) {
    RobotDetection r;
    r.team = fromWireTeam(p.team);
    r.id = fromWireRobotId(p.id);
    r.x = p.x;
    r.y = p.y;
    r.heading_valid = std::isfinite(p.theta);
    r.theta = r.heading_valid ? p.theta : 0.0;
    r.confidence = p.confidence;
    d.robots.push_back(r);
  }
  for (const BallPose& b : msg.balls) {
    BallDetection ball;
    ball.x = b.x;
    ball.y = b.y;
    ball.z = b.z;
    ball.confidence = b.confidence;
    d.balls.push_back(ball);
  }
  for (const RobotCandidate& c : msg.rejected_robots) {
    // Another node's cause names may differ: a candidate of an unknown cause is left out.
    if (const auto cause = parseRejectionCause(c.cause)) d.rejected_robots.push_back({c.u, c.v, *cause});
  }
  return d;
}

}  // namespace soccer_vision
