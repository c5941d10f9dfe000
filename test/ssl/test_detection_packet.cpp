#include <gtest/gtest.h>

#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/ssl/detection_packet.h"

using namespace soccer_vision;

namespace {

CameraFrameDetections sampleFrame() {
  CameraFrameDetections f;
  f.stamp = 1764700000.123456;
  f.camera_id = 1;
  RobotDetection yellow;
  yellow.team = Team::Yellow;
  yellow.id = 3;
  yellow.x = 1.2345;
  yellow.y = -0.5;
  yellow.theta = 2.5;
  yellow.confidence = 0.9;
  yellow.pixel = {640.25, 512.5};
  RobotDetection blue;
  blue.team = Team::Blue;
  blue.id = -1;  // team-only pattern: no id, no heading
  blue.heading_valid = false;
  blue.x = -4.0;
  blue.y = 2.75;
  blue.confidence = 0.7;
  BallDetection ball;
  ball.x = 0.1;
  ball.y = -0.2;
  ball.confidence = 0.8;
  ball.area_px = 41.6;
  ball.pixel = {100.5, 200.5};
  f.robots = {yellow, blue};
  f.balls = {ball};
  return f;
}

}  // namespace

TEST(SslDetectionPacket, CarriesFrameCameraAndTimesInTheLeaguesFields) {
  const SSL_WrapperPacket p = ssl::detectionPacket(sampleFrame(), 42, 1764700000.125);
  ASSERT_TRUE(p.has_detection());
  EXPECT_FALSE(p.has_geometry());
  EXPECT_EQ(p.source(), VISION_SOURCE_OTHER);
  const SSL_DetectionFrame& d = p.detection();
  EXPECT_EQ(d.frame_number(), 42u);
  EXPECT_EQ(d.camera_id(), 1u);
  EXPECT_DOUBLE_EQ(d.t_capture(), 1764700000.123456);  // the image stamp, as a double
  EXPECT_DOUBLE_EQ(d.t_sent(), 1764700000.125);
  EXPECT_TRUE(p.IsInitialized());  // every required field set
}

TEST(SslDetectionPacket, RobotsByTeamInMillimetresAndRadians) {
  const SSL_DetectionFrame d = ssl::detectionPacket(sampleFrame(), 0, 0.0).detection();
  ASSERT_EQ(d.robots_yellow_size(), 1);
  ASSERT_EQ(d.robots_blue_size(), 1);
  const SSL_DetectionRobot& y = d.robots_yellow(0);
  EXPECT_EQ(y.robot_id(), 3u);
  EXPECT_NEAR(y.x(), 1234.5, 1e-3);
  EXPECT_NEAR(y.y(), -500.0, 1e-3);
  EXPECT_NEAR(y.orientation(), 2.5, 1e-6);
  EXPECT_NEAR(y.height(), 150.0, 1e-3);
  EXPECT_NEAR(y.pixel_x(), 640.25, 1e-4);
  EXPECT_NEAR(y.confidence(), 0.9, 1e-6);
  const SSL_DetectionRobot& b = d.robots_blue(0);
  EXPECT_FALSE(b.has_robot_id());
  EXPECT_FALSE(b.has_orientation());
  EXPECT_NEAR(b.x(), -4000.0, 1e-3);
  EXPECT_NEAR(b.y(), 2750.0, 1e-3);
}

TEST(SslDetectionPacket, BallsInMillimetresWithTheirArea) {
  const SSL_DetectionFrame d = ssl::detectionPacket(sampleFrame(), 0, 0.0).detection();
  ASSERT_EQ(d.balls_size(), 1);
  EXPECT_NEAR(d.balls(0).x(), 100.0, 1e-3);
  EXPECT_NEAR(d.balls(0).y(), -200.0, 1e-3);
  EXPECT_EQ(d.balls(0).area(), 42u);
  EXPECT_FALSE(d.balls(0).has_z());  // our ball height is assumed, not measured
  EXPECT_NEAR(d.balls(0).pixel_y(), 200.5, 1e-4);
}

TEST(SslDetectionPacket, RobotHeightFollowsEachTeamsMarkerPlane) {
  ssl::DetectionPacketOptions options;
  options.robot_height = {0.148, 0.135};  // blue, yellow
  const SSL_DetectionFrame d = ssl::detectionPacket(sampleFrame(), 0, 0.0, options).detection();
  EXPECT_NEAR(d.robots_yellow(0).height(), 135.0, 1e-3);
  EXPECT_NEAR(d.robots_blue(0).height(), 148.0, 1e-3);
}

TEST(SslDetectionPacket, PixelsRecomputedThroughTheCameraAtMarkerAndBallHeight) {
  const FieldGeometry field = FieldGeometry::divB();
  const CameraModel camera = CameraModel::defaultCamera(field, 0);
  CameraFrameDetections f = sampleFrame();
  f.robots[0].x = -2.0;  // inside camera 0's half
  f.robots[0].y = 0.5;
  f.balls[0].x = -1.5;
  ssl::DetectionPacketOptions options;
  options.robot_height = {0.150, 0.100};  // f.robots[0] is yellow: its pixel at 0.10 m
  ASSERT_EQ(f.robots[0].team, Team::Yellow);
  const CameraFrameDetections projected = ssl::withProjectedPixels(f, camera, options);
  const Eigen::Vector2d robot_pixel = projected.robots[0].pixel;
  EXPECT_GT((robot_pixel - *camera.project({-2.0, 0.5, 0.150})).norm(), 0.5);
  const auto back = camera.pixelToField(robot_pixel, 0.100);
  ASSERT_TRUE(back.has_value());
  EXPECT_NEAR(back->x(), -2.0, 1e-6);
  EXPECT_NEAR(back->y(), 0.5, 1e-6);
  EXPECT_TRUE(camera.inImage(robot_pixel));
  const auto ball_back = camera.pixelToField(projected.balls[0].pixel, f.balls[0].z);
  ASSERT_TRUE(ball_back.has_value());
  EXPECT_NEAR(ball_back->x(), -1.5, 1e-6);
}
