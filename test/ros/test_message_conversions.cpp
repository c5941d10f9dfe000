// Core types <-> messages of the vision pipeline, and the rviz markers built from them.
#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/ros/blob_conversions.h"
#include "soccer_vision/ros/conversions.h"
#include "soccer_vision/ros/detection_conversions.h"
#include "soccer_vision/ros/field_markers.h"

using namespace soccer_vision;

TEST(DetectionConversions, BlobsComeBackAsTheRegionsTheyWereMadeFrom) {
  Region r;
  r.color = ColorClass::SkyBlue;
  r.area = 57;
  r.cx = 612.25;
  r.cy = 400.125;
  r.mu20 = 4.5;
  r.mu11 = -0.75;
  r.mu02 = 2.25;
  r.orientation = -0.3;
  r.bbox = cv::Rect(608, 396, 9, 8);
  const Region back = fromBlob(toBlob(r));
  EXPECT_EQ(back.color, r.color);
  EXPECT_EQ(back.area, r.area);
  EXPECT_DOUBLE_EQ(back.cx, r.cx);
  EXPECT_DOUBLE_EQ(back.cy, r.cy);
  EXPECT_DOUBLE_EQ(back.mu20, r.mu20);
  EXPECT_DOUBLE_EQ(back.mu11, r.mu11);
  EXPECT_DOUBLE_EQ(back.mu02, r.mu02);
  EXPECT_DOUBLE_EQ(back.orientation, r.orientation);
  EXPECT_EQ(back.bbox, r.bbox);
  Blob bad = toBlob(r);
  bad.color = 200;
  EXPECT_EQ(fromBlob(bad).color, ColorClass::None);
}

TEST(DetectionConversions, CameraDetectionsRoundTripIncludingTeamOnlyRobots) {
  CameraFrameDetections d;
  d.stamp = 1700000000.25;
  d.camera_id = 1;
  d.global_search = false;
  RobotDetection a;
  a.team = Team::Yellow;
  a.id = 4;
  a.x = 1.204;
  a.y = -0.551;
  a.theta = 1.571;
  a.confidence = 0.875;
  RobotDetection b;  // team-only pattern: no id, no heading
  b.team = Team::Blue;
  b.id = -1;
  b.heading_valid = false;
  b.x = -2.0;
  b.y = 0.5;
  b.confidence = 0.5;
  d.robots = {a, b};
  BallDetection ball;
  ball.x = 0.12;
  ball.y = 0.003;
  ball.confidence = 0.75;
  d.balls = {ball};
  d.rejected_robots = {{412.25, 301.5, RejectionCause::Id}, {90.0, 700.75, RejectionCause::Unpaired}};

  std_msgs::Header header;
  header.stamp.fromSec(d.stamp);
  header.frame_id = "camera_1_optical";
  CameraDetections msg;
  toCameraDetections(d, header, msg);
  EXPECT_EQ(msg.header.frame_id, "field");
  EXPECT_EQ(msg.header.stamp, header.stamp);
  ASSERT_EQ(msg.robots.size(), 2u);
  EXPECT_EQ(msg.robots[0].header.stamp, header.stamp);
  EXPECT_EQ(msg.robots[1].id, 255);
  EXPECT_TRUE(std::isnan(msg.robots[1].theta));

  const CameraFrameDetections back = fromCameraDetections(msg);
  EXPECT_NEAR(back.stamp, d.stamp, 1e-6);
  EXPECT_EQ(back.camera_id, 1);
  EXPECT_FALSE(back.global_search);
  ASSERT_EQ(back.robots.size(), 2u);
  EXPECT_EQ(back.robots[0].team, Team::Yellow);
  EXPECT_EQ(back.robots[0].id, 4);
  EXPECT_DOUBLE_EQ(back.robots[0].x, 1.204);
  EXPECT_DOUBLE_EQ(back.robots[0].theta, 1.571);
  EXPECT_TRUE(back.robots[0].heading_valid);
  EXPECT_NEAR(back.robots[0].confidence, 0.875, 1e-6);
  EXPECT_EQ(back.robots[1].id, -1);
  EXPECT_FALSE(back.robots[1].heading_valid);
  ASSERT_EQ(back.balls.size(), 1u);
  EXPECT_DOUBLE_EQ(back.balls[0].x, 0.12);
  EXPECT_DOUBLE_EQ(back.balls[0].z, 0.0215);
  // The rejected robot candidates, for the tracker's search windows: place and cause.
  ASSERT_EQ(msg.rejected_robots.size(), 2u);
  EXPECT_EQ(msg.rejected_robots[0].cause, "id");
  ASSERT_EQ(back.rejected_robots.size(), 2u);
  EXPECT_DOUBLE_EQ(back.rejected_robots[0].u, 412.25);
  EXPECT_DOUBLE_EQ(back.rejected_robots[1].v, 700.75);
  EXPECT_EQ(back.rejected_robots[0].cause, RejectionCause::Id);
  EXPECT_EQ(back.rejected_robots[1].cause, RejectionCause::Unpaired);
  msg.rejected_robots[1].cause = "no_such_cause";  // another node's name: left out
  EXPECT_EQ(fromCameraDetections(msg).rejected_robots.size(), 1u);
}

// One mapping of teams and ids for every message (detections, tracks, ground truth).
TEST(DetectionConversions, TeamsAndIdsOnTheWire) {
  EXPECT_EQ(toWireTeam(Team::Blue), RobotPose::TEAM_BLUE);
  EXPECT_EQ(toWireTeam(Team::Yellow), RobotPose::TEAM_YELLOW);
  EXPECT_EQ(fromWireTeam(RobotPose::TEAM_BLUE), Team::Blue);
  EXPECT_EQ(fromWireTeam(RobotPose::TEAM_YELLOW), Team::Yellow);
  EXPECT_EQ(fromWireTeam(7), Team::Blue);  // a value no sender writes stays a valid team
  RobotPoseArray robots;
  robots.robots.resize(1);
  robots.robots[0].team = 9;
  const FrameRecord f = toFrameRecord(robots, BallPoseArray());
  ASSERT_EQ(f.robots.size(), 1u);
  EXPECT_EQ(f.robots[0].team, Team::Blue);
  EXPECT_EQ(toWireRobotId(-1), kNoRobotId);
  EXPECT_EQ(toWireRobotId(300), 254);
  EXPECT_EQ(fromWireRobotId(kNoRobotId), -1);
  EXPECT_EQ(fromWireRobotId(12), 12);
}

TEST(FieldMarkers, FieldLinesGameObjectsAndStableIds) {
  const FieldGeometry field;
  const auto static_markers = fieldMarkers(field);
  ASSERT_GE(static_markers.markers.size(), 3u);
  EXPECT_EQ(static_markers.markers[1].type, visualization_msgs::Marker::LINE_LIST);
  EXPECT_EQ(static_markers.markers[1].points.size(), 2 * field.lines().size());

  RobotPoseArray robots;
  robots.header.frame_id = "field";
  robots.header.stamp.fromSec(12.5);
  RobotPose r;
  r.team = RobotPose::TEAM_BLUE;
  r.id = 3;
  r.x = 1.0;
  r.y = 2.0;
  r.theta = M_PI / 2;
  r.visible = true;
  robots.robots.push_back(r);
  r.team = RobotPose::TEAM_YELLOW;
  r.visible = false;
  robots.robots.push_back(r);
  BallPoseArray balls;
  balls.header = robots.header;
  BallPose b;
  b.x = 0.5;
  b.z = 0.0215;
  b.visible = true;
  balls.balls.push_back(b);

  visualization_msgs::MarkerArray out;
  appendGameMarkers(robots, balls, MarkerStyle{}, out);
  std::set<std::pair<std::string, int>> keys;
  int cylinders = 0, arrows = 0, spheres = 0;
  for (const auto& m : out.markers) {
    EXPECT_TRUE(keys.insert({m.ns, m.id}).second) << "duplicate marker " << m.ns << "/" << m.id;
    EXPECT_EQ(m.header.stamp, robots.header.stamp);
    cylinders += m.type == visualization_msgs::Marker::CYLINDER;
    spheres += m.type == visualization_msgs::Marker::SPHERE;
    if (m.type == visualization_msgs::Marker::ARROW) {
      ++arrows;
      // Heading pi/2: quaternion (0, 0, sin(pi/4), cos(pi/4)).
      EXPECT_NEAR(m.pose.orientation.z, std::sqrt(0.5), 1e-9);
    }
    if (m.type == visualization_msgs::Marker::CYLINDER && m.id == 3) {
      EXPECT_GT(m.color.b, 0.9);  // blue team
      EXPECT_DOUBLE_EQ(m.pose.position.x, 1.0);
      EXPECT_EQ(m.color.a, 1.0f);
    }
    if (m.type == visualization_msgs::Marker::CYLINDER && m.id != 3) {
      EXPECT_LT(m.color.a, 1.0f);  // predicted only
    }
  }
  EXPECT_EQ(cylinders, 2);
  EXPECT_EQ(arrows, 2);
  EXPECT_EQ(spheres, 1);
}

// NaN or Inf in K or D once gave 0 robots with OK diagnostics: every such camera_info is
// refused with the field named, as are zero focal lengths and absurd sizes.
TEST(CameraInfoConversions, NonFiniteZeroFocalAndHugeCameraInfoAreRefused) {
  const soccer_vision::FieldGeometry field;
  const sensor_msgs::CameraInfo good =
      soccer_vision::toCameraInfo(soccer_vision::CameraModel::defaultCamera(field, 0), "camera_0");
  EXPECT_NO_THROW(soccer_vision::intrinsicsFromCameraInfo(good));
  const auto message = [](const sensor_msgs::CameraInfo& info) -> std::string {
    try {
      soccer_vision::intrinsicsFromCameraInfo(info);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  };
  sensor_msgs::CameraInfo bad = good;
  bad.K[0] = std::nan("");
  EXPECT_NE(message(bad).find("focal length"), std::string::npos) << message(bad);
  bad = good;
  bad.K[4] = 0;
  EXPECT_NE(message(bad).find("focal length"), std::string::npos) << message(bad);
  bad = good;
  bad.K[2] = INFINITY;
  EXPECT_NE(message(bad).find("principal point"), std::string::npos) << message(bad);
  bad = good;
  bad.D[1] = std::nan("");
  EXPECT_NE(message(bad).find("distortion coefficient 1"), std::string::npos) << message(bad);
  bad = good;
  bad.width = bad.height = 100000;
  EXPECT_NE(message(bad).find("image size"), std::string::npos) << message(bad);
  bad = good;
  bad.width = 0;
  EXPECT_NE(message(bad).find("image size 0x"), std::string::npos) << message(bad);
}
