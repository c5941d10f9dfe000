#include <regex>

#include <gtest/gtest.h>

#include "soccer_vision/ssl/tracked_packet.h"

using namespace soccer_vision;

namespace {

TrackerOutput sampleOutput() {
  TrackerOutput out;
  out.stamp = 1764700000.5;
  soccer_vision::TrackedRobot blue;
  blue.team = Team::Blue;
  blue.id = 4;
  blue.x = 1.5;
  blue.y = -2.25;
  blue.theta = -1.0;
  blue.heading_valid = true;
  blue.vx = 0.5;
  blue.vy = -0.25;
  blue.omega = 3.0;
  blue.confidence = 0.75;
  soccer_vision::TrackedRobot anonymous;  // team-only track
  anonymous.team = Team::Yellow;
  anonymous.id = -1;
  soccer_vision::TrackedBall ball;
  ball.primary = true;
  ball.x = -0.5;
  ball.y = 0.25;
  ball.vx = 2.0;
  ball.vy = 1.0;
  ball.confidence = 0.5;
  out.robots = {blue, anonymous};
  out.balls = {ball};
  return out;
}

}  // namespace

TEST(SslTrackedPacket, RobotsAndBallInMetresWithTheLeaguesTeamColour) {
  ssl::TrackedPacketOptions options;
  options.uuid = "0b9c7d4e-0000-4000-8000-000000000001";
  const TrackerWrapperPacket p = ssl::trackedPacket(sampleOutput(), 9, std::nullopt, options);
  EXPECT_TRUE(p.IsInitialized());
  EXPECT_EQ(p.uuid(), options.uuid);
  EXPECT_EQ(p.source_name(), "soccer_vision");
  const TrackedFrame& f = p.tracked_frame();
  EXPECT_EQ(f.frame_number(), 9u);
  EXPECT_DOUBLE_EQ(f.timestamp(), 1764700000.5);
  ASSERT_EQ(f.robots_size(), 1);  // the team-only track has no id to send
  const ::TrackedRobot& r = f.robots(0);
  EXPECT_EQ(r.robot_id().id(), 4u);
  EXPECT_EQ(r.robot_id().team_color(), TEAM_BLUE);
  EXPECT_FLOAT_EQ(r.pos().x(), 1.5f);
  EXPECT_FLOAT_EQ(r.pos().y(), -2.25f);
  EXPECT_FLOAT_EQ(r.orientation(), -1.0f);
  EXPECT_FLOAT_EQ(r.vel().x(), 0.5f);
  EXPECT_FLOAT_EQ(r.vel_angular(), 3.0f);
  EXPECT_FLOAT_EQ(r.visibility(), 0.75f);
  ASSERT_EQ(f.balls_size(), 1);
  EXPECT_FLOAT_EQ(f.balls(0).pos().x(), -0.5f);
  EXPECT_FLOAT_EQ(f.balls(0).pos().z(), 0.0215f);
  EXPECT_FLOAT_EQ(f.balls(0).vel().y(), 1.0f);
  EXPECT_FALSE(f.has_kicked_ball());
}

TEST(SslTrackedPacket, CapabilitiesSayWhatTheTrackerDoes) {
  ssl::TrackedPacketOptions options;
  options.uuid = "u";
  TrackedFrame f = ssl::trackedPacket(sampleOutput(), 0, std::nullopt, options).tracked_frame();
  ASSERT_EQ(f.capabilities_size(), 2);
  EXPECT_EQ(f.capabilities(0), CAPABILITY_DETECT_MULTIPLE_BALLS);
  EXPECT_EQ(f.capabilities(1), CAPABILITY_DETECT_KICKED_BALLS);
  options.kicked_balls = false;
  options.multiple_balls = false;
  f = ssl::trackedPacket(sampleOutput(), 0, std::nullopt, options).tracked_frame();
  EXPECT_EQ(f.capabilities_size(), 0);
}

TEST(SslTrackedPacket, KickedBallWithItsKicker) {
  ssl::KickedBallEstimate kick;
  kick.start_position = {1.0, 2.0};
  kick.start_time = 10.0;
  kick.velocity = {4.0, 0.0, 0.0};
  kick.stop_time = 23.0;
  kick.stop_position = {27.0, 2.0};
  kick.kicker_team = Team::Yellow;
  kick.kicker_id = 7;
  ssl::TrackedPacketOptions options;
  options.uuid = "u";
  const TrackedFrame f = ssl::trackedPacket(sampleOutput(), 0, kick, options).tracked_frame();
  ASSERT_TRUE(f.has_kicked_ball());
  EXPECT_FLOAT_EQ(f.kicked_ball().pos().y(), 2.0f);
  EXPECT_FLOAT_EQ(f.kicked_ball().vel().x(), 4.0f);
  EXPECT_DOUBLE_EQ(f.kicked_ball().start_timestamp(), 10.0);
  EXPECT_DOUBLE_EQ(f.kicked_ball().stop_timestamp(), 23.0);
  EXPECT_EQ(f.kicked_ball().robot_id().id(), 7u);
  EXPECT_EQ(f.kicked_ball().robot_id().team_color(), TEAM_YELLOW);
}

TEST(SslTrackedPacket, RandomUuidsAreVersionFourAndDiffer) {
  const std::string a = ssl::randomUuid(), b = ssl::randomUuid();
  const std::regex v4("[0-9a-f]{8}-[0-9a-f]{4}-4[0-9a-f]{3}-[89ab][0-9a-f]{3}-[0-9a-f]{12}");
  EXPECT_TRUE(std::regex_match(a, v4)) << a;
  EXPECT_NE(a, b);
}
