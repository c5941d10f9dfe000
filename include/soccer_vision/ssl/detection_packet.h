// One camera frame's detections as an SSL-Vision detection packet (docs/ssl.md). The league's
// field frame is ours (`field`: origin at the centre point, x along the length, y along the
// width), so a position only changes unit: m -> mm; headings stay in rad.
#pragma once

#include <cstdint>

#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/detections.h"
#include "soccer_vision/common/robot_pattern.h"
#include "ssl_vision_wrapper.pb.h"

namespace soccer_vision::ssl {

struct DetectionPacketOptions {
  // [m] the marker plane each team's robots were projected onto (the pattern's
  // PatternSet::heights), sent as their `height`.
  TeamHeights robot_height{0.150, 0.150};
  double height(Team team) const { return heightOf(robot_height, team); }
};

// frame_number counts this camera's frames; t_sent is the Unix time [s] of sending.
// t_capture is the frame's capture stamp. A robot without an id (team-only pattern) is sent
// without robot_id, one without a heading without orientation; balls keep their order (best
// first) and carry their region area, not a height (ours is assumed, not measured).
::SSL_WrapperPacket detectionPacket(const CameraFrameDetections& frame, std::uint32_t frame_number,
                                    double t_sent, const DetectionPacketOptions& options = {});

// The detections with their raw pixels recomputed through the camera: robots at their team's
// marker plane (options.height), balls at their centre height, where identification found
// them. For detections that arrive without pixels (the CameraDetections message carries none).
// A point behind the camera keeps its pixel.
CameraFrameDetections withProjectedPixels(CameraFrameDetections frame, const CameraModel& camera,
                                          const DetectionPacketOptions& options);

}  // namespace soccer_vision::ssl
