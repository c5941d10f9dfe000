// The whole vision system of launch/demo.launch (one manager: synthetic CameraDriver ->
// Segmentation -> Identification -> Tracking) against the simulator's ground truth:
// detection rate, precision, identity errors, position and heading RMSE of the tracked
// robots, the ball; every output stamp is a capture stamp; tf frames; search windows in
// use; the driver's image buffer is the one segmentation reads (zero copy).
//
// Private parameters: ~duration [s] of scoring after the first tracked output (default 10;
// with a bag, at most that: scoring ends when the bag has been played, its player gone),
// ~first_output_within [s] of the test's start (default 60),
// ~check_zero_copy (default true; false for images from rosbag play),
// ~min_detection, ~min_precision, ~max_position_rmse [m], ~max_heading_rmse [deg],
// ~min_ball_detection, ~min_ball_precision (the targets of the scenario under test),
// ~bag (the recording played, if any: its camera_info stamps are the frames' stamps),
// ~min_frames scored (default 60: a sample, not a speed; how many frames a loaded machine
// keeps up with is the benchmarks' business).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <std_msgs/UInt64MultiArray.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "soccer_vision/BallPoseArray.h"
#include "soccer_vision/RobotPoseArray.h"
#include "soccer_vision/SearchWindows.h"
#include "soccer_vision/evaluation/scoring.h"
#include "soccer_vision/ros/conversions.h"

using namespace soccer_vision;

namespace {

struct Recorder {
  std::mutex mutex;
  std::set<ros::Time> image_stamps;
  std::map<ros::Time, RobotPoseArrayConstPtr> truth_robots, robots;
  std::map<ros::Time, BallPoseArrayConstPtr> truth_balls, balls;
  std::map<ros::Time, std::uint64_t> published, segmented;
  std::size_t windows_msgs = 0, windowed_msgs = 0;
  ros::WallTime first_output, last_output;
  double longest_gap = 0;  // [s] wall time between two outputs: a stalled pipeline shows here
};

template <typename M, typename F>
ros::Subscriber sub(ros::NodeHandle& nh, const std::string& topic, F f) {
  return nh.subscribe<M>(topic, 200, boost::function<void(const boost::shared_ptr<const M>&)>(f));
}

double param(const std::string& name, double fallback) {
  double v = fallback;
  ros::NodeHandle("~").param(name, v, fallback);
  return v;
}

}  // namespace

TEST(VisionPipeline, TrackedGameMatchesTheGroundTruth) {
  ros::NodeHandle nh;
  Recorder rec;
  auto address = [&rec](std::map<ros::Time, std::uint64_t>& into) {
    return [&rec, &into](const std_msgs::UInt64MultiArrayConstPtr& m) {
      if (m->data.size() < 3) return;
      std::lock_guard<std::mutex> lock(rec.mutex);
      into[ros::Time(static_cast<std::uint32_t>(m->data[0]), static_cast<std::uint32_t>(m->data[1]))] =
          m->data[2];
    };
  };
  std::vector<ros::Subscriber> subs;
  subs.push_back(sub<sensor_msgs::CameraInfo>(nh, "/camera_0/camera_info",
                                              [&](const sensor_msgs::CameraInfoConstPtr& m) {
                                                std::lock_guard<std::mutex> lock(rec.mutex);
                                                rec.image_stamps.insert(m->header.stamp);
                                              }));
  subs.push_back(
      sub<RobotPoseArray>(nh, "/camera_0/ground_truth/robots", [&](const RobotPoseArrayConstPtr& m) {
        std::lock_guard<std::mutex> lock(rec.mutex);
        rec.truth_robots[m->header.stamp] = m;
      }));
  subs.push_back(sub<BallPoseArray>(nh, "/camera_0/ground_truth/balls", [&](const BallPoseArrayConstPtr& m) {
    std::lock_guard<std::mutex> lock(rec.mutex);
    rec.truth_balls[m->header.stamp] = m;
  }));
  subs.push_back(sub<RobotPoseArray>(nh, "/vision/robots", [&](const RobotPoseArrayConstPtr& m) {
    std::lock_guard<std::mutex> lock(rec.mutex);
    const ros::WallTime now = ros::WallTime::now();
    if (rec.robots.empty())
      rec.first_output = now;
    else
      rec.longest_gap = std::max(rec.longest_gap, (now - rec.last_output).toSec());
    rec.last_output = now;
    rec.robots[m->header.stamp] = m;
  }));
  subs.push_back(sub<BallPoseArray>(nh, "/vision/balls", [&](const BallPoseArrayConstPtr& m) {
    std::lock_guard<std::mutex> lock(rec.mutex);
    rec.balls[m->header.stamp] = m;
  }));
  subs.push_back(sub<SearchWindows>(nh, "/camera_0/search_windows", [&](const SearchWindowsConstPtr& m) {
    std::lock_guard<std::mutex> lock(rec.mutex);
    ++rec.windows_msgs;
    rec.windowed_msgs += !m->global_search && !m->windows.empty();
  }));
  subs.push_back(nh.subscribe<std_msgs::UInt64MultiArray>("/camera_0/debug/published_address", 200,
                                                          address(rec.published)));
  subs.push_back(nh.subscribe<std_msgs::UInt64MultiArray>("/camera_0/debug/image_data_address", 200,
                                                          address(rec.segmented)));
  tf2_ros::Buffer tf_buffer;
  tf2_ros::TransformListener tf_listener(tf_buffer);

  ros::AsyncSpinner spinner(2);
  spinner.start();
  const double duration = param("duration", 10.0);
  // Start-up: the colour table is calibrated and loaded, the game starts (for a bag: the
  // recording is made and calibrated first, over a minute on a loaded machine). Then the
  // whole scoring duration after the first output, however late that came: a single
  // deadline from the start scored 3 frames once, when the first output came just before it.
  const double first_output_within = param("first_output_within", 60.0);
  const ros::WallTime give_up = ros::WallTime::now() + ros::WallDuration(first_output_within);
  // A bag is scored whole, until its player has left (the camera_info subscription has no
  // publisher any more): beside the vision system, rosbag play stalled for up to 9 s at the
  // start, and a fixed time after the first output scored 1 frame of 480 once (CI).
  // Gone means gone for a second, and why scoring ended goes into the failure message: a CI
  // run scored 41 frames of 480 once (2026-12-07), and a run by hand received 287 outputs of
  // 480, the player and the vision system competing for 2 cores (play_scenario.sh plays at
  // half rate since); a single look that finds no publisher could end scoring early too.
  const bool from_bag = !ros::NodeHandle("~").param("bag", std::string()).empty();
  std::optional<ros::WallTime> player_last_seen;
  const ros::WallTime start = ros::WallTime::now();
  std::string scoring_ended;  // why and when, for the figures' failure messages
  while (ros::ok()) {
    const ros::WallTime now = ros::WallTime::now();
    if (subs.front().getNumPublishers() > 0) player_last_seen = now;
    const bool player_gone = from_bag && player_last_seen && (now - *player_last_seen).toSec() > 1.0;
    {
      std::lock_guard<std::mutex> lock(rec.mutex);
      const char* why = nullptr;
      if (rec.robots.empty()) {
        if (now > give_up) why = "no output came";
      } else if ((now - rec.first_output).toSec() > duration) {
        why = "the duration has passed";
      } else if (player_gone) {
        why = "the bag's player has left";
      }
      if (why) {
        scoring_ended =
            std::string(why) + ", " + std::to_string((now - start).toSec()) + " s after the start";
        std::printf("[ vision pipeline ] scoring ends: %s\n", scoring_ended.c_str());
        break;
      }
    }
    ros::WallDuration(0.1).sleep();
  }
  // tf while the game runs: the camera's pose and a tracked robot's frame.
  std::string robot_frame;
  RobotPose robot;
  {
    std::lock_guard<std::mutex> lock(rec.mutex);
    ASSERT_FALSE(rec.robots.empty()) << "no /vision/robots within " << first_output_within << " s";
    for (const RobotPose& r : rec.robots.rbegin()->second->robots) {
      if (r.visible && r.id != 255) {
        robot = r;
        robot_frame = std::string("robot/") + (r.team == RobotPose::TEAM_BLUE ? "blue_" : "yellow_") +
                      std::to_string(r.id);
        break;
      }
    }
  }
  EXPECT_TRUE(tf_buffer.canTransform("field", "camera_0_optical", ros::Time(0), ros::Duration(2.0)));
  ASSERT_FALSE(robot_frame.empty()) << "no measured robot in the last output";
  ASSERT_TRUE(tf_buffer.canTransform("field", robot_frame, robot.header.stamp, ros::Duration(2.0)))
      << robot_frame;
  const auto t = tf_buffer.lookupTransform("field", robot_frame, robot.header.stamp);
  EXPECT_NEAR(t.transform.translation.x, robot.x, 1e-6);
  EXPECT_NEAR(t.transform.translation.y, robot.y, 1e-6);
  EXPECT_NEAR(2 * std::atan2(t.transform.rotation.z, t.transform.rotation.w), robot.theta, 1e-6);
  spinner.stop();
  for (auto& s : subs) s.shutdown();

  std::lock_guard<std::mutex> lock(rec.mutex);
  // Every output carries the capture stamp of a camera frame. With a bag, the frames are its
  // camera_info stamps: what the test received cannot tell, as a loaded machine dropped 0.5 s
  // of every topic for the test's subscriptions once, but two robots messages from that
  // stretch arrived (CI of 2026-12-05, beside a held-out run). Live, one of a camera_info or
  // of the ground truth, which come with every frame, between the first and the last
  // camera_info received: earlier frames were before its subscription was connected; at the
  // end, a loaded machine may run the callback of the last robots message before the one of
  // its camera_info when the subscriptions are shut down.
  ASSERT_FALSE(rec.image_stamps.empty());
  std::set<ros::Time> frame_stamps = rec.image_stamps;
  std::string bag_path;
  ros::NodeHandle("~").param("bag", bag_path, std::string());
  if (!bag_path.empty()) {
    rosbag::Bag bag(bag_path, rosbag::bagmode::Read);
    for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery("/camera_0/camera_info"))) {
      if (const auto info = m.instantiate<sensor_msgs::CameraInfo>()) frame_stamps.insert(info->header.stamp);
    }
  }
  for (const auto& [stamp, msg] : rec.truth_robots) frame_stamps.insert(stamp);
  for (const auto& [stamp, msg] : rec.truth_balls) frame_stamps.insert(stamp);
  std::size_t foreign = 0;
  for (const auto& [stamp, msg] : rec.robots) {
    const bool inside =
        !bag_path.empty() || (stamp > *rec.image_stamps.begin() && stamp < *rec.image_stamps.rbegin());
    if (inside && !frame_stamps.count(stamp)) {
      ++foreign;
      const auto after = frame_stamps.upper_bound(stamp);
      std::printf("[ foreign stamp ] robots at %u.%09u; the frames around it: %.6f and %.6f\n", stamp.sec,
                  stamp.nsec, after == frame_stamps.begin() ? 0.0 : std::prev(after)->toSec(),
                  after == frame_stamps.end() ? 0.0 : after->toSec());
    }
    for (const RobotPose& r : msg->robots) ASSERT_EQ(r.header.stamp, stamp);
  }
  EXPECT_EQ(foreign, 0u) << "robots messages whose stamp is no frame's";

  // Scored: the frames whose robot and ball truth and ball output this test all received.
  // Tracking publishes robots and balls for every frame; a missing message before the first
  // one of its topic is a subscription that was still connecting (each topic connects on its
  // own; under load that took 0.7 s, 40 frames), not a frame without a ball. After the first
  // one, a missing message is a lost one, counted.
  Score score;
  std::size_t without_ball_truth = 0, before_ball_truth = 0, without_balls = 0, before_balls = 0;
  std::vector<std::int64_t> missed_ball_frames;  // scored frame indices
  ASSERT_FALSE(rec.truth_balls.empty()) << "no ground_truth/balls";
  ASSERT_FALSE(rec.balls.empty()) << "no /vision/balls";
  const ros::Time first_ball_truth = rec.truth_balls.begin()->first;
  const ros::Time first_balls = rec.balls.begin()->first;
  for (const auto& [stamp, msg] : rec.robots) {
    const auto truth = rec.truth_robots.find(stamp);
    const auto tb = rec.truth_balls.find(stamp);
    if (truth == rec.truth_robots.end()) continue;
    if (tb == rec.truth_balls.end()) {
      ++(stamp < first_ball_truth ? before_ball_truth : without_ball_truth);
      continue;
    }
    const auto b = rec.balls.find(stamp);
    if (b == rec.balls.end()) {
      ++(stamp < first_balls ? before_balls : without_balls);
      continue;
    }
    const FrameRecord truth_frame = toFrameRecord(*truth->second, *tb->second);
    const FrameRecord result_frame = toFrameRecord(*msg, *b->second);
    const Score frame = scoreFrame(truth_frame, result_frame);
    // A wrong ball says where and when, so that a failure can be understood from the log.
    if (frame.false_balls > 0 && score.false_balls < 20) {
      const BallRecord& r = result_frame.balls.front();
      std::printf("[ false ball ] stamp %.4f (frame %ld of the recording): reported (%.3f, %.3f) %s; truth:",
                  stamp.toSec(), static_cast<long>(score.frames), r.x, r.y,
                  r.visible.value_or(true) ? "measured" : "coasting");
      for (const BallRecord& t : truth_frame.balls)
        std::printf(" (%.3f, %.3f) %s", t.x, t.y, t.visible.value_or(true) ? "in view" : "out of view");
      std::printf("\n");
    }
    // A missed ball too: the first frames of a stretch of misses say what went wrong.
    if (frame.matched_balls < frame.truth_balls) {
      if (missed_ball_frames.size() < 20) {
        std::printf("[ missed ball ] stamp %.4f (frame %ld): truth", stamp.toSec(),
                    static_cast<long>(score.frames));
        for (const BallRecord& t : truth_frame.balls) std::printf(" (%.3f, %.3f)", t.x, t.y);
        std::printf("; reported");
        for (const BallRecord& r : result_frame.balls)
          std::printf(" (%.3f, %.3f) %s", r.x, r.y, r.visible.value_or(true) ? "measured" : "coasting");
        std::printf("\n");
      }
      missed_ball_frames.push_back(score.frames);
    }
    score.add(frame);
  }
  std::printf(
      "[ vision pipeline ] outputs not scored: %zu without ball truth (%zu more before the first), %zu "
      "without /vision/balls (%zu more before the first)\n",
      without_ball_truth, before_ball_truth, without_balls, before_balls);
  EXPECT_LE(without_ball_truth, 30u) << "the ball truth must come with the frames";
  EXPECT_LE(without_balls, 30u) << "/vision/balls must come with /vision/robots";
  std::printf(
      "[ vision pipeline ] %ld frames: robots detection %.3f %% (%ld/%ld), precision %.3f %%, identity "
      "errors "
      "%ld, position RMSE %.2f mm, heading RMSE %.3f deg; ball detection %.3f %% (%ld/%ld), precision %.3f "
      "%%, "
      "RMSE %.2f mm; %zu of %zu window messages windowed; received %zu outputs (longest gap %.2f s), %zu "
      "ground truths, %zu camera_infos\n",
      static_cast<long>(score.frames), 100 * score.robotDetectionRate(),
      static_cast<long>(score.matched_robots), static_cast<long>(score.truth_robots),
      100 * score.robotPrecision(), static_cast<long>(score.identity_errors), 1e3 * score.robotPositionRmse(),
      score.robotHeadingRmse() * 180 / M_PI, 100 * score.ballDetectionRate(),
      static_cast<long>(score.matched_balls), static_cast<long>(score.truth_balls),
      100 * score.ballPrecision(), 1e3 * score.ballPositionRmse(), rec.windowed_msgs, rec.windows_msgs,
      rec.robots.size(), rec.longest_gap, rec.truth_robots.size(), rec.image_stamps.size());
  EXPECT_GE(score.frames,
            static_cast<std::int64_t>(param("min_frames", 60.0)))  // a sample that means something
      << "scoring ended: " << scoring_ended << "; " << rec.robots.size() << " outputs received";
  EXPECT_GT(score.truth_robots, 3 * score.frames);  // robots were in view
  EXPECT_GE(score.robotDetectionRate(), param("min_detection", 0.999));
  EXPECT_GE(score.robotPrecision(), param("min_precision", 0.9995));
  EXPECT_EQ(score.identity_errors, 0);
  EXPECT_LE(score.robotPositionRmse(), param("max_position_rmse", 0.005));
  EXPECT_LE(score.robotHeadingRmse() * 180 / M_PI, param("max_heading_rmse", 1.0));
  if (score.truth_balls > 0) {
    EXPECT_GE(score.ballDetectionRate(), param("min_ball_detection", 0.98))
        << missed_ball_frames.size() << " frames missed the ball, the first " << missed_ball_frames.front()
        << ", the last " << missed_ball_frames.back() << " of " << score.frames;
    EXPECT_GE(score.ballPrecision(), param("min_ball_precision", 0.98));
  }
  // Tracking feeds windows back: most frames are searched in windows, not whole.
  EXPECT_GT(rec.windowed_msgs, rec.windows_msgs * 8 / 10);

  // Zero copy: for every frame seen by both, segmentation read the driver's buffer (not
  // with rosbag play, whose images arrive serialised).
  bool check_zero_copy = true;
  ros::NodeHandle("~").param("check_zero_copy", check_zero_copy, true);
  if (!check_zero_copy) return;
  std::size_t compared = 0, same = 0;
  for (const auto& [stamp, addr] : rec.segmented) {
    const auto it = rec.published.find(stamp);
    if (it == rec.published.end()) continue;
    ++compared;
    same += it->second == addr;
  }
  EXPECT_GT(compared, 100u);
  EXPECT_EQ(same, compared) << "frames segmented from another buffer than the one published";
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_vision_pipeline");
  return RUN_ALL_TESTS();
}
