// soccer_vision/Identification: blobs of one camera -> robots and ball candidates on the field
// (paper §III-D). A thin adapter over FrameIdentifier (src/identification/): it builds the
// camera model from camera_info and the camera pose (tf or a camera_pose.yaml) and turns each
// BlobArray into one CameraDetections with the image's capture stamp. Parameters and topics:
// docs/nodelets.md, generated from cfg/Identification.cfg and cfg/Identification.params.yaml.
#include <atomic>
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
#include <tf2_ros/transform_listener.h>

#include "soccer_vision/BlobArray.h"
#include "soccer_vision/CameraDetections.h"
#include "soccer_vision/IdentificationConfig.h"
#include "soccer_vision/common/camera_pose_file.h"
#include "soccer_vision/identification/frame_identification.h"
#include "soccer_vision/ros/blob_conversions.h"
#include "soccer_vision/ros/conversions.h"
#include "soccer_vision/ros/detection_conversions.h"
#include "soccer_vision/ros/transforms.h"

namespace soccer_vision {

namespace {

IdentificationParams toIdentificationParams(const IdentificationConfig& c) {
  IdentificationParams p;
  p.robots.marker_gate = c.marker_gate;
  p.robots.area_ratio_gate = c.area_ratio_gate;
  p.robots.small_marker_confidence = c.small_marker_confidence;
  p.robots.recall.max_age = c.recall_age;
  p.robots.recall.max_distance = c.recall_distance;
  p.robots.recall.max_heading_deg = c.recall_heading_deg;
  p.robots.recalled_confidence = c.recalled_confidence;
  p.robots.axis_weight = c.axis_weight;
  p.robots.min_confidence = c.min_confidence;
  p.robots.max_missing_markers = c.max_missing_markers;
  p.robots.report_unidentified = c.report_unidentified;
  p.confirm_confidence = c.confirm_confidence;
  p.balls.area_ratio_min = c.ball_area_ratio_min;
  p.balls.area_ratio_max = std::max(c.ball_area_ratio_max, c.ball_area_ratio_min);
  p.balls.field_margin = c.ball_field_margin;
  p.balls.max_candidates = c.max_ball_candidates;
  return p;
}

double msSince(const ros::WallTime& start) { return (ros::WallTime::now() - start).toSec() * 1e3; }

}  // namespace

class IdentificationNodelet : public nodelet::Nodelet {
 private:
  void onInit() override;
  void blobsCallback(const BlobArrayConstPtr& blobs);
  void cameraInfoCallback(const sensor_msgs::CameraInfoConstPtr& info);
  void reconfigure(IdentificationConfig& config, uint32_t level);
  // The identifier for these blobs' camera, built or rebuilt when intrinsics, pose or
  // pattern changed; nullptr (with the reason logged) when something is missing.
  std::shared_ptr<const FrameIdentifier> identifierFor(const BlobArray& blobs);
  void diagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat);
  void drop(std::uint64_t& counter);

  int camera_id_ = 0;
  std::string field_frame_ = "field";
  std::optional<CameraPoseFile> pose_file_;
  std::string pose_file_path_;
  std::optional<FieldGeometry> field_;  // none: the `field` parameter names no valid field
  std::string field_error_;

  ros::Subscriber blobs_sub_, info_sub_;
  ros::Publisher detections_pub_;
  ros::Publisher confirmed_pub_;  // the confirmed markers, for Segmentation's online calibration
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::shared_ptr<SharedStaticTf> static_tf_;
  ros::WallTimer tf_timer_;

  using ReconfigureServer = dynamic_reconfigure::Server<IdentificationConfig>;
  std::unique_ptr<ReconfigureServer> reconfigure_server_;
  boost::recursive_mutex reconfigure_mutex_;

  std::mutex mutex_;  // everything below
  sensor_msgs::CameraInfoConstPtr info_;
  IdentificationParams params_;
  PatternSet patterns_ = PatternSet::twoTag();
  std::string pattern_name_;
  bool rebuild_ = true;
  std::shared_ptr<const FrameIdentifier> identifier_;
  std::string identifier_frame_;
  std::string problem_;  // why there is no identifier
  // Diagnostics.
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  ros::WallTimer diag_timer_;
  ros::WallTime window_start_;
  std::uint64_t frames_ = 0, window_frames_ = 0, window_robots_ = 0, window_balls_ = 0;
  double window_ms_sum_ = 0, window_ms_max_ = 0;
  std::uint64_t dropped_no_camera_ = 0, dropped_other_camera_ = 0, dropped_error_ = 0;
  std::uint64_t camera_info_refused_ = 0;
  RejectionCounts rejections_;  // candidates identification did not report, since start, by cause
  std::uint64_t recalled_ids_ = 0, small_marker_robots_ = 0;  // reported with reservations, since start
  // The robots this camera identified in its last frames. Only the blobs callback uses it,
  // and ROS runs one subscription's callbacks one at a time.
  RecentIdentities recent_;
};

void IdentificationNodelet::onInit() {
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  pnh.param("camera_id", camera_id_, 0);
  pnh.param("field_frame", field_frame_, std::string("field"));
  pnh.param("camera_pose", pose_file_path_, std::string());  // loaded with the first frame
  std::string field_name;
  pnh.param("field", field_name, std::string("div_b"));
  try {
    field_ = fieldGeometryByName(field_name);
  } catch (const std::exception& e) {
    // No silent fallback to another field: its on-carpet test would accept or drop the wrong balls.
    field_error_ = e.what();
    NODELET_ERROR("%s; no detections until the parameter names a valid field", e.what());
  }
  tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh);

  updater_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
  updater_->setHardwareID("camera " + std::to_string(camera_id_));
  updater_->add("identification", this, &IdentificationNodelet::diagnostics);
  window_start_ = ros::WallTime::now();
  diag_timer_ =
      nh.createWallTimer(ros::WallDuration(0.5), [this](const ros::WallTimerEvent&) { updater_->update(); });

  reconfigure_server_ = std::make_unique<ReconfigureServer>(reconfigure_mutex_, pnh);
  reconfigure_server_->setCallback(
      [this](IdentificationConfig& c, uint32_t level) { reconfigure(c, level); });

  detections_pub_ = nh.advertise<CameraDetections>("detections", 5);
  confirmed_pub_ = nh.advertise<BlobArray>("confirmed_markers", 5);
  info_sub_ = nh.subscribe("camera_info", 2, &IdentificationNodelet::cameraInfoCallback, this);
  blobs_sub_ = nh.subscribe("blobs", 5, &IdentificationNodelet::blobsCallback, this);
}

void IdentificationNodelet::reconfigure(IdentificationConfig& config, uint32_t /*level*/) {
  std::lock_guard<std::mutex> lock(mutex_);
  params_ = toIdentificationParams(config);
  if (config.pattern != pattern_name_) {
    try {
      patterns_ = patternSetByName(config.pattern);
      pattern_name_ = config.pattern;
    } catch (const std::exception& e) {
      NODELET_ERROR("pattern '%s': %s; keeping '%s'", config.pattern.c_str(), e.what(),
                    pattern_name_.empty() ? "two_tag" : pattern_name_.c_str());
      config.pattern = pattern_name_.empty() ? "two_tag" : pattern_name_;
    }
  }
  rebuild_ = true;
}

void IdentificationNodelet::cameraInfoCallback(const sensor_msgs::CameraInfoConstPtr& info) {
  // Bad input keeps the last good camera_info (NaN or Inf once gave 0 robots silently).
  try {
    intrinsicsFromCameraInfo(*info);
  } catch (const std::exception& e) {
    NODELET_ERROR_THROTTLE(5.0, "camera_info refused (%s); keeping the previous one", e.what());
    std::lock_guard<std::mutex> lock(mutex_);
    ++camera_info_refused_;
    if (!info_) problem_ = std::string("camera_info refused: ") + e.what();
    return;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  const bool changed = !info_ || info_->K != info->K || info_->D != info->D || info_->width != info->width ||
                       info_->height != info->height || info_->header.frame_id != info->header.frame_id;
  info_ = info;
  rebuild_ = rebuild_ || changed;
}

std::shared_ptr<const FrameIdentifier> IdentificationNodelet::identifierFor(const BlobArray& blobs) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!rebuild_ && identifier_ && identifier_frame_ == blobs.header.frame_id) return identifier_;
  if (!field_) {
    problem_ = field_error_;
    return nullptr;
  }
  if (!info_) {
    if (camera_info_refused_ == 0) problem_ = "no camera_info received yet";
    return nullptr;
  }
  try {
    const CameraIntrinsics intrinsics = intrinsicsFromCameraInfo(*info_);
    CameraModel camera;
    // A missing or bad file is retried with every frame (error throttled): it may be
    // being written by calibrate_field, or fixed by hand.
    if (!pose_file_path_.empty() && !pose_file_) pose_file_ = loadCameraPoseFile(pose_file_path_);
    if (pose_file_) {
      camera = cameraModelFromPose(*pose_file_, intrinsics, pose_file_path_);
      const std::string child =
          pose_file_->child_frame_id.empty() ? blobs.header.frame_id : pose_file_->child_frame_id;
      if (!static_tf_) {
        static_tf_ = SharedStaticTf::get();
        const auto t = toTransformStamped(pose_file_->field_T_camera, field_frame_, child, ros::Time::now());
        static_tf_->send(t);
        // Re-sent: another static broadcaster of this process may replace the latched message.
        tf_timer_ = getNodeHandle().createWallTimer(
            ros::WallDuration(2.0), [this, t](const ros::WallTimerEvent&) { static_tf_->send(t); });
      }
    } else {
      const geometry_msgs::TransformStamped t =
          tf_buffer_->lookupTransform(field_frame_, blobs.header.frame_id, ros::Time(0));
      camera = CameraModel(intrinsics, fromTransform(t.transform));
    }
    identifier_ = std::make_shared<const FrameIdentifier>(camera, patterns_, *field_, params_);
    identifier_frame_ = blobs.header.frame_id;
    rebuild_ = false;
    problem_.clear();
  } catch (const std::exception& e) {
    problem_ = e.what();
    identifier_.reset();
  }
  return identifier_;
}

void IdentificationNodelet::drop(std::uint64_t& counter) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++counter;
}

void IdentificationNodelet::blobsCallback(const BlobArrayConstPtr& blobs) {
  const ros::WallTime start = ros::WallTime::now();
  if (blobs->camera_id != camera_id_) {
    NODELET_ERROR_THROTTLE(5.0, "blobs of camera %d, this nodelet is camera %d; frame dropped",
                           blobs->camera_id, camera_id_);
    drop(dropped_other_camera_);
    return;
  }
  const std::shared_ptr<const FrameIdentifier> identifier = identifierFor(*blobs);
  if (!identifier) {
    std::string why;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      why = problem_;
    }
    NODELET_ERROR_THROTTLE(5.0, "no camera model for frame '%s': %s; frame dropped",
                           blobs->header.frame_id.c_str(), why.c_str());
    drop(dropped_no_camera_);
    return;
  }
  auto out = boost::make_shared<CameraDetections>();
  RejectionCounts rejections;
  int recalled_ids = 0, small_marker_robots = 0;
  // Lazy: the confirmed markers only when Segmentation learns from them.
  const bool confirm = confirmed_pub_.getNumSubscribers() > 0;
  std::vector<int> confirmed;
  const std::vector<Region> regions = fromBlobArray(*blobs);
  try {
    const CameraFrameDetections d =
        identifier->identify(regions, blobs->header.stamp.toSec(), camera_id_, blobs->global_search,
                             confirm ? &confirmed : nullptr, &recent_);
    toCameraDetections(d, blobs->header, *out);
    rejections = d.rejections;
    recalled_ids = d.recalled_ids;
    small_marker_robots = d.small_marker_robots;
  } catch (const std::exception& e) {
    NODELET_ERROR_THROTTLE(5.0, "identification failed: %s; frame dropped", e.what());
    drop(dropped_error_);
    return;
  }
  detections_pub_.publish(out);  // never touched after this
  if (confirm) {
    // Every frame, with or without markers: Segmentation reads the carpet of each.
    auto markers = boost::make_shared<BlobArray>();
    markers->header = blobs->header;
    markers->camera_id = blobs->camera_id;
    markers->image_width = blobs->image_width;
    markers->image_height = blobs->image_height;
    markers->global_search = blobs->global_search;
    markers->mosaic = blobs->mosaic;
    markers->blobs.reserve(confirmed.size());
    for (const int i : confirmed) markers->blobs.push_back(toBlob(regions[static_cast<std::size_t>(i)]));
    confirmed_pub_.publish(markers);  // never touched after this
  }
  const double ms = msSince(start);
  std::lock_guard<std::mutex> lock(mutex_);
  ++frames_;
  ++window_frames_;
  window_robots_ += out->robots.size();
  window_balls_ += out->balls.size();
  rejections_ += rejections;
  recalled_ids_ += static_cast<std::uint64_t>(recalled_ids);
  small_marker_robots_ += static_cast<std::uint64_t>(small_marker_robots);
  window_ms_sum_ += ms;
  window_ms_max_ = std::max(window_ms_max_, ms);
}

void IdentificationNodelet::diagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  std::lock_guard<std::mutex> lock(mutex_);
  const double seconds = std::max((ros::WallTime::now() - window_start_).toSec(), 1e-6);
  const double n = std::max<double>(window_frames_, 1);
  if (!identifier_ && !problem_.empty()) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "no camera model: " + problem_);
  } else if (window_frames_ == 0) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "no blobs received");
  } else {
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "identifying");
  }
  stat.add("rate [Hz]", window_frames_ / seconds);
  stat.add("processing time mean [ms]", window_ms_sum_ / n);
  stat.add("processing time max [ms]", window_ms_max_);
  stat.add("robots per frame", window_robots_ / n);
  stat.add("ball candidates per frame", window_balls_ / n);
  stat.add("frames", frames_);
  stat.add("dropped: no camera model", dropped_no_camera_);
  stat.add("dropped: other camera", dropped_other_camera_);
  stat.add("dropped: errors", dropped_error_);
  stat.add("camera_info refused (NaN/Inf, focal <= 0, size)", camera_info_refused_);
  // Candidates (team-colour regions, orange clusters) not reported, since start, by cause.
  for (const auto& [name, count] : rejections_.named(false))
    stat.add(std::string("rejected: ") + name, count);
  // Robots reported, but unsure enough to begin no track (their confidence is capped).
  stat.add("reported unsure: id recalled from the last frames", recalled_ids_);
  stat.add("reported unsure: a marker below its area gate", small_marker_robots_);
  stat.add("pattern", pattern_name_);
  stat.add("camera pose", !pose_file_path_.empty()
                              ? "file " + pose_file_path_ + (pose_file_ ? "" : " (not loaded yet)")
                              : "tf " + field_frame_ + " -> " + identifier_frame_);
  window_start_ = ros::WallTime::now();
  window_frames_ = window_robots_ = window_balls_ = 0;
  window_ms_sum_ = window_ms_max_ = 0;
}

}  // namespace soccer_vision

PLUGINLIB_EXPORT_CLASS(soccer_vision::IdentificationNodelet, nodelet::Nodelet)
