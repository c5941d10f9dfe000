// rostest for the CameraDriver nodelet (synthetic source). Run in the camera's namespace;
// private parameters say what the launch file configured:
//   ~camera_id (int, 0), ~width/~height (int, 640/512), ~fps (double, 30),
//   ~encoding (string, "bgr8"), ~frames (int, 30: frames to collect),
//   ~min_color_match (double, 0.95: fraction of ground-truth markers whose pixel must show
//   the right colour class), ~test_reconfigure (bool, false: also change brightness and
//   fps through dynamic_reconfigure, service <~driver>/set_parameters, ~driver default
//   "camera_driver").
// Checks: image/camera_info pairing and stamps, the capture time grid, encoding and size,
// camera_info = the synthetic camera's true calibration, the static tf field -> optical
// frame, and that the ground truth matches the rendered frames (team marker and ball
// colours at the projected ground-truth positions).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include <cv_bridge/cv_bridge.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "soccer_vision/BallPose.h"
#include "soccer_vision/BallPoseArray.h"
#include "soccer_vision/RobotPoseArray.h"
#include "soccer_vision/common/bayer_encoding.h"
#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/common/robot_pattern.h"
#include "soccer_vision/simulation/field_renderer.h"
#include "soccer_vision/sources/frame_source.h"

namespace sv = soccer_vision;

namespace {

struct Params {
  int camera_id = 0;
  int width = 640;
  int height = 512;
  double fps = 30;
  std::string encoding = "bgr8";
  int frames = 30;
  double min_color_match = 0.95;
};

Params readParams() {
  ros::NodeHandle pnh("~");
  Params p;
  pnh.param("camera_id", p.camera_id, p.camera_id);
  pnh.param("width", p.width, p.width);
  pnh.param("height", p.height, p.height);
  pnh.param("fps", p.fps, p.fps);
  pnh.param("encoding", p.encoding, p.encoding);
  pnh.param("frames", p.frames, p.frames);
  pnh.param("min_color_match", p.min_color_match, p.min_color_match);
  return p;
}

// Everything received, keyed by stamp.
struct Recorder {
  std::mutex mutex;
  std::vector<sensor_msgs::ImageConstPtr> images;
  std::map<ros::Time, sensor_msgs::CameraInfoConstPtr> infos;
  std::map<ros::Time, soccer_vision::RobotPoseArrayConstPtr> robots;
  std::map<ros::Time, soccer_vision::BallPoseArrayConstPtr> balls;
  std::map<ros::Time, soccer_vision::BallPoseConstPtr> ball;

  void image(const sensor_msgs::ImageConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    images.push_back(m);
  }
  void info(const sensor_msgs::CameraInfoConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    infos[m->header.stamp] = m;
  }
  void robotArray(const soccer_vision::RobotPoseArrayConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    robots[m->header.stamp] = m;
  }
  void ballArray(const soccer_vision::BallPoseArrayConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    balls[m->header.stamp] = m;
  }
  void firstBall(const soccer_vision::BallPoseConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    ball[m->header.stamp] = m;
  }
  std::size_t imageCount() {
    std::lock_guard<std::mutex> l(mutex);
    return images.size();
  }
};

// Nearest colour class of a BGR pixel among the painted classes, allowing a global gain
// (illumination) on each class albedo.
sv::ColorClass nearestClass(const cv::Vec3b& px) {
  const sv::ColorClass candidates[] = {
      sv::ColorClass::Blue,    sv::ColorClass::Yellow, sv::ColorClass::Pink,    sv::ColorClass::Purple,
      sv::ColorClass::SkyBlue, sv::ColorClass::Green,  sv::ColorClass::Red,     sv::ColorClass::Orange,
      sv::ColorClass::Carpet,  sv::ColorClass::Line,   sv::ColorClass::RobotTop};
  const cv::Vec3f p(px[0], px[1], px[2]);
  sv::ColorClass best = sv::ColorClass::None;
  double best_d = 1e18;
  for (sv::ColorClass c : candidates) {
    const cv::Vec3f a = sv::classAlbedo(c);
    const double aa = a.dot(a);
    const double g = aa > 0 ? std::clamp(p.dot(a) / aa, 0.5, 2.0) : 1.0;
    const double d = cv::norm(p - static_cast<float>(g) * a);
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  return best;
}

class CameraDriverTest : public ::testing::Test {
 protected:
  void SetUp() override {
    params_ = readParams();
    ros::NodeHandle nh;
    subs_.push_back(nh.subscribe("image_raw", 100, &Recorder::image, &rec_));
    subs_.push_back(nh.subscribe("camera_info", 100, &Recorder::info, &rec_));
    subs_.push_back(nh.subscribe("ground_truth/robots", 100, &Recorder::robotArray, &rec_));
    subs_.push_back(nh.subscribe("ground_truth/balls", 100, &Recorder::ballArray, &rec_));
    subs_.push_back(nh.subscribe("ground_truth/ball", 100, &Recorder::firstBall, &rec_));
    camera_ =
        sv::CameraModel::defaultCamera(sv::FieldGeometry{}, params_.camera_id, params_.width, params_.height);
  }

  // Collects `params_.frames` frames (after the first few, once every subscriber is
  // connected) and gives in-flight companions a moment to arrive.
  void collect() {
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(45.0);
    while (rec_.imageCount() < static_cast<std::size_t>(params_.frames + 5) &&
           ros::WallTime::now() < deadline)
      ros::WallDuration(0.01).sleep();
    ros::WallDuration(0.5).sleep();
    std::lock_guard<std::mutex> l(rec_.mutex);
    ASSERT_GE(rec_.images.size(), static_cast<std::size_t>(params_.frames + 5))
        << "too few images on " << ros::names::resolve("image_raw");
    // Drop the first frames: ground-truth subscriptions may connect after the image one.
    images_.assign(rec_.images.begin() + 5, rec_.images.end());
  }

  Params params_;
  Recorder rec_;
  std::vector<ros::Subscriber> subs_;
  sv::CameraModel camera_;
  std::vector<sensor_msgs::ImageConstPtr> images_;
};

TEST_F(CameraDriverTest, ImagesCameraInfoAndStamps) {
  collect();
  std::lock_guard<std::mutex> l(rec_.mutex);
  const double period = 1.0 / params_.fps;
  const ros::Time t0 = images_.front()->header.stamp;
  int matched = 0;
  for (std::size_t i = 0; i < images_.size(); ++i) {
    const sensor_msgs::Image& im = *images_[i];
    EXPECT_EQ(im.encoding, params_.encoding);
    EXPECT_EQ(static_cast<int>(im.width), params_.width);
    EXPECT_EQ(static_cast<int>(im.height), params_.height);
    EXPECT_EQ(im.data.size(), static_cast<std::size_t>(im.step) * im.height);
    EXPECT_EQ(im.header.frame_id, "camera_" + std::to_string(params_.camera_id) + "_optical");
    if (i > 0) {
      EXPECT_GT(im.header.stamp, images_[i - 1]->header.stamp) << "stamps must increase";
    }
    // Capture times lie on the frame grid (1/fps apart, gaps only for dropped frames).
    const double steps = (im.header.stamp - t0).toSec() / period;
    EXPECT_NEAR(steps, std::round(steps), 1e-4);

    auto it = rec_.infos.find(im.header.stamp);
    if (it == rec_.infos.end()) continue;
    ++matched;
    const sensor_msgs::CameraInfo& ci = *it->second;
    EXPECT_EQ(ci.header.frame_id, im.header.frame_id);
    EXPECT_EQ(ci.width, im.width);
    EXPECT_EQ(ci.height, im.height);
  }
  EXPECT_GE(matched, static_cast<int>(images_.size()) - 1)
      << "every image needs a camera_info with the identical stamp";
  EXPECT_GE(matched, 20);

  // camera_info: the synthetic camera's true calibration as plumb_bob.
  const sensor_msgs::CameraInfo& ci = *rec_.infos.begin()->second;
  const sv::CameraIntrinsics& k = camera_.intrinsics();
  EXPECT_EQ(ci.distortion_model, "plumb_bob");
  ASSERT_EQ(ci.D.size(), 5u);
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(ci.D[i], k.dist[i], 1e-9);
  EXPECT_NEAR(ci.K[0], k.fx, 1e-6);
  EXPECT_NEAR(ci.K[2], k.cx, 1e-6);
  EXPECT_NEAR(ci.K[4], k.fy, 1e-6);
  EXPECT_NEAR(ci.K[5], k.cy, 1e-6);
  EXPECT_NEAR(ci.P[0], k.fx, 1e-6);
  EXPECT_NEAR(ci.P[5], k.fy, 1e-6);
}

TEST_F(CameraDriverTest, StaticTfIsTheTrueCameraPose) {
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  const std::string frame = "camera_" + std::to_string(params_.camera_id) + "_optical";
  geometry_msgs::TransformStamped t;
  ASSERT_NO_THROW(t = buffer.lookupTransform("field", frame, ros::Time(0), ros::Duration(10.0)));
  const Eigen::Isometry3d& pose = camera_.fieldTCamera();
  EXPECT_NEAR(t.transform.translation.x, pose.translation().x(), 1e-6);
  EXPECT_NEAR(t.transform.translation.y, pose.translation().y(), 1e-6);
  EXPECT_NEAR(t.transform.translation.z, pose.translation().z(), 1e-6);
  const Eigen::Quaterniond q(pose.rotation());
  const Eigen::Quaterniond r(t.transform.rotation.w, t.transform.rotation.x, t.transform.rotation.y,
                             t.transform.rotation.z);
  EXPECT_NEAR(std::abs(q.dot(r)), 1.0, 1e-9);
}

TEST_F(CameraDriverTest, GroundTruthMatchesRenderedFrames) {
  collect();
  std::lock_guard<std::mutex> l(rec_.mutex);
  const sv::PatternSet pattern = sv::PatternSet::twoTag();
  int robot_checks = 0, robot_ok = 0, ball_checks = 0, ball_ok = 0, gt_frames = 0;
  int visible_robots = 0, invisible_robots = 0;
  std::string mismatches;
  for (const sensor_msgs::ImageConstPtr& msg : images_) {
    const ros::Time stamp = msg->header.stamp;
    auto rit = rec_.robots.find(stamp);
    auto bit = rec_.balls.find(stamp);
    if (rit == rec_.robots.end() || bit == rec_.balls.end()) continue;
    ++gt_frames;

    cv::Mat bgr;
    const cv_bridge::CvImageConstPtr cv = cv_bridge::toCvShare(msg);
    const int code = sv::bayerToBgrCode(msg->encoding);
    if (code >= 0) {
      cv::cvtColor(cv->image, bgr, code);
    } else {
      bgr = cv->image;
    }
    ASSERT_EQ(bgr.type(), CV_8UC3);

    for (const soccer_vision::RobotPose& r : rit->second->robots) {
      EXPECT_EQ(r.header.frame_id, "field");
      EXPECT_EQ(r.header.stamp, stamp);
      EXPECT_EQ(r.camera_id, params_.camera_id);
      EXPECT_FLOAT_EQ(r.confidence, 1.0f);
      EXPECT_GT(r.theta, -M_PI);
      EXPECT_LE(r.theta, M_PI);
      if (!r.visible) {
        ++invisible_robots;
        continue;
      }
      ++visible_robots;
      const double c = std::cos(r.theta), s = std::sin(r.theta);
      const double mx = pattern.team_marker.x, my = pattern.team_marker.y;
      const Eigen::Vector3d p(r.x + c * mx - s * my, r.y + s * mx + c * my, pattern.robot_height);
      const auto px = camera_.project(p);
      ASSERT_TRUE(px.has_value());
      ASSERT_TRUE(camera_.inImage(*px)) << "visible robot projects outside the image";
      const int u = static_cast<int>(std::lround(px->x()));
      const int v = static_cast<int>(std::lround(px->y()));
      const sv::ColorClass expected =
          r.team == soccer_vision::RobotPose::TEAM_BLUE ? sv::ColorClass::Blue : sv::ColorClass::Yellow;
      ++robot_checks;
      const sv::ColorClass got = nearestClass(bgr.at<cv::Vec3b>(v, u));
      if (got == expected) {
        ++robot_ok;
      } else if (mismatches.size() < 5) {
        std::ostringstream os;
        os << "\n  " << (r.team == soccer_vision::RobotPose::TEAM_BLUE ? "blue" : "yellow") << " "
           << int(r.id) << " at (" << r.x << ", " << r.y << ") -> pixel (" << u << ", " << v << ") shows "
           << sv::colorClassName(got);
        mismatches += os.str();
      }
    }
    ASSERT_FALSE(bit->second->balls.empty());
    for (const soccer_vision::BallPose& b : bit->second->balls) {
      EXPECT_EQ(b.header.frame_id, "field");
      EXPECT_FLOAT_EQ(b.confidence, 1.0f);
      if (!b.visible) continue;
      const auto px = camera_.project(Eigen::Vector3d(b.x, b.y, b.z));
      ASSERT_TRUE(px.has_value());
      const int u = static_cast<int>(std::lround(px->x()));
      const int v = static_cast<int>(std::lround(px->y()));
      ++ball_checks;
      if (nearestClass(bgr.at<cv::Vec3b>(v, u)) == sv::ColorClass::Orange) ++ball_ok;
    }
    // The single-ball topic carries the first ball of the array.
    auto one = rec_.ball.find(stamp);
    if (one != rec_.ball.end()) {
      EXPECT_DOUBLE_EQ(one->second->x, bit->second->balls.front().x);
      EXPECT_DOUBLE_EQ(one->second->y, bit->second->balls.front().y);
    }
  }
  EXPECT_GE(gt_frames, 20) << "ground truth must come with the images (same stamps)";
  EXPECT_GE(visible_robots, 2 * gt_frames) << "too few robots in view to test anything";
  std::printf(
      "[ ground truth ] %d frames, team colour at %d of %d visible robots, orange at %d "
      "of %d visible balls, %d robot samples out of view\n",
      gt_frames, robot_ok, robot_checks, ball_ok, ball_checks, invisible_robots);
  ASSERT_GT(robot_checks, 0);
  const double robot_rate = static_cast<double>(robot_ok) / robot_checks;
  EXPECT_GE(robot_rate, params_.min_color_match)
      << robot_ok << " of " << robot_checks
      << " team markers show the team colour; first misses:" << mismatches;
  if (ball_checks > 0) {
    EXPECT_GE(static_cast<double>(ball_ok) / ball_checks, params_.min_color_match)
        << ball_ok << " of " << ball_checks << " balls show orange";
  }
}

// dynamic_reconfigure: brightness and fps change the published frames from the next frame
// on (only where the launch file sets ~test_reconfigure, as it changes the driver).
TEST_F(CameraDriverTest, ReconfigureBrightnessAndFps) {
  bool enabled = false;
  std::string driver = "camera_driver";
  ros::NodeHandle("~").param("test_reconfigure", enabled, false);
  ros::NodeHandle("~").param("driver", driver, driver);
  if (!enabled) GTEST_SKIP() << "~test_reconfigure is false";

  auto mean_level = [](const std::vector<sensor_msgs::ImageConstPtr>& images) {
    double sum = 0;
    for (const auto& m : images) {
      const cv::Scalar mean = cv::mean(cv_bridge::toCvShare(m)->image);
      sum += (mean[0] + mean[1] + mean[2]) / 3.0;
    }
    return sum / images.size();
  };
  auto reconfigure = [&](double brightness, double fps) {
    dynamic_reconfigure::Reconfigure srv;
    dynamic_reconfigure::DoubleParameter p;
    p.name = "brightness";
    p.value = brightness;
    srv.request.config.doubles.push_back(p);
    p.name = "fps";
    p.value = fps;
    srv.request.config.doubles.push_back(p);
    const std::string service = ros::names::resolve(driver + "/set_parameters");
    EXPECT_TRUE(ros::service::waitForService(service, ros::Duration(10.0))) << service;
    EXPECT_TRUE(ros::service::call(service, srv)) << service;
    std::lock_guard<std::mutex> l(rec_.mutex);
    rec_.images.clear();
  };
  auto after_change = [&](std::size_t n) {
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(20.0);
    while (rec_.imageCount() < n + 2 && ros::WallTime::now() < deadline) ros::WallDuration(0.01).sleep();
    std::lock_guard<std::mutex> l(rec_.mutex);
    // The frame in flight during the call may still have the old settings.
    return std::vector<sensor_msgs::ImageConstPtr>(
        rec_.images.begin() + std::min<std::size_t>(2, rec_.images.size()), rec_.images.end());
  };

  collect();
  const double before = mean_level(images_);
  reconfigure(0.5, params_.fps / 2);
  const std::vector<sensor_msgs::ImageConstPtr> dim = after_change(10);
  ASSERT_GE(dim.size(), 10u);
  const double after = mean_level(dim);
  std::printf("[ reconfigure ] mean level %.1f at brightness 1, %.1f at 0.5\n", before, after);
  EXPECT_LT(after, 0.75 * before) << "brightness 0.5 must darken the frames";
  EXPECT_GT(after, 0.25 * before);
  for (std::size_t i = 1; i < dim.size(); ++i)
    EXPECT_NEAR((dim[i]->header.stamp - dim[i - 1]->header.stamp).toSec(), 2.0 / params_.fps, 1e-4)
        << "frames must come at the new rate";

  reconfigure(1.0, params_.fps);
  const std::vector<sensor_msgs::ImageConstPtr> back = after_change(10);
  ASSERT_GE(back.size(), 10u);
  EXPECT_NEAR(mean_level(back), before, 0.1 * before);
  for (std::size_t i = 1; i < back.size(); ++i)
    EXPECT_NEAR((back[i]->header.stamp - back[i - 1]->header.stamp).toSec(), 1.0 / params_.fps, 1e-4);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_camera_driver");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int result = RUN_ALL_TESTS();
  spinner.stop();
  ros::shutdown();
  return result;
}
