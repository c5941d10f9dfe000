#include <cmath>

#include <gtest/gtest.h>

#include "soccer_vision/ros/detection_conversions.h"
#include "soccer_vision/ros/tracking_conversions.h"

namespace soccer_vision {

namespace {

std_msgs::Header header() {
  std_msgs::Header h;
  h.stamp = ros::Time(1700000000, 500000000);
  h.frame_id = "field";
  h.seq = 42;
  return h;
}

}  // namespace

TEST(TrackingConversions, RobotsKeepTeamIdStateAndTheHeader) {
  TrackerOutput out;
  TrackedRobot a;
  a.team = Team::Yellow;
  a.id = 7;
  a.x = 1.25;
  a.y = -0.5;
  a.theta = 2.0;
  a.vx = 0.75;
  a.vy = -1.5;
  a.omega = 3.0;
  a.heading_valid = true;
  a.confidence = 0.875;
  a.camera_id = 1;
  a.visible = true;
  out.robots.push_back(a);
  const RobotPoseArray msg = toRobotPoseArray(out, header());
  EXPECT_EQ(msg.header.stamp, header().stamp);
  EXPECT_EQ(msg.header.frame_id, "field");
  ASSERT_EQ(msg.robots.size(), 1u);
  const RobotPose& p = msg.robots[0];
  EXPECT_EQ(p.header.stamp, header().stamp);
  EXPECT_EQ(p.team, RobotPose::TEAM_YELLOW);
  EXPECT_EQ(p.id, 7);
  EXPECT_DOUBLE_EQ(p.x, 1.25);
  EXPECT_DOUBLE_EQ(p.y, -0.5);
  EXPECT_DOUBLE_EQ(p.theta, 2.0);
  EXPECT_DOUBLE_EQ(p.vx, 0.75);
  EXPECT_DOUBLE_EQ(p.vy, -1.5);
  EXPECT_DOUBLE_EQ(p.omega, 3.0);
  EXPECT_FLOAT_EQ(p.confidence, 0.875f);
  EXPECT_EQ(p.camera_id, 1);
  EXPECT_TRUE(p.visible);
}

TEST(TrackingConversions, ARobotWithoutHeadingOrIdSaysSoOnTheWire) {
  TrackerOutput out;
  TrackedRobot t;
  t.team = Team::Blue;
  t.id = -1;  // team-only pattern
  t.theta = 1.0;
  t.omega = 2.0;
  t.heading_valid = false;
  t.camera_id = 300;  // does not fit a uint8
  out.robots.push_back(t);
  const RobotPose p = toRobotPoseArray(out, header()).robots.at(0);
  EXPECT_EQ(p.team, RobotPose::TEAM_BLUE);
  EXPECT_EQ(p.id, kNoRobotId);
  EXPECT_TRUE(std::isnan(p.theta));
  EXPECT_EQ(p.omega, 0.0);
  EXPECT_EQ(p.camera_id, 255);
}

TEST(TrackingConversions, BallsKeepOrderHeightAndVelocity) {
  TrackerOutput out;
  TrackedBall primary, other;
  primary.primary = true;
  primary.x = 0.5;
  primary.z = 0.3;
  primary.vx = 4.0;
  primary.vy = -2.0;
  primary.confidence = 0.5;
  primary.visible = true;
  other.x = -3.0;
  other.camera_id = 1;
  out.balls = {primary, other};
  const BallPoseArray msg = toBallPoseArray(out, header());
  EXPECT_EQ(msg.header.frame_id, "field");
  ASSERT_EQ(msg.balls.size(), 2u);
  EXPECT_DOUBLE_EQ(msg.balls[0].x, 0.5);
  EXPECT_DOUBLE_EQ(msg.balls[0].z, 0.3);
  EXPECT_DOUBLE_EQ(msg.balls[0].vx, 4.0);
  EXPECT_DOUBLE_EQ(msg.balls[0].vy, -2.0);
  EXPECT_FLOAT_EQ(msg.balls[0].confidence, 0.5f);
  EXPECT_TRUE(msg.balls[0].visible);
  EXPECT_DOUBLE_EQ(msg.balls[1].x, -3.0);
  EXPECT_EQ(msg.balls[1].camera_id, 1);
  EXPECT_FALSE(msg.balls[1].visible);
  EXPECT_EQ(msg.balls[1].header.stamp, header().stamp);
}

TEST(TrackingConversions, MessagesBackToTheTrackerOutputRoundTrip) {
  TrackerOutput out;
  TrackedRobot r;
  r.team = Team::Yellow;
  r.id = 7;
  r.x = 1.25;
  r.theta = 2.0;
  r.heading_valid = true;
  r.omega = 3.0;
  r.confidence = 0.875;
  r.camera_id = 1;
  r.visible = true;
  TrackedRobot headless;
  headless.team = Team::Blue;
  headless.id = 3;
  out.robots = {r, headless};
  TrackedBall primary, other;
  primary.primary = true;
  primary.x = 0.5;
  primary.z = 0.3;
  primary.vx = 4.0;
  other.x = -3.0;
  out.balls = {primary, other};
  const TrackerOutput back =
      fromTrackingMessages(toRobotPoseArray(out, header()), toBallPoseArray(out, header()));
  EXPECT_DOUBLE_EQ(back.stamp, header().stamp.toSec());
  ASSERT_EQ(back.robots.size(), 2u);
  EXPECT_EQ(back.robots[0].team, Team::Yellow);
  EXPECT_EQ(back.robots[0].id, 7);
  EXPECT_DOUBLE_EQ(back.robots[0].x, 1.25);
  EXPECT_TRUE(back.robots[0].heading_valid);
  EXPECT_DOUBLE_EQ(back.robots[0].theta, 2.0);
  EXPECT_DOUBLE_EQ(back.robots[0].omega, 3.0);
  EXPECT_EQ(back.robots[0].camera_id, 1);
  EXPECT_TRUE(back.robots[0].visible);
  EXPECT_EQ(back.robots[1].team, Team::Blue);
  EXPECT_FALSE(back.robots[1].heading_valid);  // NaN on the wire
  ASSERT_EQ(back.balls.size(), 2u);
  EXPECT_TRUE(back.balls[0].primary);
  EXPECT_FALSE(back.balls[1].primary);
  EXPECT_DOUBLE_EQ(back.balls[0].z, 0.3);
  EXPECT_DOUBLE_EQ(back.balls[0].vx, 4.0);
  EXPECT_DOUBLE_EQ(back.balls[1].x, -3.0);
}

}  // namespace soccer_vision
