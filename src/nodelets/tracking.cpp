// soccer_vision/Tracking: the detections of every camera -> tracked robots and ball (paper
// §III-C), their tf frames and rviz markers, and the search windows fed back to each camera's
// segmentation. A thin adapter over Tracker and SearchPlanner (src/tracking/): one tracker for
// all cameras, so a robot in the overlap is one track. Parameters and topics:
// docs/nodelets.md, generated from cfg/Tracking.cfg and cfg/Tracking.params.yaml.
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <boost/make_shared.hpp>
#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>

#include "soccer_vision/BallPose.h"
#include "soccer_vision/BallPoseArray.h"
#include "soccer_vision/CameraDetections.h"
#include "soccer_vision/RobotPoseArray.h"
#include "soccer_vision/SearchWindows.h"
#include "soccer_vision/TrackingConfig.h"
#include "soccer_vision/common/robot_pattern.h"
#include "soccer_vision/common/statistics.h"
#include "soccer_vision/ros/blob_conversions.h"
#include "soccer_vision/ros/conversions.h"
#include "soccer_vision/ros/detection_conversions.h"
#include "soccer_vision/ros/field_markers.h"
#include "soccer_vision/ros/tracking_conversions.h"
#include "soccer_vision/ros/transforms.h"
#include "soccer_vision/tracking/result_recording.h"
#include "soccer_vision/tracking/search_planner.h"
#include "soccer_vision/tracking/stamp_jump_gate.h"
#include "soccer_vision/tracking/tracker.h"

namespace soccer_vision {

class TrackingNodelet : public nodelet::Nodelet {
 private:
  struct Camera {
    std::string ns;
    ros::Subscriber detections_sub, info_sub;
    ros::Publisher windows_pub;
    sensor_msgs::CameraInfoConstPtr info;
    std::optional<CameraModel> model;  // built from info + tf when first needed
    bool model_stale = true;
    SearchPlanner planner;  // the next frame's windows or global search
    int camera_id = -1;
    std::optional<double> measurement_offset;  // [s] ~measurement_offsets entry
  };

  void onInit() override;
  void reconfigure(TrackingConfig& config, uint32_t level);
  void detectionsCallback(Camera& camera, const CameraDetectionsConstPtr& msg);
  void cameraInfoCallback(Camera& camera, const sensor_msgs::CameraInfoConstPtr& info);
  const CameraModel* cameraModel(Camera& camera);
  void publishWindows(Camera& camera, const std_msgs::Header& header, double stamp);
  void publishTf(const TrackerOutput& out, const ros::Time& stamp);
  void publishWindowMarkers(const CameraModel& model, const SearchWindows& windows);
  void diagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat);

  std::string field_frame_ = "field";
  bool publish_tf_ = true;
  std::vector<std::unique_ptr<Camera>> cameras_;
  ros::Publisher robots_pub_, balls_pub_, ball_pub_, markers_pub_, field_markers_pub_, window_markers_pub_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> tf_broadcaster_;
  std::unique_ptr<JsonLinesWriter> results_;

  using ReconfigureServer = dynamic_reconfigure::Server<TrackingConfig>;
  std::unique_ptr<ReconfigureServer> reconfigure_server_;
  boost::recursive_mutex reconfigure_mutex_;

  std::mutex mutex_;  // the tracker, the cameras' state, the settings and statistics below
  Tracker tracker_;
  TrackerParams tracker_params_;
  SearchPlannerParams search_params_;
  bool show_windows_ = false;
  MarkerStyle marker_style_;
  TeamHeights robot_height_{0.150, 0.150};  // [m] the pattern's marker planes
  // Diagnostics.
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  ros::WallTimer diag_timer_;
  ros::WallTime window_start_;
  std::vector<double> latencies_ms_;
  std::uint64_t frames_ = 0, window_frames_ = 0, global_frames_ = 0, windowed_frames_ = 0;
  std::uint64_t no_camera_model_ = 0, results_errors_ = 0, camera_info_refused_ = 0;
  std::uint64_t withheld_robots_ = 0, withheld_balls_ = 0;  // outputs of too uncertain coasting tracks
  // Outputs of ball tracks begun outside the playing area, not yet confirmed, of those
  // outside it below outside_min_confidence, and of parked ones.
  std::uint64_t unconfirmed_balls_ = 0, unsure_outside_balls_ = 0, parked_balls_ = 0;
  StampJumpGate tf_gate_;  // tf only for stamps on a confirmed time line
  // tf once per stamp: cameras that capture at the same instants give one output each, and
  // tf2 refuses (and every listener warns of) a frame's transform repeated at its stamp.
  ros::Time last_tf_stamp_;
  std::uint64_t tf_same_stamp_ = 0;
};

void TrackingNodelet::onInit() {
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  pnh.param("field_frame", field_frame_, std::string("field"));
  pnh.param("publish_tf", publish_tf_, true);
  std::vector<std::string> namespaces;
  if (!pnh.getParam("cameras", namespaces) || namespaces.empty()) namespaces = {"/camera_0"};
  std::string results_file;
  pnh.param("results_file", results_file, std::string());
  if (!results_file.empty()) {
    try {
      results_ = std::make_unique<JsonLinesWriter>(results_file);
      NODELET_INFO("writing per-frame results to %s", results_file.c_str());
    } catch (const std::exception& e) {
      NODELET_ERROR("results_file: %s; results are not recorded", e.what());
    }
  }

  tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh);
  tf_broadcaster_ = std::make_unique<tf2_ros::TransformBroadcaster>();

  updater_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
  updater_->setHardwareID("tracker");
  updater_->add("tracking", this, &TrackingNodelet::diagnostics);
  window_start_ = ros::WallTime::now();
  diag_timer_ =
      nh.createWallTimer(ros::WallDuration(0.5), [this](const ros::WallTimerEvent&) { updater_->update(); });

  // The field: its markers, and the playing area that tells the ball from a still orange
  // object by the lines. Read before the reconfigure callback applies the tracker's parameters.
  std::string field_name;
  pnh.param("field", field_name, std::string("div_b"));
  try {
    tracker_params_.field = fieldGeometryByName(field_name);
  } catch (const std::exception& e) {
    NODELET_ERROR("%s; no field markers, and every ball track is taken as in play", e.what());
  }

  // The pattern's marker planes, per team: where the robots' windows, rviz bodies and tf
  // frames are. Read before the reconfigure callback copies the search parameters.
  std::string pattern;
  pnh.param("pattern", pattern, std::string("two_tag"));
  try {
    const PatternSet patterns = patternSetByName(pattern);
    robot_height_ = patterns.heights();
  } catch (const std::exception& e) {
    NODELET_ERROR("pattern: %s; robots at 0.15 m", e.what());
  }
  search_params_.windows.robot_height = robot_height_;
  marker_style_.robot_height = robot_height_;

  reconfigure_server_ = std::make_unique<ReconfigureServer>(reconfigure_mutex_, pnh);
  reconfigure_server_->setCallback([this](TrackingConfig& c, uint32_t level) { reconfigure(c, level); });

  robots_pub_ = nh.advertise<RobotPoseArray>("robots", 5);
  balls_pub_ = nh.advertise<BallPoseArray>("balls", 5);
  ball_pub_ = nh.advertise<BallPose>("ball", 5);
  markers_pub_ = nh.advertise<visualization_msgs::MarkerArray>("markers", 5);
  field_markers_pub_ = nh.advertise<visualization_msgs::MarkerArray>("field_markers", 1, true);
  window_markers_pub_ = nh.advertise<visualization_msgs::MarkerArray>("window_markers", 5);
  if (tracker_params_.field) {
    field_markers_pub_.publish(boost::make_shared<visualization_msgs::MarkerArray>(
        fieldMarkers(*tracker_params_.field, field_frame_)));
  }

  std::vector<double> offsets;
  pnh.getParam("measurement_offsets", offsets);
  if (offsets.size() > namespaces.size()) {
    NODELET_ERROR("measurement_offsets has %zu entries for %zu cameras; the extra ones are ignored",
                  offsets.size(), namespaces.size());
  }
  for (const std::string& ns : namespaces) {
    auto camera = std::make_unique<Camera>();
    camera->ns = ns;
    const std::size_t index = cameras_.size();
    if (index < offsets.size()) {
      if (std::abs(offsets[index]) <= 0.1) {
        camera->measurement_offset = offsets[index];
      } else {
        NODELET_ERROR("measurement_offsets[%zu] = %g s is outside [-0.1, 0.1] s; %s uses measurement_offset",
                      index, offsets[index], ns.c_str());
      }
    }
    camera->planner = SearchPlanner(search_params_);
    Camera* c = camera.get();
    camera->windows_pub = nh.advertise<SearchWindows>(ns + "/search_windows", 2);
    camera->info_sub = nh.subscribe<sensor_msgs::CameraInfo>(
        ns + "/camera_info", 2,
        [this, c](const sensor_msgs::CameraInfoConstPtr& m) { cameraInfoCallback(*c, m); });
    camera->detections_sub = nh.subscribe<CameraDetections>(
        ns + "/detections", 5, [this, c](const CameraDetectionsConstPtr& m) { detectionsCallback(*c, m); });
    cameras_.push_back(std::move(camera));
  }
}

void TrackingNodelet::reconfigure(TrackingConfig& config, uint32_t /*level*/) {
  std::lock_guard<std::mutex> lock(mutex_);
  tracker_params_.robot_lost_timeout = config.robot_lost_timeout;
  tracker_params_.ball_lost_timeout = config.ball_lost_timeout;
  tracker_params_.min_confidence = config.min_confidence;
  tracker_params_.min_start_confidence = config.min_start_confidence;
  tracker_params_.misread_distance = config.misread_distance;
  tracker_params_.misread_established_reads = config.misread_established_reads;
  tracker_params_.time.max_forward_jump = config.max_forward_jump;
  tracker_params_.time.late_tolerance = config.late_tolerance;
  tracker_params_.measurement_offset = config.measurement_offset;
  tracker_params_.max_coast_uncertainty = config.max_coast_uncertainty;
  try {
    tracker_.setParams(tracker_params_);
  } catch (const std::exception& e) {
    NODELET_ERROR("tracking parameters: %s; keeping the previous ones", e.what());
    tracker_params_ = tracker_.params();
  }
  SearchPlannerParams search = search_params_;
  search.windows.side_px = config.window_side;
  search.entry_band_px = config.entry_band;
  search.global_search.period_frames = config.global_search_period;
  search.sweep = config.global_search_sweep;
  search.lost_ball_sweep_streaks = config.lost_ball_sweep_streaks;
  search.candidate_frames = config.candidate_frames;
  search.max_candidates = config.max_candidates;
  search.search_windows = config.search_windows;
  try {
    validate(search);  // all cameras take the same parameters: check once, then apply
    search_params_ = search;
    for (auto& c : cameras_) c->planner.setParams(search_params_);
  } catch (const std::exception& e) {  // the cfg's ranges make this unexpected
    NODELET_ERROR("search window parameters: %s; keeping the previous ones", e.what());
  }
  show_windows_ = config.show_windows;
}

void TrackingNodelet::cameraInfoCallback(Camera& camera, const sensor_msgs::CameraInfoConstPtr& info) {
  try {
    intrinsicsFromCameraInfo(*info);
  } catch (const std::exception& e) {
    NODELET_ERROR_THROTTLE(5.0, "%s: camera_info refused (%s); keeping the previous one", camera.ns.c_str(),
                           e.what());
    std::lock_guard<std::mutex> lock(mutex_);
    ++camera_info_refused_;
    return;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  if (!camera.info || camera.info->K != info->K || camera.info->D != info->D ||
      camera.info->header.frame_id != info->header.frame_id || camera.info->width != info->width) {
    camera.model_stale = true;
  }
  camera.info = info;
}

const CameraModel* TrackingNodelet::cameraModel(Camera& camera) {
  if (!camera.model_stale && camera.model) return &*camera.model;
  if (!camera.info) return nullptr;
  try {
    const auto t = tf_buffer_->lookupTransform(field_frame_, camera.info->header.frame_id, ros::Time(0));
    camera.model = CameraModel(intrinsicsFromCameraInfo(*camera.info), fromTransform(t.transform));
    camera.model_stale = false;
  } catch (const std::exception& e) {
    NODELET_ERROR_THROTTLE(5.0, "%s: no camera model for search windows (%s); its frames are searched whole",
                           camera.ns.c_str(), e.what());
    return nullptr;
  }
  return &*camera.model;
}

void TrackingNodelet::detectionsCallback(Camera& camera, const CameraDetectionsConstPtr& msg) {
  const CameraFrameDetections frame = fromCameraDetections(*msg);
  std_msgs::Header header = msg->header;
  header.frame_id = field_frame_;

  auto robots = boost::make_shared<RobotPoseArray>();
  auto balls = boost::make_shared<BallPoseArray>();
  auto markers = boost::make_shared<visualization_msgs::MarkerArray>();
  TrackerOutput out;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    camera.camera_id = frame.camera_id;
    if (camera.measurement_offset) {
      // Camera ids are known from the detections only: the camera's own offset is keyed by it.
      const auto it = tracker_params_.camera_measurement_offsets.find(frame.camera_id);
      if (it == tracker_params_.camera_measurement_offsets.end() ||
          it->second != *camera.measurement_offset) {
        tracker_params_.camera_measurement_offsets[frame.camera_id] = *camera.measurement_offset;
        try {
          tracker_.setParams(tracker_params_);
        } catch (const std::exception& e) {  // range checked at start-up: not expected
          NODELET_ERROR_THROTTLE(5.0, "%s: measurement offset not applied: %s", camera.ns.c_str(), e.what());
          tracker_params_ = tracker_.params();
          camera.measurement_offset.reset();
        }
      }
    }
    const TrackerUpdateReport report = tracker_.update(frame);
    if (report.reset()) {
      NODELET_WARN_THROTTLE(5.0, "tracker reset: %s of the stamps (camera %d, %.3f s; %lu resets so far)",
                            timeEventName(report.time.event), frame.camera_id, frame.stamp,
                            static_cast<unsigned long>(tracker_.stats().resets));
      for (auto& c : cameras_) c->planner.restart();
    }
    camera.planner.observe(report, frame.stamp, msg->global_search, frame.rejected_robots);
    if (!report.processed()) return;  // late or invalid frame: nothing new to publish
    out = tracker_.output(frame.stamp);
    withheld_robots_ += out.withheld_robots;
    withheld_balls_ += out.withheld_balls;
    unconfirmed_balls_ += out.unconfirmed_balls;
    unsure_outside_balls_ += out.unsure_outside_balls;
    parked_balls_ += out.parked_balls;
    *robots = toRobotPoseArray(out, header);
    *balls = toBallPoseArray(out, header);
    appendGameMarkers(*robots, *balls, marker_style_, *markers);
    ++frames_;
    ++window_frames_;
    (msg->global_search ? global_frames_ : windowed_frames_)++;
    publishWindows(camera, header, frame.stamp);
    if (results_) {
      try {
        results_->write(toFrameRecord(out));
      } catch (const std::exception& e) {
        ++results_errors_;
        NODELET_ERROR_THROTTLE(5.0, "results_file: %s", e.what());
      }
    }
  }
  robots_pub_.publish(robots);  // never touched after publishing
  balls_pub_.publish(balls);
  if (out.primaryBall()) ball_pub_.publish(boost::make_shared<BallPose>(balls->balls.front()));
  // The tracked output is out: the markers and tf frames for rviz follow.
  const double latency_ms = (ros::Time::now() - header.stamp).toSec() * 1e3;
  markers_pub_.publish(markers);
  bool tf_ok = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (publish_tf_ && header.stamp == last_tf_stamp_) {
      ++tf_same_stamp_;
    } else if (publish_tf_ && tf_gate_.accept(header.stamp.toSec())) {
      tf_ok = true;
      last_tf_stamp_ = header.stamp;
    }
    latencies_ms_.push_back(latency_ms);
  }
  if (tf_ok) publishTf(out, header.stamp);
}

// The windows for this camera's next frame (mutex held).
void TrackingNodelet::publishWindows(Camera& camera, const std_msgs::Header& header, double stamp) {
  const CameraModel* model = search_params_.search_windows ? cameraModel(camera) : nullptr;
  if (search_params_.search_windows && !model) ++no_camera_model_;
  const SearchPlan plan = camera.planner.plan(tracker_, model, stamp);
  auto msg = boost::make_shared<SearchWindows>();
  msg->header = header;
  msg->header.stamp.fromSec(plan.stamp);  // the frame these predictions are for
  msg->camera_id = static_cast<std::uint8_t>(std::clamp(camera.camera_id, 0, 255));
  msg->global_search = plan.global_search;
  for (const cv::Rect& r : plan.rects) msg->windows.push_back(toRegionOfInterest(r));
  for (const cv::Rect& r : plan.ball_streak_rects) msg->ball_streak_windows.push_back(toRegionOfInterest(r));
  for (const cv::Rect& r : plan.lost_ball_streak_rects)
    msg->lost_ball_streak_windows.push_back(toRegionOfInterest(r));
  camera.windows_pub.publish(msg);
  if (show_windows_ && model) publishWindowMarkers(*model, *msg);
}

// The windows' outlines on the marker plane (mutex held). A window (and an entry band) has
// no team: drawn on the higher of the teams' planes, over every top rather than under one.
void TrackingNodelet::publishWindowMarkers(const CameraModel& model, const SearchWindows& windows) {
  const double height = std::max(robot_height_[0], robot_height_[1]);
  std::vector<std::vector<Eigen::Vector3d>> outlines;
  for (const auto& roi : windows.windows) {
    const double x0 = roi.x_offset, y0 = roi.y_offset, x1 = x0 + roi.width - 1.0, y1 = y0 + roi.height - 1.0;
    std::vector<Eigen::Vector3d> outline;
    for (const Eigen::Vector2d& corner : {Eigen::Vector2d(x0, y0), Eigen::Vector2d(x1, y0),
                                          Eigen::Vector2d(x1, y1), Eigen::Vector2d(x0, y1)}) {
      if (const auto p = model.pixelToField(corner, height)) outline.push_back(*p);
    }
    if (outline.size() == 4) outlines.push_back(std::move(outline));
  }
  auto markers = boost::make_shared<visualization_msgs::MarkerArray>();
  std_msgs::Header header = windows.header;
  header.frame_id = field_frame_;
  appendOutlineMarkers(outlines, header, 0.1, *markers);
  window_markers_pub_.publish(markers);
}

void TrackingNodelet::publishTf(const TrackerOutput& out, const ros::Time& stamp) {
  std::vector<geometry_msgs::TransformStamped> transforms;
  for (const TrackedRobot& r : out.robots) {
    const std::string name = std::string(teamName(r.team)) + "_" +
                             (r.id >= 0 ? std::to_string(r.id) : "track" + std::to_string(r.track_id));
    transforms.push_back(planarTransform(r.x, r.y, heightOf(robot_height_, r.team),
                                         r.heading_valid ? r.theta : 0.0, field_frame_, "robot/" + name,
                                         stamp));
  }
  if (const TrackedBall* b = out.primaryBall()) {
    transforms.push_back(planarTransform(b->x, b->y, b->z, 0.0, field_frame_, "ball", stamp));
  }
  if (!transforms.empty()) tf_broadcaster_->sendTransform(transforms);
}

void TrackingNodelet::diagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  std::lock_guard<std::mutex> lock(mutex_);
  const double seconds = std::max((ros::WallTime::now() - window_start_).toSec(), 1e-6);
  if (window_frames_ == 0) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "no detections received");
  } else {
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "tracking");
  }
  double mean = 0;
  for (double l : latencies_ms_) mean += l;
  mean /= std::max<std::size_t>(latencies_ms_.size(), 1);
  stat.add("rate [Hz]", window_frames_ / seconds);
  stat.add("latency capture -> publish mean [ms]", mean);
  stat.add("latency p50 [ms]", percentile(latencies_ms_, 50));
  stat.add("latency p99 [ms]", percentile(latencies_ms_, 99));
  stat.add("robot tracks", tracker_.numRobotTracks());
  stat.add("ball tracks", tracker_.numBallTracks());
  const TrackerStats& s = tracker_.stats();
  stat.add("frames", s.frames);
  stat.add("frames dropped (late/invalid stamps)", s.dropped_frames);
  stat.add("resets (time jumps)", s.resets);
  stat.add("robot outliers", s.robot_outliers);
  stat.add("robot ids misread (taken as the track's robot)", s.misread_ids);
  stat.add("detections too unsure to begin a track", s.unsure_starts);
  stat.add("robot manoeuvres (sudden velocity changes)", s.robot_maneuvers);
  stat.add("heading manoeuvres (sudden turns)", s.heading_maneuvers);
  stat.add("heading manoeuvres undone (misread headings)", s.maneuvers_undone);
  stat.add("measurement offset [s]", tracker_params_.measurement_offset);
  stat.add("ball kicks", s.ball_kicks);
  stat.add("ball tracks replaced (parked outside the lines)", s.balls_replaced);
  stat.add("robots withheld (coasting, too uncertain)", withheld_robots_);
  stat.add("balls withheld (coasting, too uncertain)", withheld_balls_);
  stat.add("balls withheld (begun outside the playing area, not yet confirmed)", unconfirmed_balls_);
  stat.add("balls withheld (outside the lines, unsure)", unsure_outside_balls_);
  stat.add("balls withheld (parked: still outside the lines since first seen)", parked_balls_);
  stat.add("frames searched whole", global_frames_);
  stat.add("frames searched in windows", windowed_frames_);
  stat.add("windows without camera model", no_camera_model_);
  stat.add("camera_info refused (NaN/Inf, focal <= 0, size)", camera_info_refused_);
  stat.add("tf held back (unconfirmed stamp jumps)", tf_gate_.held());
  stat.add("tf skipped (stamp already published by another camera's output)", tf_same_stamp_);
  if (results_) stat.add("results lines", results_->written());
  window_start_ = ros::WallTime::now();
  window_frames_ = 0;
  latencies_ms_.clear();
}

}  // namespace soccer_vision

PLUGINLIB_EXPORT_CLASS(soccer_vision::TrackingNodelet, nodelet::Nodelet)
