// The tracker's output as a league tracked packet (TrackerWrapperPacket; docs/ssl.md): m, m/s,
// rad in the league's field frame, which is ours (`field`).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "soccer_vision/ssl/kicked_ball.h"
#include "soccer_vision/tracking/tracker.h"
#include "ssl_vision_wrapper_tracked.pb.h"

namespace soccer_vision::ssl {

struct TrackedPacketOptions {
  std::string uuid;  // this source's id, constant while it runs
  std::string source_name = "soccer_vision";
  bool multiple_balls = true;  // the tracker follows more than one ball track
  bool kicked_balls = true;    // kicked-ball estimates are sent
};

// A random version-4 UUID (for TrackedPacketOptions::uuid).
std::string randomUuid();

// Robots without an id (team-only patterns) are left out: the league identifies robots by id.
// A robot whose track has had no heading is sent with orientation 0. Balls keep the tracker's
// order, the primary first; visibility is the running confidence.
::TrackerWrapperPacket trackedPacket(const TrackerOutput& output, std::uint32_t frame_number,
                                     const std::optional<KickedBallEstimate>& kick,
                                     const TrackedPacketOptions& options);

}  // namespace soccer_vision::ssl
