// soccer_vision/CameraDriver: captures frames from a pluggable FrameSource (parameter `source`,
// src/sources/) on a thread of its own and publishes each with its camera_info, and the ground
// truth when the source knows it (synthetic). A thin adapter: capture and simulation live in
// the sources. Parameters, topics and services: docs/nodelets.md, generated from
// cfg/CameraDriver.cfg and cfg/CameraDriver.params.yaml.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <boost/make_shared.hpp>
#include <camera_info_manager/camera_info_manager.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <diagnostic_updater/publisher.h>
#include <dynamic_reconfigure/server.h>
#include <geometry_msgs/TransformStamped.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/UInt64MultiArray.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include "soccer_vision/BallPose.h"
#include "soccer_vision/BallPoseArray.h"
#include "soccer_vision/CameraDriverConfig.h"
#include "soccer_vision/RobotPose.h"
#include "soccer_vision/RobotPoseArray.h"
#include "soccer_vision/common/angle.h"
#include "soccer_vision/common/statistics.h"
#include "soccer_vision/ros/conversions.h"
#include "soccer_vision/ros/image_pool.h"
#include "soccer_vision/ros/package_paths.h"
#include "soccer_vision/ros/transforms.h"
#include "soccer_vision/sources/frame_source.h"

namespace soccer_vision {

namespace {

// Parameters passed to the sources as FrameSourceOptions::settings (strings).
constexpr const char* kSettingNames[] = {
    "device", "file",        "path",    "loop",        "realtime",      "encoding",     "pixel_format",
    "camera", "packet_size", "buffers", "stamp_delay", "frame_timeout", "replay_frames"};

std::string settingText(XmlRpc::XmlRpcValue& v) {
  switch (v.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean:
      return static_cast<bool>(v) ? "true" : "false";
    case XmlRpc::XmlRpcValue::TypeInt:
      return std::to_string(static_cast<int>(v));
    case XmlRpc::XmlRpcValue::TypeDouble: {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.17g", static_cast<double>(v));
      return buf;
    }
    case XmlRpc::XmlRpcValue::TypeString:
      return static_cast<std::string>(v);
    default:
      return v.toXml();  // the source reports it as malformed
  }
}

}  // namespace

class CameraDriverNodelet : public nodelet::Nodelet {
 public:
  CameraDriverNodelet() = default;
  ~CameraDriverNodelet() override;

 private:
  void onInit() override;
  void captureLoop();
  bool openSource();
  void publishFrame(const sensor_msgs::ImagePtr& image, const FrameInfo& info);
  sensor_msgs::CameraInfoPtr makeCameraInfo(const std_msgs::Header& header, int width, int height);
  void setupCalibration(int width, int height);
  void publishGroundTruth(const std_msgs::Header& image_header, const FrameInfo& info);
  void sendStaticTf();
  void reconfigure(CameraDriverConfig& config, uint32_t level);
  void sourceDiagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat);
  // Sleeps up to `seconds`; false when shutting down.
  bool sleepFor(double seconds);

  // Parameters.
  std::string source_name_;
  int camera_id_ = 0;
  std::string frame_id_;
  std::string camera_info_url_;
  FrameSourceOptions options_;
  double retry_period_ = 2.0;
  double tf_period_ = 2.0;

  std::unique_ptr<FrameSource> source_;  // capture thread (interrupt() from anywhere)
  std::unique_ptr<image_transport::ImageTransport> it_;
  image_transport::CameraPublisher camera_pub_;
  ros::Publisher gt_robots_pub_, gt_balls_pub_, gt_ball_pub_;
  ros::Publisher address_pub_;  // debug_report_data_pointer only
  std::shared_ptr<camera_info_manager::CameraInfoManager> cinfo_;
  std::shared_ptr<SharedStaticTf> static_tf_;
  ros::WallTime last_tf_sent_;

  using ReconfigureServer = dynamic_reconfigure::Server<CameraDriverConfig>;
  std::unique_ptr<ReconfigureServer> reconfigure_server_;  // created by the capture thread
  boost::recursive_mutex reconfigure_mutex_;

  std::unique_ptr<diagnostic_updater::Updater> updater_;
  std::unique_ptr<diagnostic_updater::TopicDiagnostic> image_diag_;
  double min_freq_ = 0, max_freq_ = 0;  // read by image_diag_ under its own lock
  ros::WallTimer diag_timer_;

  // State shown in diagnostics and shared with the reconfigure callback.
  std::mutex state_mutex_;
  bool source_open_ = false;
  std::string source_error_;
  std::vector<std::string> source_warnings_;
  std::uint64_t frames_published_ = 0;
  std::uint64_t frames_missing_ = 0;  // gaps in the source sequence
  // [ms] from each frame's capture stamp to its publication, since the last diagnostics: the
  // source's share of the tracker's capture -> output latency (transfer, conversion, copy).
  std::vector<double> publish_delays_ms_;
  std::string encoding_;
  int width_ = 0, height_ = 0;
  std::string calibration_problem_;                // why camera_info is not from camera_info_url
  std::string logged_open_error_;                  // capture thread: one error per state change
  bool grab_failing_ = false;                      // capture thread
  bool was_open_ = false;                          // capture thread: opened at least once
  bool source_failing_ = false;                    // grabs failing (diagnostics)
  static constexpr double kReminderPeriod = 60.0;  // [s]
  ImagePool image_pool_{6};                        // capture thread: published images back once released
  ros::WallTime next_reminder_;                    // capture thread

  std::thread thread_;
  std::atomic<bool> running_{false};
  std::mutex wake_mutex_;
  std::condition_variable wake_;
};

CameraDriverNodelet::~CameraDriverNodelet() {
  diag_timer_.stop();
  running_ = false;
  wake_.notify_all();
  if (source_) source_->interrupt();
  if (thread_.joinable()) thread_.join();
  if (source_) source_->close();
}

void CameraDriverNodelet::onInit() {
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();

  pnh.param<std::string>("source", source_name_, "synthetic");
  pnh.param("camera_id", camera_id_, 0);
  if (camera_id_ < 0 || camera_id_ > 255) {
    NODELET_ERROR("camera_id %d out of range 0..255; using 0", camera_id_);
    camera_id_ = 0;
  }
  const std::string n = std::to_string(camera_id_);
  pnh.param<std::string>("frame_id", frame_id_, "camera_" + n + "_optical");
  std::string camera_name;
  pnh.param<std::string>("camera_name", camera_name, "camera_" + n);
  pnh.param<std::string>("camera_info_url", camera_info_url_, "");
  pnh.param("retry_period", retry_period_, 2.0);
  retry_period_ = std::max(0.1, retry_period_);
  pnh.param("tf_period", tf_period_, 2.0);

  options_.camera_index = camera_id_;
  pnh.param<std::string>("scenario", options_.scenario, "");
  try {
    options_.scenario = resolveScenarioPath(options_.scenario);
  } catch (const std::exception& e) {
    NODELET_ERROR("%s", e.what());  // the source then reports the unreadable path and falls back
  }
  pnh.param("fps", options_.fps, 0.0);  // 0: the source's native rate
  pnh.param("width", options_.width, 0);
  pnh.param("height", options_.height, 0);
  if (options_.fps < 0 || options_.width < 0 || options_.height < 0) {
    NODELET_ERROR("fps/width/height must be >= 0 (0 = the scenario's); ignoring the overrides");
    options_.fps = 0;
    options_.width = options_.height = 0;
  }
  for (const char* key : kSettingNames) {
    XmlRpc::XmlRpcValue value;
    if (pnh.getParam(key, value)) options_.settings[key] = settingText(value);
  }
  bool report_data_pointer = false;
  pnh.param("debug_report_data_pointer", report_data_pointer, false);
  if (report_data_pointer)
    address_pub_ = nh.advertise<std_msgs::UInt64MultiArray>("debug/published_address", 20);
  pnh.param("epoch", options_.epoch, 0.0);
  std::string epoch_param;
  pnh.param<std::string>("epoch_param", epoch_param, "/soccer_vision/synthetic_epoch");
  if (source_name_ == "synthetic" && options_.epoch <= 0 && !epoch_param.empty()) {
    const double now = ros::WallTime::now().toSec();
    double epoch = 0;
    if (ros::param::get(epoch_param, epoch) && now - epoch >= 0 && now - epoch < 3600) {
      options_.epoch = epoch;
    } else {
      options_.epoch = std::floor(now);
      ros::param::set(epoch_param, options_.epoch);
    }
  }

  it_ = std::make_unique<image_transport::ImageTransport>(nh);
  camera_pub_ = it_->advertiseCamera("image_raw", 2);
  gt_robots_pub_ = nh.advertise<RobotPoseArray>("ground_truth/robots", 5);
  gt_balls_pub_ = nh.advertise<BallPoseArray>("ground_truth/balls", 5);
  gt_ball_pub_ = nh.advertise<BallPose>("ground_truth/ball", 5);
  static_tf_ = SharedStaticTf::get();

  // The calibration is loaded once the source is open and its resolution known
  // (setupCalibration, capture thread).
  cinfo_ = std::make_shared<camera_info_manager::CameraInfoManager>(nh, camera_name);

  updater_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
  updater_->setHardwareID(source_name_ + " camera " + n);
  updater_->add("source", this, &CameraDriverNodelet::sourceDiagnostics);
  image_diag_ = std::make_unique<diagnostic_updater::TopicDiagnostic>(
      "image_raw", *updater_, diagnostic_updater::FrequencyStatusParam(&min_freq_, &max_freq_, 0.1, 5),
      diagnostic_updater::TimeStampStatusParam(-0.01, 0.25));
  diag_timer_ =
      nh.createWallTimer(ros::WallDuration(0.5), [this](const ros::WallTimerEvent&) { updater_->update(); });

  std::string error;
  source_ = createFrameSource(source_name_, error);
  if (!source_) {
    NODELET_ERROR("%s; CameraDriver publishes nothing", error.c_str());
    std::lock_guard<std::mutex> lock(state_mutex_);
    source_error_ = error;
    return;
  }
  running_ = true;
  thread_ = std::thread(&CameraDriverNodelet::captureLoop, this);
}

bool CameraDriverNodelet::sleepFor(double seconds) {
  std::unique_lock<std::mutex> lock(wake_mutex_);
  wake_.wait_for(lock, std::chrono::duration<double>(seconds), [this] { return !running_; });
  return running_;
}

bool CameraDriverNodelet::openSource() {
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  // Re-open after a failure: keep the frame rate chosen through dynamic_reconfigure.
  if (reconfigure_server_) pnh.getParam("fps", options_.fps);
  OpenResult r = source_->open(options_);
  {
    std::lock_guard<std::mutex> lock(state_mutex_);
    source_open_ = r.ok;
    source_failing_ = false;
    source_error_ = r.error;
    source_warnings_ = r.warnings;
  }
  if (!r.ok) {
    // One error per state change: a new failure, not every retry of the same one.
    if (r.error != logged_open_error_)
      NODELET_ERROR("cannot open %s source (camera %d): %s; retrying every %.1f s", source_name_.c_str(),
                    camera_id_, r.error.c_str(), retry_period_);
    logged_open_error_ = r.error;
    return false;
  }
  if (!logged_open_error_.empty() && was_open_)
    NODELET_INFO("%s source (camera %d) is back", source_name_.c_str(), camera_id_);
  logged_open_error_.clear();
  was_open_ = true;
  for (const std::string& w : r.warnings) NODELET_ERROR("%s", w.c_str());

  // Controls given as parameters at start-up (the reconfigure server is created below, so
  // a parameter present now was set by the user or by a previous reconfigure).
  for (const std::string& name : source_->controls()) {
    double value = 0;
    std::string error;
    if (pnh.getParam(name, value) && !source_->setControl(name, value, error))
      NODELET_ERROR("parameter %s: %s", name.c_str(), error.c_str());
  }

  const FrameFormat f = source_->format();
  {
    std::lock_guard<std::mutex> lock(state_mutex_);
    encoding_ = f.encoding;
    width_ = f.width;
    height_ = f.height;
  }
  min_freq_ = max_freq_ = source_->fps();
  NODELET_INFO("%s source open: camera %d, %dx%d %s at %.1f Hz, frame %s", source_name_.c_str(), camera_id_,
               f.width, f.height, f.encoding.c_str(), source_->fps(), frame_id_.c_str());

  if (!reconfigure_server_) {
    reconfigure_server_ = std::make_unique<ReconfigureServer>(reconfigure_mutex_, pnh);
    CameraDriverConfig config;
    reconfigure_server_->getConfigDefault(config);
    config.fps = source_->fps();
    for (const std::string& name : source_->controls()) {
      const std::optional<double> v = source_->control(name);
      if (!v) continue;
      if (name == "brightness") config.brightness = *v;
      if (name == "noise_sigma") config.noise_sigma = *v;
      if (name == "flicker") config.flicker = *v;
      if (name == "exposure") config.exposure = *v;
      if (name == "gain") config.gain = *v;
    }
    reconfigure_server_->updateConfig(config);  // show the source's actual settings
    reconfigure_server_->setCallback(
        [this](CameraDriverConfig& c, uint32_t level) { reconfigure(c, level); });
  }
  setupCalibration(f.width, f.height);
  next_reminder_ = ros::WallTime::now() + ros::WallDuration(kReminderPeriod);
  last_tf_sent_ = ros::WallTime();
  sendStaticTf();
  return true;
}

void CameraDriverNodelet::reconfigure(CameraDriverConfig& config, uint32_t /*level*/) {
  if (!source_) return;
  std::string error;
  // A free-running source (fps 0: video/images with realtime false) has no rate to set.
  if (source_->fps() > 0 && std::abs(config.fps - source_->fps()) > 1e-9) {
    if (source_->setFps(config.fps, error)) {
      min_freq_ = max_freq_ = config.fps;
      NODELET_INFO("fps -> %.2f Hz", config.fps);
    } else {
      NODELET_ERROR("fps %.2f rejected: %s", config.fps, error.c_str());
      config.fps = source_->fps();
    }
  }
  auto apply = [&](const char* name, double& value) {
    const std::optional<double> current = source_->control(name);
    if (!current) return;  // not a control of this source (synthetic only): no effect
    if (std::abs(*current - value) <= 1e-12) return;
    if (source_->setControl(name, value, error)) {
      NODELET_INFO("%s -> %g", name, value);
    } else {
      NODELET_ERROR("%s", error.c_str());
      value = *current;
    }
  };
  apply("brightness", config.brightness);
  apply("noise_sigma", config.noise_sigma);
  apply("flicker", config.flicker);
  apply("exposure", config.exposure);
  apply("gain", config.gain);
}

void CameraDriverNodelet::captureLoop() {
  std::uint64_t last_sequence = 0;
  bool have_sequence = false;
  int consecutive_errors = 0;
  while (running_) {
    if (!source_->isOpen()) {
      if (!openSource()) {
        if (!sleepFor(retry_period_)) break;
        continue;
      }
      have_sequence = false;
      consecutive_errors = 0;
    }

    const FrameFormat f = source_->format();
    sensor_msgs::ImagePtr image = image_pool_.acquire(f.bytes());
    image->height = static_cast<uint32_t>(f.height);
    image->width = static_cast<uint32_t>(f.width);
    image->encoding = f.encoding;
    image->is_bigendian = 0;
    image->step = static_cast<uint32_t>(f.step);
    cv::Mat wrapped(f.height, f.width, f.cv_type, image->data.data(), f.step);

    FrameInfo info;
    std::string error;
    const GrabStatus status = source_->grab(wrapped, info, 0.5, error);
    if (status == GrabStatus::Interrupted) break;
    if (status == GrabStatus::Timeout) continue;
    if (status == GrabStatus::EndOfStream) {
      NODELET_INFO("%s source: end of stream; no more frames", source_name_.c_str());
      {
        std::lock_guard<std::mutex> lock(state_mutex_);
        source_error_ = "end of stream";
      }
      while (sleepFor(1.0)) {
      }
      break;
    }
    if (status == GrabStatus::Error) {
      if (!grab_failing_)  // one error per state change; the retries are in diagnostics
        NODELET_ERROR("%s source (camera %d): grab failed: %s", source_name_.c_str(), camera_id_,
                      error.c_str());
      grab_failing_ = true;
      {
        std::lock_guard<std::mutex> lock(state_mutex_);
        source_error_ = error;
        source_failing_ = true;
      }
      if (++consecutive_errors >= 3) {
        source_->close();
        std::lock_guard<std::mutex> lock(state_mutex_);
        source_open_ = false;
      }
      if (!sleepFor(std::min(retry_period_, 0.2 * consecutive_errors))) break;
      continue;
    }
    consecutive_errors = 0;
    if (grab_failing_) {
      grab_failing_ = false;
      NODELET_INFO("%s source (camera %d): frames again", source_name_.c_str(), camera_id_);
      std::lock_guard<std::mutex> lock(state_mutex_);
      source_failing_ = false;
    }
    if (have_sequence && info.sequence > last_sequence + 1) {
      std::lock_guard<std::mutex> lock(state_mutex_);
      frames_missing_ += info.sequence - last_sequence - 1;
    }
    last_sequence = info.sequence;
    have_sequence = true;
    if (!info.encoding.empty()) image->encoding = info.encoding;
    publishFrame(image, info);
  }
}

void CameraDriverNodelet::publishFrame(const sensor_msgs::ImagePtr& image, const FrameInfo& info) {
  image->header.seq = static_cast<uint32_t>(info.sequence);
  image->header.stamp = ros::Time(info.stamp);
  image->header.frame_id = frame_id_;
  sensor_msgs::CameraInfoPtr camera_info =
      makeCameraInfo(image->header, static_cast<int>(image->width), static_cast<int>(image->height));
  const std_msgs::Header header = image->header;
  if (address_pub_) {
    auto report = boost::make_shared<std_msgs::UInt64MultiArray>();
    report->data = {header.stamp.sec, header.stamp.nsec,
                    static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(image->data.data()))};
    address_pub_.publish(report);
  }
  camera_pub_.publish(image, camera_info);  // untouched until every holder released it (ImagePool)
  const double publish_delay_ms = (ros::Time::now() - header.stamp).toSec() * 1e3;
  image_diag_->tick(header.stamp);
  {
    std::lock_guard<std::mutex> lock(state_mutex_);
    ++frames_published_;
    publish_delays_ms_.push_back(publish_delay_ms);
  }
  if (info.ground_truth) publishGroundTruth(header, info);
  // Re-sent: another static broadcaster of this process may replace the latched message.
  if (tf_period_ > 0 && (ros::WallTime::now() - last_tf_sent_).toSec() >= tf_period_) sendStaticTf();
  // Degraded operation (logged when it started) is repeated every kReminderPeriod.
  const ros::WallTime now = ros::WallTime::now();
  if (now >= next_reminder_) {
    next_reminder_ = now + ros::WallDuration(kReminderPeriod);
    std::string calibration_problem;
    {
      std::lock_guard<std::mutex> lock(state_mutex_);
      calibration_problem = calibration_problem_;
    }
    if (!calibration_problem.empty()) NODELET_ERROR("%s", calibration_problem.c_str());
    for (const std::string& w : source_warnings_) NODELET_ERROR("%s", w.c_str());
  }
}

void CameraDriverNodelet::setupCalibration(int width, int height) {
  const std::optional<CameraIntrinsics> truth = source_->trueIntrinsics();
  const char* fallback = truth ? "the source's true calibration" : "an uncalibrated camera_info";
  std::string problem;
  // Empty URL: a source that knows its calibration (synthetic) uses it; others use
  // camera_info_manager's default URL (${ROS_HOME}/camera_info/<camera_name>.yaml).
  if (!camera_info_url_.empty() || !truth) {
    if (!cinfo_->validateURL(camera_info_url_)) {
      problem = "camera_info_url '" + camera_info_url_ + "' is not a valid URL; publishing " + fallback;
    } else if (cinfo_->loadCameraInfo(camera_info_url_) && cinfo_->isCalibrated()) {
      const sensor_msgs::CameraInfo ci = cinfo_->getCameraInfo();
      if (static_cast<int>(ci.width) == width && static_cast<int>(ci.height) == height) {
        std::lock_guard<std::mutex> lock(state_mutex_);
        calibration_problem_.clear();
        return;
      }
      problem = "calibration from camera_info_url '" + camera_info_url_ + "' is for " +
                std::to_string(ci.width) + "x" + std::to_string(ci.height) + ", the image is " +
                std::to_string(width) + "x" + std::to_string(height) + "; publishing " + fallback;
    } else if (!camera_info_url_.empty()) {
      problem = "camera_info_url '" + camera_info_url_ + "' could not be loaded; publishing " + fallback;
    }
  }
  // set_camera_info can still replace this at run time.
  cinfo_->setCameraInfo(truth ? toCameraInfo(CameraModel(*truth, Eigen::Isometry3d::Identity()), frame_id_)
                              : sensor_msgs::CameraInfo());
  if (!problem.empty()) NODELET_ERROR("%s", problem.c_str());
  std::lock_guard<std::mutex> lock(state_mutex_);
  calibration_problem_ = problem;
}

sensor_msgs::CameraInfoPtr CameraDriverNodelet::makeCameraInfo(const std_msgs::Header& header, int width,
                                                               int height) {
  auto ci = boost::make_shared<sensor_msgs::CameraInfo>(cinfo_->getCameraInfo());
  if (static_cast<int>(ci->width) != width || static_cast<int>(ci->height) != height) {
    // Uncalibrated, or set_camera_info sent another resolution: size only.
    if (ci->K[0] != 0)
      NODELET_ERROR_THROTTLE(30.0,
                             "camera_info is for %ux%u, the image is %dx%d; publishing "
                             "an uncalibrated camera_info",
                             ci->width, ci->height, width, height);
    *ci = sensor_msgs::CameraInfo();
    ci->width = static_cast<uint32_t>(width);
    ci->height = static_cast<uint32_t>(height);
  }
  ci->header = header;
  return ci;
}

void CameraDriverNodelet::publishGroundTruth(const std_msgs::Header& image_header, const FrameInfo& info) {
  const bool want_robots = gt_robots_pub_.getNumSubscribers() > 0;
  const bool want_balls = gt_balls_pub_.getNumSubscribers() > 0;
  const bool want_ball = gt_ball_pub_.getNumSubscribers() > 0;
  if (!want_robots && !want_balls && !want_ball) return;
  const SceneState& scene = *info.ground_truth;
  // Visibility as computed by the source, per object of the scene (same order).
  auto flag = [](const std::vector<bool>& flags, const auto& items, const auto& item) {
    const std::ptrdiff_t i = &item - items.data();
    return i >= 0 && static_cast<std::size_t>(i) < flags.size() && flags[i];
  };
  if (want_robots) {
    auto robots = boost::make_shared<RobotPoseArray>(
        toRobotPoseArray(scene, image_header.stamp, camera_id_,
                         [&](const RobotState& r) { return flag(info.robot_visible, scene.robots, r); }));
    robots->header.seq = image_header.seq;
    for (RobotPose& p : robots->robots) {
      p.header.seq = image_header.seq;
      p.theta = wrapToPi(p.theta);
    }
    gt_robots_pub_.publish(robots);
  }
  if (!want_balls && !(want_ball && !scene.balls.empty())) return;
  auto balls = boost::make_shared<BallPoseArray>(
      toBallPoseArray(scene, image_header.stamp, camera_id_,
                      [&](const BallState& b) { return flag(info.ball_visible, scene.balls, b); }));
  balls->header.seq = image_header.seq;
  for (BallPose& p : balls->balls) p.header.seq = image_header.seq;
  if (want_ball && !balls->balls.empty())
    gt_ball_pub_.publish(boost::make_shared<BallPose>(balls->balls.front()));
  if (want_balls) gt_balls_pub_.publish(balls);
}

void CameraDriverNodelet::sendStaticTf() {
  const std::optional<Eigen::Isometry3d> pose = source_->trueFieldTCamera();
  if (!pose) return;  // real cameras: field calibration publishes this transform
  static_tf_->send(toTransformStamped(*pose, "field", frame_id_, ros::Time::now()));
  last_tf_sent_ = ros::WallTime::now();
}

void CameraDriverNodelet::sourceDiagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  std::lock_guard<std::mutex> lock(state_mutex_);
  if (!source_open_) {
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::ERROR, "%s source not open: %s", source_name_.c_str(),
                  source_error_.c_str());
  } else if (source_failing_) {
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::ERROR, "%s source failing: %s", source_name_.c_str(),
                  source_error_.c_str());
  } else if (!source_warnings_.empty() || !calibration_problem_.empty()) {
    std::string msg = source_warnings_.empty() ? "" : source_warnings_.front();
    if (!calibration_problem_.empty()) msg += (msg.empty() ? "" : "; ") + calibration_problem_;
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, msg);
  } else {
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "capturing");
  }
  stat.add("source", source_name_);
  stat.add("camera_id", camera_id_);
  stat.add("frame_id", frame_id_);
  stat.add("resolution", std::to_string(width_) + "x" + std::to_string(height_));
  stat.add("encoding", encoding_);
  stat.add("target fps", min_freq_);
  stat.add("frames published", frames_published_);
  stat.add("frames dropped by the source", frames_missing_);
  stat.add("capture -> publish p50 [ms]", percentile(publish_delays_ms_, 50));
  stat.add("capture -> publish p99 [ms]", percentile(publish_delays_ms_, 99));
  publish_delays_ms_.clear();
  if (!source_error_.empty()) stat.add("last error", source_error_);
  for (const std::string& w : source_warnings_) stat.add("warning", w);
  if (source_)
    for (const auto& [key, value] : source_->statistics()) stat.add(key, value);
}

}  // namespace soccer_vision

PLUGINLIB_EXPORT_CLASS(soccer_vision::CameraDriverNodelet, nodelet::Nodelet)
