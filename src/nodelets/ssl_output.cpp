// soccer_vision/SslOutput: the vision system in the league's protocol (docs/ssl.md). A thin
// adapter over src/ssl/: every camera's CameraDetections -> one SSL-Vision detection packet,
// the field and the cameras' calibration -> a geometry packet at start and every 3 s (both on
// ssl_detection_port), the Tracking nodelet's robots + balls of one stamp -> one tracked packet
// (ssl_tracked_port); optionally all of them into a league log file. Parameters and topics:
// docs/nodelets.md, generated from cfg/SslOutput.params.yaml.
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <diagnostic_updater/diagnostic_updater.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "soccer_vision/BallPoseArray.h"
#include "soccer_vision/CameraDetections.h"
#include "soccer_vision/RobotPoseArray.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/common/robot_pattern.h"
#include "soccer_vision/common/statistics.h"
#include "soccer_vision/ros/conversions.h"
#include "soccer_vision/ros/detection_conversions.h"
#include "soccer_vision/ros/tracking_conversions.h"
#include "soccer_vision/ros/transforms.h"
#include "soccer_vision/ssl/detection_packet.h"
#include "soccer_vision/ssl/geometry_packet.h"
#include "soccer_vision/ssl/kicked_ball.h"
#include "soccer_vision/ssl/log_file.h"
#include "soccer_vision/ssl/tracked_packet.h"
#include "soccer_vision/ssl/udp_sender.h"

namespace soccer_vision {

namespace {

double unixNow() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

std::int64_t unixNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

class SslOutputNodelet : public nodelet::Nodelet {
 private:
  struct Camera {
    std::string ns;
    ros::Subscriber detections_sub, info_sub;
    sensor_msgs::CameraInfoConstPtr info;
    std::optional<CameraModel> model;  // from info + tf, for the pixels and the calibration
    int camera_id = -1;
    std::uint32_t frame_number = 0;
  };

  void onInit() override;
  void detectionsCallback(Camera& camera, const CameraDetectionsConstPtr& msg);
  void robotsCallback(const RobotPoseArrayConstPtr& msg);
  void ballsCallback(const BallPoseArrayConstPtr& msg);
  void sendTrackedIfPaired();  // with mutex_ held
  void sendGeometry();
  const CameraModel* cameraModel(Camera& camera);  // with mutex_ held
  // Sends and logs one packet; false when it was not sent.
  bool send(ssl::UdpSender* sender, ssl::LogMessageType type, const std::string& payload);
  void diagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat);

  std::string field_frame_ = "field";
  FieldGeometry field_;
  ssl::DetectionPacketOptions detection_options_;
  ssl::TrackedPacketOptions tracked_options_;
  std::unique_ptr<ssl::UdpSender> detection_sender_, tracked_sender_;
  std::unique_ptr<ssl::LogWriter> log_;
  std::vector<std::unique_ptr<Camera>> cameras_;
  ros::Subscriber robots_sub_, balls_sub_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  ros::WallTimer geometry_timer_, diag_timer_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;

  std::mutex mutex_;  // everything below, the cameras' state, the senders and the log
  ssl::KickedBallEstimator kicks_;
  RobotPoseArrayConstPtr robots_;
  BallPoseArrayConstPtr balls_;
  double last_tracked_stamp_ = -1;
  std::uint32_t tracked_frame_number_ = 0;
  std::uint64_t detection_packets_ = 0, geometry_packets_ = 0, tracked_packets_ = 0;
  std::vector<double> tracked_delays_ms_;  // capture stamp -> tracked packet sent, since the last diagnostics
  std::uint64_t send_errors_ = 0, log_errors_ = 0, unpaired_outputs_ = 0;
  std::string last_send_error_;
};

void SslOutputNodelet::onInit() {
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  std::string address, interface, log_path, field_name, pattern;
  double robot_height = 0.150;
  int detection_port = 10006, tracked_port = 10010;
  double geometry_period = 3.0;
  pnh.param("ssl_address", address, std::string("224.5.23.2"));
  pnh.param("ssl_detection_port", detection_port, 10006);
  pnh.param("ssl_tracked_port", tracked_port, 10010);
  pnh.param("ssl_interface", interface, std::string());
  pnh.param("ssl_log", log_path, std::string());
  pnh.param("field", field_name, std::string("div_b"));
  pnh.param("field_frame", field_frame_, std::string("field"));
  pnh.param("robot_height", robot_height, 0.150);
  pnh.param("pattern", pattern, std::string());
  pnh.param("geometry_period", geometry_period, 3.0);
  pnh.param("source_name", tracked_options_.source_name, std::string("soccer_vision"));
  tracked_options_.uuid = ssl::randomUuid();
  std::vector<std::string> namespaces;
  if (!pnh.getParam("cameras", namespaces) || namespaces.empty()) namespaces = {"/camera_0"};

  try {
    field_ = fieldGeometryByName(field_name);
  } catch (const std::exception& e) {
    NODELET_ERROR("field: %s; sending the default div_b geometry", e.what());
  }
  if (!(geometry_period > 0 && geometry_period <= 60)) {
    NODELET_ERROR("geometry_period %g s outside (0, 60]; using 3 s", geometry_period);
    geometry_period = 3.0;
  }
  if (!(robot_height >= 0 && robot_height <= 0.5)) {
    NODELET_ERROR("robot_height %g m outside [0, 0.5]; using 0.15 m", robot_height);
    robot_height = 0.150;
  }
  detection_options_.robot_height = {robot_height, robot_height};
  if (!pattern.empty()) {
    // The pattern's heights, per team (identification projected each team onto its own).
    try {
      const PatternSet patterns = patternSetByName(pattern);
      detection_options_.robot_height = patterns.heights();
    } catch (const std::exception& e) {
      NODELET_ERROR("pattern: %s; sending robot_height %g m for both teams", e.what(), robot_height);
    }
  }
  try {
    detection_sender_ = std::make_unique<ssl::UdpSender>(address, detection_port, interface);
    tracked_sender_ = std::make_unique<ssl::UdpSender>(address, tracked_port, interface);
    NODELET_INFO("sending SSL packets to %s:%d (detection, geometry) and :%d (tracked)%s", address.c_str(),
                 detection_port, tracked_port, detection_sender_->multicast() ? " (multicast)" : "");
  } catch (const std::exception& e) {
    NODELET_ERROR("%s; no SSL packets are sent", e.what());
    detection_sender_.reset();
    tracked_sender_.reset();
  }
  if (!log_path.empty()) {
    try {
      log_ = std::make_unique<ssl::LogWriter>(log_path);
      NODELET_INFO("recording SSL packets to %s", log_path.c_str());
    } catch (const std::exception& e) {
      NODELET_ERROR("ssl_log: %s; packets are not recorded", e.what());
    }
  }

  tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh);
  for (const std::string& ns : namespaces) {
    auto camera = std::make_unique<Camera>();
    camera->ns = ns;
    Camera* c = camera.get();
    camera->info_sub = nh.subscribe<sensor_msgs::CameraInfo>(
        ns + "/camera_info", 2, [this, c](const sensor_msgs::CameraInfoConstPtr& m) {
          std::lock_guard<std::mutex> lock(mutex_);
          if (!c->info || c->info->K != m->K || c->info->D != m->D || c->info->width != m->width ||
              c->info->header.frame_id != m->header.frame_id) {
            c->model.reset();  // rebuilt with the new intrinsics when next needed
          }
          c->info = m;
        });
    camera->detections_sub = nh.subscribe<CameraDetections>(
        ns + "/detections", 5, [this, c](const CameraDetectionsConstPtr& m) { detectionsCallback(*c, m); });
    cameras_.push_back(std::move(camera));
  }
  robots_sub_ = nh.subscribe("robots", 5, &SslOutputNodelet::robotsCallback, this);
  balls_sub_ = nh.subscribe("balls", 5, &SslOutputNodelet::ballsCallback, this);

  updater_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
  updater_->setHardwareID("ssl_output");
  updater_->add("ssl_output", this, &SslOutputNodelet::diagnostics);
  diag_timer_ =
      nh.createWallTimer(ros::WallDuration(0.5), [this](const ros::WallTimerEvent&) { updater_->update(); });
  // Geometry at start (the field), again when a camera's first detections tell its id, and
  // every period.
  geometry_timer_ = nh.createWallTimer(
      ros::WallDuration(geometry_period), [this](const ros::WallTimerEvent&) { sendGeometry(); }, false,
      false);
  geometry_timer_.start();
  sendGeometry();
}

bool SslOutputNodelet::send(ssl::UdpSender* sender, ssl::LogMessageType type, const std::string& payload) {
  bool sent = false;
  if (sender) {
    sent = sender->send(payload);
    if (!sent) {
      ++send_errors_;
      last_send_error_ = sender->lastError();
      NODELET_ERROR_THROTTLE(5.0, "SSL packet not sent: %s", last_send_error_.c_str());
    }
  }
  if (log_) {
    try {
      log_->write({unixNowNs(), static_cast<std::int32_t>(type), payload});
    } catch (const std::exception& e) {
      ++log_errors_;
      NODELET_ERROR_THROTTLE(5.0, "%s", e.what());
    }
  }
  return sent;
}

void SslOutputNodelet::detectionsCallback(Camera& camera, const CameraDetectionsConstPtr& msg) {
  CameraFrameDetections frame = fromCameraDetections(*msg);
  bool new_camera = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    // The message carries no pixels: they come back through the camera model.
    if (const CameraModel* model = cameraModel(camera)) {
      frame = ssl::withProjectedPixels(frame, *model, detection_options_);
    }
    new_camera = camera.camera_id != frame.camera_id;
    camera.camera_id = frame.camera_id;
    const std::string payload =
        ssl::detectionPacket(frame, camera.frame_number++, unixNow(), detection_options_).SerializeAsString();
    if (send(detection_sender_.get(), ssl::LogMessageType::Vision2014, payload)) ++detection_packets_;
  }
  if (new_camera) sendGeometry();
}

void SslOutputNodelet::robotsCallback(const RobotPoseArrayConstPtr& msg) {
  std::lock_guard<std::mutex> lock(mutex_);
  robots_ = msg;
  sendTrackedIfPaired();
}

void SslOutputNodelet::ballsCallback(const BallPoseArrayConstPtr& msg) {
  std::lock_guard<std::mutex> lock(mutex_);
  balls_ = msg;
  sendTrackedIfPaired();
}

void SslOutputNodelet::sendTrackedIfPaired() {
  // Tracking publishes robots and balls of one stamp together; one packet per stamp.
  if (!robots_ || !balls_ || robots_->header.stamp != balls_->header.stamp) return;
  const double stamp = robots_->header.stamp.toSec();
  if (stamp == last_tracked_stamp_) return;
  if (stamp < last_tracked_stamp_) ++unpaired_outputs_;  // an older pair completed late: sent anyway
  last_tracked_stamp_ = stamp;
  const TrackerOutput out = fromTrackingMessages(*robots_, *balls_);
  const auto& kick = kicks_.update(out);
  const std::string payload =
      ssl::trackedPacket(out, tracked_frame_number_++, kick, tracked_options_).SerializeAsString();
  if (send(tracked_sender_.get(), ssl::LogMessageType::VisionTracker2020, payload)) {
    ++tracked_packets_;
    tracked_delays_ms_.push_back((ros::Time::now() - robots_->header.stamp).toSec() * 1e3);
  }
}

const CameraModel* SslOutputNodelet::cameraModel(Camera& camera) {
  if (camera.model) return &*camera.model;
  if (!camera.info) return nullptr;
  try {
    const auto t = tf_buffer_->lookupTransform(field_frame_, camera.info->header.frame_id, ros::Time(0));
    camera.model = CameraModel(intrinsicsFromCameraInfo(*camera.info), fromTransform(t.transform));
  } catch (const std::exception& e) {
    NODELET_WARN_THROTTLE(10.0, "%s: no camera pose (%s); pixels 0 and no calibration in the packets",
                          camera.ns.c_str(), e.what());
    return nullptr;
  }
  return &*camera.model;
}

void SslOutputNodelet::sendGeometry() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<ssl::CameraCalibrationInput> calibrations;
  for (const auto& c : cameras_) {
    if (c->camera_id < 0) continue;  // its id comes with its first detections
    if (const CameraModel* model = cameraModel(*c)) calibrations.push_back({c->camera_id, *model});
  }
  if (send(detection_sender_.get(), ssl::LogMessageType::Vision2014,
           ssl::geometryPacket(field_, calibrations).SerializeAsString())) {
    ++geometry_packets_;
  }
}

void SslOutputNodelet::diagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!detection_sender_) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "no UDP sender (see the log)");
  } else if (send_errors_ > 0 || log_errors_ > 0) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "send or log errors");
  } else {
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "sending");
  }
  stat.add("detection packets sent", detection_packets_);
  stat.add("geometry packets sent", geometry_packets_);
  stat.add("tracked packets sent", tracked_packets_);
  stat.add("capture -> tracked packet sent p50 [ms]", percentile(tracked_delays_ms_, 50));
  stat.add("capture -> tracked packet sent p99 [ms]", percentile(tracked_delays_ms_, 99));
  tracked_delays_ms_.clear();
  stat.add("send errors", send_errors_);
  stat.add("last send error", last_send_error_);
  stat.add("log write errors", log_errors_);
  stat.add("tracked outputs out of order", unpaired_outputs_);
  stat.add("log file", log_ ? log_->path() : std::string("(none)"));
}

}  // namespace soccer_vision

PLUGINLIB_EXPORT_CLASS(soccer_vision::SslOutputNodelet, nodelet::Nodelet)
