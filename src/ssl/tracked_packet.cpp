#include "soccer_vision/ssl/tracked_packet.h"

#include <cstdio>
#include <random>

namespace soccer_vision::ssl {

namespace {

void setVector(const Eigen::Vector2d& v, ::Vector2* out) {
  out->set_x(static_cast<float>(v.x()));
  out->set_y(static_cast<float>(v.y()));
}

void setVector(const Eigen::Vector3d& v, ::Vector3* out) {
  out->set_x(static_cast<float>(v.x()));
  out->set_y(static_cast<float>(v.y()));
  out->set_z(static_cast<float>(v.z()));
}

::TeamColor leagueTeam(Team team) { return team == Team::Yellow ? ::TEAM_YELLOW : ::TEAM_BLUE; }

}  // namespace

std::string randomUuid() {
  std::random_device device;
  std::mt19937_64 rng((static_cast<std::uint64_t>(device()) << 32) ^ device());
  std::uint64_t hi = rng(), lo = rng();
  hi = (hi & ~0xF000ull) | 0x4000ull;              // version 4
  lo = (lo & ~(0xC0ull << 56)) | (0x80ull << 56);  // variant 1
  char text[37];
  std::snprintf(text, sizeof text, "%08x-%04x-%04x-%04x-%012llx", static_cast<unsigned>(hi >> 32),
                static_cast<unsigned>((hi >> 16) & 0xFFFF), static_cast<unsigned>(hi & 0xFFFF),
                static_cast<unsigned>(lo >> 48), static_cast<unsigned long long>(lo & 0xFFFFFFFFFFFFull));
  return text;
}

::TrackerWrapperPacket trackedPacket(const TrackerOutput& output, std::uint32_t frame_number,
                                     const std::optional<KickedBallEstimate>& kick,
                                     const TrackedPacketOptions& options) {
  ::TrackerWrapperPacket packet;
  packet.set_uuid(options.uuid);
  packet.set_source_name(options.source_name);
  ::TrackedFrame* f = packet.mutable_tracked_frame();
  f->set_frame_number(frame_number);
  f->set_timestamp(output.stamp);
  for (const TrackedBall& b : output.balls) {
    ::TrackedBall* out = f->add_balls();
    setVector(Eigen::Vector3d(b.x, b.y, b.z), out->mutable_pos());
    setVector(Eigen::Vector3d(b.vx, b.vy, 0.0), out->mutable_vel());
    out->set_visibility(static_cast<float>(b.confidence));
  }
  for (const TrackedRobot& r : output.robots) {
    if (r.id < 0) continue;
    ::TrackedRobot* out = f->add_robots();
    out->mutable_robot_id()->set_id(static_cast<std::uint32_t>(r.id));
    out->mutable_robot_id()->set_team_color(leagueTeam(r.team));
    setVector(Eigen::Vector2d(r.x, r.y), out->mutable_pos());
    out->set_orientation(r.heading_valid ? static_cast<float>(r.theta) : 0.0f);
    setVector(Eigen::Vector2d(r.vx, r.vy), out->mutable_vel());
    out->set_vel_angular(static_cast<float>(r.omega));
    out->set_visibility(static_cast<float>(r.confidence));
  }
  if (kick && options.kicked_balls) {
    ::KickedBall* k = f->mutable_kicked_ball();
    setVector(kick->start_position, k->mutable_pos());
    setVector(kick->velocity, k->mutable_vel());
    k->set_start_timestamp(kick->start_time);
    k->set_stop_timestamp(kick->stop_time);
    setVector(kick->stop_position, k->mutable_stop_pos());
    if (kick->kicker_team) {
      k->mutable_robot_id()->set_id(static_cast<std::uint32_t>(kick->kicker_id));
      k->mutable_robot_id()->set_team_color(leagueTeam(*kick->kicker_team));
    }
  }
  if (options.multiple_balls) f->add_capabilities(::CAPABILITY_DETECT_MULTIPLE_BALLS);
  if (options.kicked_balls) f->add_capabilities(::CAPABILITY_DETECT_KICKED_BALLS);
  return packet;
}

}  // namespace soccer_vision::ssl
