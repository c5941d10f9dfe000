// demo_monitor: watches one camera of the running vision system for a while, prints a
// summary and writes an annotated snapshot. Used by `demo.launch headless:=true`.
//
//   demo_monitor [--duration SECONDS] [--snapshot PATH]
//
// Parameters (private):
//   ~camera    string "camera_0"   camera namespace: subscribes <camera>/image_raw,
//                                   <camera>/camera_info, <camera>/ground_truth/robots and
//                                   <camera>/ground_truth/balls
//   ~camera_id int    0            synthetic camera index, of the scenario's layout, used to
//   ~scenario  string ""           project the ground truth onto the snapshot through the scenario's
//                                   camera (scenarioCamera; "" = the embedded default scenario)
//   ~duration  double 10           [s] run time (the --duration option wins); 0 = until Ctrl-C
//   ~snapshot  string "./soccer_vision_snapshot.png"  annotated PNG of the last frame
//
//   ~vision    string "/vision"    namespace of the tracking outputs: subscribes
//                                   <vision>/robots and <vision>/balls
//
// Summary: frames received, rate [Hz], latency (receipt - capture stamp: mean, p99, max),
// visible robots/balls per frame from the ground truth, encoding and resolution; and, when
// the tracking outputs arrive, their rate and latency (capture stamp -> receipt, p50/p99)
// and their score against the ground truth of the same stamps (scoring.h: detection rate,
// precision, identity errors, position and heading RMSE, ball detection and RMSE) over the
// frames whose four messages all arrived (printTrackingScore).
// Exit status: 0 after a run with frames, 1 when no frame arrived, 2 on bad arguments,
// 3 when the snapshot could not be written.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <cv_bridge/cv_bridge.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include "soccer_vision/BallPoseArray.h"
#include "soccer_vision/RobotPoseArray.h"
#include "soccer_vision/common/bayer_encoding.h"
#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/common/statistics.h"
#include "soccer_vision/evaluation/scoring.h"
#include "soccer_vision/ros/conversions.h"
#include "soccer_vision/ros/package_paths.h"
#include "soccer_vision/simulation/scenario.h"
#include "soccer_vision/simulation/scenario_camera.h"
#include "tool_command_line.h"

namespace sv = soccer_vision;

namespace {

struct Monitor {
  std::mutex mutex;
  std::size_t frames = 0;
  ros::WallTime first_receipt, last_receipt;
  std::vector<double> latencies;  // [s]
  sensor_msgs::ImageConstPtr last_image;
  std::deque<sensor_msgs::ImageConstPtr> recent;  // newest last, for the snapshot
  std::size_t camera_infos = 0;
  std::map<ros::Time, soccer_vision::RobotPoseArrayConstPtr> robots;  // recent, by stamp
  std::map<ros::Time, soccer_vision::BallPoseArrayConstPtr> balls;
  std::size_t gt_frames = 0, visible_robot_sum = 0, visible_ball_sum = 0;
  // Tracking outputs and the ground truth they are scored against, by stamp.
  std::map<ros::Time, soccer_vision::RobotPoseArrayConstPtr> truth_robots, result_robots;
  std::map<ros::Time, soccer_vision::BallPoseArrayConstPtr> truth_balls, result_balls;
  std::vector<double> result_latencies;  // [s]
  ros::WallTime first_result, last_result;

  void resultRobots(const soccer_vision::RobotPoseArrayConstPtr& msg) {
    const ros::WallTime now = ros::WallTime::now();
    const double latency = ros::Time::now().toSec() - msg->header.stamp.toSec();
    std::lock_guard<std::mutex> lock(mutex);
    if (result_robots.empty()) first_result = now;
    last_result = now;
    result_robots[msg->header.stamp] = msg;
    result_latencies.push_back(latency);
  }
  void resultBalls(const soccer_vision::BallPoseArrayConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex);
    result_balls[msg->header.stamp] = msg;
  }

  void image(const sensor_msgs::ImageConstPtr& msg) {
    const ros::WallTime now = ros::WallTime::now();
    const double latency = ros::Time::now().toSec() - msg->header.stamp.toSec();
    std::lock_guard<std::mutex> lock(mutex);
    if (frames == 0) first_receipt = now;
    last_receipt = now;
    ++frames;
    latencies.push_back(latency);
    last_image = msg;
    recent.push_back(msg);
    if (recent.size() > 10) recent.pop_front();
  }
  void info(const sensor_msgs::CameraInfoConstPtr&) {
    std::lock_guard<std::mutex> lock(mutex);
    ++camera_infos;
  }
  void robotArray(const soccer_vision::RobotPoseArrayConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex);
    robots[msg->header.stamp] = msg;
    truth_robots[msg->header.stamp] = msg;
    while (robots.size() > 120) robots.erase(robots.begin());
    ++gt_frames;
    for (const auto& r : msg->robots) visible_robot_sum += r.visible ? 1 : 0;
  }
  void ballArray(const soccer_vision::BallPoseArrayConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex);
    balls[msg->header.stamp] = msg;
    truth_balls[msg->header.stamp] = msg;
    while (balls.size() > 120) balls.erase(balls.begin());
    for (const auto& b : msg->balls) visible_ball_sum += b.visible ? 1 : 0;
  }
};

// The tracking outputs against the ground truth of the same stamps (mutex held).
void printTrackingScore(const Monitor& m) {
  if (m.result_robots.empty()) {
    std::printf("  tracking          no %s received\n", "robots");
    return;
  }
  // Scored: the frames whose robots and balls, output and truth, all arrived. Each topic's
  // subscription connects on its own (under load the second one 0.7 s after the first:
  // test_vision_pipeline), and the run may end between a frame's messages; such a frame,
  // scored, counted a ball the vision system had not missed (its balls message not yet
  // received) or a false one (its truth's). Frames left out before a topic's first
  // message or after its last are counted apart from ones lost between.
  sv::Score score;
  long connecting = 0, lost = 0;
  const ros::Time first_balls = m.result_balls.empty() ? ros::TIME_MAX : m.result_balls.begin()->first;
  const ros::Time last_balls = m.result_balls.empty() ? ros::TIME_MIN : m.result_balls.rbegin()->first;
  const ros::Time first_truth = m.truth_balls.empty() ? ros::TIME_MAX : m.truth_balls.begin()->first;
  const ros::Time last_truth = m.truth_balls.empty() ? ros::TIME_MIN : m.truth_balls.rbegin()->first;
  for (const auto& [stamp, robots] : m.result_robots) {
    const auto truth = m.truth_robots.find(stamp);
    if (truth == m.truth_robots.end()) continue;  // other camera's frame, or before the truth
    const auto truth_balls = m.truth_balls.find(stamp);
    const auto balls = m.result_balls.find(stamp);
    if (truth_balls == m.truth_balls.end() || balls == m.result_balls.end()) {
      const bool outside =
          stamp < std::max(first_balls, first_truth) || stamp > std::min(last_balls, last_truth);
      ++(outside ? connecting : lost);
      continue;
    }
    score.add(sv::scoreFrame(sv::toFrameRecord(*truth->second, *truth_balls->second),
                             sv::toFrameRecord(*robots, *balls->second)));
  }
  const double span = (m.last_result - m.first_result).toSec();
  const double rate = m.result_robots.size() > 1 && span > 0 ? (m.result_robots.size() - 1) / span : 0.0;
  std::printf("  tracking outputs  %zu at %.2f Hz, latency capture -> receipt p50 %.2f ms, p99 %.2f ms\n",
              m.result_robots.size(), rate, 1e3 * sv::percentile(m.result_latencies, 50),
              1e3 * sv::percentile(m.result_latencies, 99));
  std::printf(
      "  scored frames     %ld (robots and balls, output and truth, of one stamp); left out: %ld "
      "before or after a topic's first or last message, %ld lost\n",
      static_cast<long>(score.frames), connecting, lost);
  std::printf("  robots            detection %.3f %% (%ld of %ld), precision %.3f %%, identity errors %ld\n",
              100 * score.robotDetectionRate(), static_cast<long>(score.matched_robots),
              static_cast<long>(score.truth_robots), 100 * score.robotPrecision(),
              static_cast<long>(score.identity_errors));
  std::printf("  robot error       position RMSE %.2f mm, heading RMSE %.3f deg\n",
              1e3 * score.robotPositionRmse(), score.robotHeadingRmse() * 180 / M_PI);
  std::printf("  ball              detection %.3f %% (%ld of %ld), precision %.3f %%, RMSE %.2f mm\n",
              100 * score.ballDetectionRate(), static_cast<long>(score.matched_balls),
              static_cast<long>(score.truth_balls), 100 * score.ballPrecision(),
              1e3 * score.ballPositionRmse());
}

// Draws the ground truth of one frame onto `bgr` (ground truth projected with the
// synthetic camera model).
void annotate(cv::Mat& bgr, const sv::CameraModel& camera,
              const soccer_vision::RobotPoseArrayConstPtr& robots,
              const soccer_vision::BallPoseArrayConstPtr& balls) {
  const double scale = bgr.cols / 1280.0;
  const int thickness = std::max(1, static_cast<int>(std::lround(2 * scale)));
  // The monitor is given no pattern: both teams' truth drawn at the default marker plane (a
  // team 2 cm lower is drawn a few pixels off near the image's edge).
  const double robot_height = 0.15, robot_radius = 0.09;
  if (robots) {
    for (const auto& r : robots->robots) {
      const auto c = camera.project(Eigen::Vector3d(r.x, r.y, robot_height));
      const auto edge = camera.project(Eigen::Vector3d(r.x + robot_radius, r.y, robot_height));
      const auto head =
          camera.project(Eigen::Vector3d(r.x + 2 * robot_radius * std::cos(r.theta),
                                         r.y + 2 * robot_radius * std::sin(r.theta), robot_height));
      if (!c || !edge || !head) continue;
      const cv::Scalar colour = !r.visible                                      ? cv::Scalar(128, 128, 128)
                                : r.team == soccer_vision::RobotPose::TEAM_BLUE ? cv::Scalar(255, 160, 0)
                                                                                : cv::Scalar(0, 230, 255);
      const cv::Point pc(static_cast<int>(std::lround(c->x())), static_cast<int>(std::lround(c->y())));
      const int radius = std::max(3, static_cast<int>(std::lround((*edge - *c).norm())));
      cv::circle(bgr, pc, radius, colour, thickness, cv::LINE_AA);
      cv::line(bgr, pc,
               cv::Point(static_cast<int>(std::lround(head->x())), static_cast<int>(std::lround(head->y()))),
               colour, thickness, cv::LINE_AA);
      const std::string label =
          std::string(r.team == soccer_vision::RobotPose::TEAM_BLUE ? "B" : "Y") + std::to_string(r.id);
      cv::putText(bgr, label, pc + cv::Point(radius + 2, -radius), cv::FONT_HERSHEY_SIMPLEX,
                  0.6 * std::max(scale, 0.5), colour, thickness, cv::LINE_AA);
    }
  }
  if (balls) {
    for (const auto& b : balls->balls) {
      const auto c = camera.project(Eigen::Vector3d(b.x, b.y, b.z));
      if (!c) continue;
      const cv::Point pc(static_cast<int>(std::lround(c->x())), static_cast<int>(std::lround(c->y())));
      const cv::Scalar colour = b.visible ? cv::Scalar(0, 0, 255) : cv::Scalar(128, 128, 128);
      cv::circle(bgr, pc, std::max(6, static_cast<int>(std::lround(12 * scale))), colour, thickness,
                 cv::LINE_AA);
      cv::putText(bgr, "ball", pc + cv::Point(10, -10), cv::FONT_HERSHEY_SIMPLEX, 0.6 * std::max(scale, 0.5),
                  colour, thickness, cv::LINE_AA);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "demo_monitor");  // strips remapping arguments (__name:= ...)
  double duration = -1;
  std::string snapshot;
  CLI::App app{
      "demo_monitor: watches <~camera>/image_raw (+ camera_info, ground truth) and the tracking\n"
      "outputs, prints a summary and writes an annotated snapshot; exits 1 if no frame arrived.\n"
      "Private parameters (_camera:=/camera_0 _camera_id:=0 _vision:=/vision _scenario:=NAME,\n"
      "~duration, ~snapshot) as in docs/tools.md",
      "demo_monitor"};
  app.add_option("--duration", duration, "[s] run time (wins over ~duration); 0: until Ctrl-C")
      ->check(CLI::Range(0.0, 1e6));
  app.add_option("--snapshot", snapshot, "the annotated snapshot to write (wins over ~snapshot)");
  if (const auto status = sv::parseLaunchedCommandLine(app, argc, argv)) return *status;

  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  std::string camera_ns;
  int camera_id = 0;
  pnh.param<std::string>("camera", camera_ns, "camera_0");
  pnh.param("camera_id", camera_id, 0);
  std::string scenario_name;
  pnh.param<std::string>("scenario", scenario_name, "");
  std::string vision_ns;
  pnh.param<std::string>("vision", vision_ns, "/vision");
  if (duration < 0) pnh.param("duration", duration, 10.0);
  if (snapshot.empty()) pnh.param<std::string>("snapshot", snapshot, "./soccer_vision_snapshot.png");

  Monitor m;
  ros::NodeHandle cam(nh, camera_ns);
  const ros::TransportHints hints = ros::TransportHints().tcpNoDelay();
  ros::Subscriber s1 = cam.subscribe("image_raw", 5, &Monitor::image, &m, hints);
  ros::Subscriber s2 = cam.subscribe("camera_info", 5, &Monitor::info, &m, hints);
  ros::Subscriber s3 = cam.subscribe("ground_truth/robots", 20, &Monitor::robotArray, &m, hints);
  ros::Subscriber s4 = cam.subscribe("ground_truth/balls", 20, &Monitor::ballArray, &m, hints);
  ros::NodeHandle vision(nh, vision_ns);
  ros::Subscriber s5 = vision.subscribe("robots", 50, &Monitor::resultRobots, &m, hints);
  ros::Subscriber s6 = vision.subscribe("balls", 50, &Monitor::resultBalls, &m, hints);
  ROS_INFO("demo_monitor: watching %s for %.1f s", s1.getTopic().c_str(), duration);

  ros::AsyncSpinner spinner(2);
  spinner.start();
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(duration);
  while (ros::ok() && (duration == 0 || ros::WallTime::now() < end)) ros::WallDuration(0.05).sleep();
  spinner.stop();
  s1.shutdown();
  s2.shutdown();
  s3.shutdown();
  s4.shutdown();
  s5.shutdown();
  s6.shutdown();

  std::lock_guard<std::mutex> lock(m.mutex);
  if (m.frames == 0 || !m.last_image) {
    std::printf("demo_monitor: no frame received on %s in %.1f s\n", s1.getTopic().c_str(), duration);
    std::fflush(stdout);
    return 1;
  }
  const sensor_msgs::Image& im = *m.last_image;
  const double span = (m.last_receipt - m.first_receipt).toSec();
  const double rate = m.frames > 1 && span > 0 ? (m.frames - 1) / span : 0.0;
  std::vector<double> lat = m.latencies;
  std::sort(lat.begin(), lat.end());
  double mean = 0;
  for (double l : lat) mean += l;
  mean /= lat.size();
  const double p99 = sv::percentile(lat, 99);

  std::printf("demo_monitor summary (%s)\n", s1.getTopic().c_str());
  std::printf("  frames received   %zu in %.2f s\n", m.frames, span);
  std::printf("  rate              %.2f Hz\n", rate);
  std::printf("  latency           mean %.2f ms, p99 %.2f ms, max %.2f ms (receipt - capture stamp)\n",
              1e3 * mean, 1e3 * p99, 1e3 * lat.back());
  std::printf("  camera_info       %zu messages\n", m.camera_infos);
  std::printf("  encoding          %s\n", im.encoding.c_str());
  std::printf("  resolution        %ux%u\n", im.width, im.height);
  if (m.gt_frames > 0) {
    std::printf("  visible robots    %.2f per frame (ground truth, %zu frames)\n",
                static_cast<double>(m.visible_robot_sum) / m.gt_frames, m.gt_frames);
    std::printf("  visible balls     %.2f per frame\n",
                static_cast<double>(m.visible_ball_sum) / m.gt_frames);
  } else {
    std::printf("  ground truth      none received\n");
  }

  printTrackingScore(m);

  // Snapshot: the newest frame whose ground truth arrived (else the last frame), demosaiced
  // if Bayer, with its ground truth drawn on it.
  sensor_msgs::ImageConstPtr shot = m.last_image;
  for (auto it = m.recent.rbegin(); it != m.recent.rend(); ++it) {
    if (m.robots.count((*it)->header.stamp)) {
      shot = *it;
      break;
    }
  }
  int status = 0;
  try {
    const cv_bridge::CvImageConstPtr cv = cv_bridge::toCvShare(shot);
    cv::Mat bgr;
    const int code = sv::bayerToBgrCode(im.encoding);
    if (code >= 0) {
      cv::cvtColor(cv->image, bgr, code);
    } else if (im.encoding == "bgr8") {
      bgr = cv->image.clone();
    } else {
      bgr = cv_bridge::cvtColor(cv, "bgr8")->image;
    }
    const auto rit = m.robots.find(shot->header.stamp);
    const auto bit = m.balls.find(shot->header.stamp);
    const std::string path = sv::resolveScenarioPath(scenario_name);
    sv::ScenarioConfig scenario = path.empty() ? sv::ScenarioConfig{} : sv::loadScenario(path);
    scenario.width = static_cast<int>(im.width);
    scenario.height = static_cast<int>(im.height);
    const sv::CameraModel camera =
        sv::scenarioCamera(sv::fieldGeometryByName(scenario.field), camera_id, scenario);
    annotate(bgr, camera, rit != m.robots.end() ? rit->second : nullptr,
             bit != m.balls.end() ? bit->second : nullptr);
    if (!cv::imwrite(snapshot, bgr)) throw std::runtime_error("cv::imwrite failed");
    std::printf("  snapshot          %s%s\n", snapshot.c_str(),
                rit == m.robots.end() ? " (no ground truth for this frame)" : "");
  } catch (const std::exception& e) {
    std::printf("demo_monitor: cannot write snapshot %s: %s\n", snapshot.c_str(), e.what());
    status = 3;
  }
  std::fflush(stdout);
  return status;
}
