#include "soccer_vision/ssl/detection_packet.h"

#include <cmath>

#include "soccer_vision/ssl/units.h"

namespace soccer_vision::ssl {

namespace {

void fillRobot(const RobotDetection& r, double height, ::SSL_DetectionRobot* out) {
  out->set_confidence(static_cast<float>(r.confidence));
  if (r.id >= 0) out->set_robot_id(static_cast<std::uint32_t>(r.id));
  out->set_x(toMillimetres(r.x));
  out->set_y(toMillimetres(r.y));
  if (r.heading_valid) out->set_orientation(static_cast<float>(r.theta));
  out->set_pixel_x(static_cast<float>(r.pixel.x()));
  out->set_pixel_y(static_cast<float>(r.pixel.y()));
  out->set_height(toMillimetres(height));
}

}  // namespace

CameraFrameDetections withProjectedPixels(CameraFrameDetections frame, const CameraModel& camera,
                                          const DetectionPacketOptions& options) {
  for (RobotDetection& r : frame.robots) {
    if (const auto pixel = camera.project({r.x, r.y, options.height(r.team)})) r.pixel = *pixel;
  }
  for (BallDetection& b : frame.balls) {
    if (const auto pixel = camera.project({b.x, b.y, b.z})) b.pixel = *pixel;
  }
  return frame;
}

::SSL_WrapperPacket detectionPacket(const CameraFrameDetections& frame, std::uint32_t frame_number,
                                    double t_sent, const DetectionPacketOptions& options) {
  ::SSL_WrapperPacket packet;
  packet.set_source(::VISION_SOURCE_OTHER);
  ::SSL_DetectionFrame* d = packet.mutable_detection();
  d->set_frame_number(frame_number);
  d->set_t_capture(frame.stamp);
  d->set_t_sent(t_sent);
  d->set_camera_id(static_cast<std::uint32_t>(frame.camera_id));
  for (const BallDetection& b : frame.balls) {
    ::SSL_DetectionBall* out = d->add_balls();
    out->set_confidence(static_cast<float>(b.confidence));
    out->set_area(static_cast<std::uint32_t>(std::lround(std::max(0.0, b.area_px))));
    out->set_x(toMillimetres(b.x));
    out->set_y(toMillimetres(b.y));
    out->set_pixel_x(static_cast<float>(b.pixel.x()));
    out->set_pixel_y(static_cast<float>(b.pixel.y()));
  }
  for (const RobotDetection& r : frame.robots) {
    fillRobot(r, options.height(r.team),
              r.team == Team::Yellow ? d->add_robots_yellow() : d->add_robots_blue());
  }
  return packet;
}

}  // namespace soccer_vision::ssl
