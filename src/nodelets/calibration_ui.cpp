// soccer_vision/CalibrationUi: the calibration UI in the browser, served by the running system.
// A thin adapter: the HTTP server, request checks and the field model in pixels are the ui stage
// (src/ui/); this file keeps the latest messages of each camera (image, blobs, camera_info,
// classification), the tracked robots and /diagnostics, and answers the server from them, calling
// the Segmentation's ~calibrate and the camera-pose solver. Subscription callbacks only store
// shared pointers: encoding JPEGs, projecting and calibrating happen on the server's threads.
// Parameters, topics and services: docs/nodelets.md, generated from cfg/CalibrationUi.params.yaml.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <cv_bridge/cv_bridge.h>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/package.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "soccer_vision/BallPoseArray.h"
#include "soccer_vision/BlobArray.h"
#include "soccer_vision/Calibrate.h"
#include "soccer_vision/RobotPoseArray.h"
#include "soccer_vision/calibration/camera_pose_solver.h"
#include "soccer_vision/calibration/field_line_calibration.h"
#include "soccer_vision/common/camera_pose_file.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/common/robot_pattern.h"
#include "soccer_vision/ros/conversions.h"
#include "soccer_vision/ros/transforms.h"
#include "soccer_vision/ui/calibration_ui_server.h"
#include "soccer_vision/ui/field_overlay.h"
#include "soccer_vision/ui/jpeg_frame.h"

namespace soccer_vision {

namespace {

constexpr std::size_t kRecentFrames = 8;  // images kept to pair a frozen frame with its blobs

nlohmann::json toJson(const Eigen::Vector2d& p) { return {p.x(), p.y()}; }

nlohmann::json toJson(const std::vector<PixelPolyline>& lines) {
  nlohmann::json out = nlohmann::json::array();
  for (const PixelPolyline& line : lines) {
    nlohmann::json l = nlohmann::json::array();
    for (const Eigen::Vector2d& p : line)
      l.push_back({std::round(p.x() * 10) / 10, std::round(p.y() * 10) / 10});
    out.push_back(l);
  }
  return out;
}

// The camera number of a namespace "/camera_<n>" (else its index in the list).
int cameraIdOf(const std::string& ns, int index) {
  std::size_t end = ns.size();
  while (end > 0 && std::isdigit(static_cast<unsigned char>(ns[end - 1]))) --end;
  if (end == ns.size() || ns.size() - end > 3) return index;
  return std::min(255, std::stoi(ns.substr(end)));
}

}  // namespace

class CalibrationUiNodelet : public nodelet::Nodelet, public CalibrationUiBackend {
 public:
  ~CalibrationUiNodelet() override;

  nlohmann::json info() override;
  nlohmann::json status() override;
  std::string liveJpeg(int camera) override;
  std::string frozenJpeg(int camera) override;
  std::string classificationJpeg(int camera) override;
  nlohmann::json overlay(int camera, bool frozen) override;
  nlohmann::json freeze(int camera) override;
  nlohmann::json calibrateColors(int camera, const nlohmann::json& body) override;
  nlohmann::json solvePose(int camera, const nlohmann::json& body) override;
  nlohmann::json savePose(int camera) override;

 private:
  struct Camera {
    explicit Camera(double live_rate) : live(live_rate), classification_jpeg(live_rate) {}
    int id = 0;
    std::string ns;
    image_transport::Subscriber image_sub, classification_sub;
    ros::Subscriber info_sub, blobs_sub;
    ros::WallTime classification_wanted;  // last request: subscribed while a browser asks
    std::mutex mutex;                     // everything below
    std::deque<sensor_msgs::ImageConstPtr> recent;
    std::deque<BlobArrayConstPtr> recent_blobs;
    sensor_msgs::CameraInfoConstPtr info;
    sensor_msgs::ImageConstPtr classification;
    sensor_msgs::ImageConstPtr frozen;
    BlobArrayConstPtr frozen_blobs;
    // The clicked solution, its pose refined on the frozen frame's lines where they confirm it.
    std::optional<CameraPoseSolution> solved;
    std::optional<FieldLineFit> refined;  // that refinement
    JpegThrottle live, classification_jpeg;
    std::uint64_t frames = 0;
  };

  void onInit() override;
  Camera& camera(int id);
  std::optional<CameraModel> currentModel(Camera& cam, const std::string& frame_id);
  std::string toJpeg(const sensor_msgs::ImageConstPtr& image);
  void updateClassificationSubscriptions();
  void diagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat);

  FieldGeometry field_;
  std::string field_name_;
  std::string pose_dir_;
  int jpeg_quality_ = 80;
  std::vector<std::unique_ptr<Camera>> cameras_;
  std::unique_ptr<image_transport::ImageTransport> it_;
  ros::Subscriber robots_sub_, ball_sub_, diagnostics_sub_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  ros::WallTimer housekeeping_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  std::unique_ptr<CalibrationUiServer> server_;
  std::string server_error_;

  std::mutex state_mutex_;  // the latest tracked robots, ball and diagnostics
  RobotPoseArrayConstPtr robots_;
  BallPoseArrayConstPtr balls_;
  std::map<std::string, diagnostic_msgs::DiagnosticStatus> diagnostics_;
  std::uint64_t calibrations_ = 0, calibrations_failed_ = 0;
};

CalibrationUiNodelet::~CalibrationUiNodelet() {
  housekeeping_.stop();
  if (server_) server_->stop();  // no request runs into a half-destroyed nodelet
}

void CalibrationUiNodelet::onInit() {
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();

  CalibrationUiSettings settings;
  pnh.param("ui_port", settings.port, 8085);
  pnh.param("ui_address", settings.address, std::string("127.0.0.1"));
  pnh.param("ui_token", settings.token, std::string());
  pnh.param("www_dir", settings.www_dir, ros::package::getPath("soccer_vision") + "/www");
  double live_rate = 5.0;
  pnh.param("live_rate", live_rate, 5.0);
  live_rate = std::clamp(live_rate, 0.1, 30.0);
  pnh.param("jpeg_quality", jpeg_quality_, 80);
  jpeg_quality_ = std::clamp(jpeg_quality_, 10, 100);
  pnh.param("field", field_name_, std::string("div_b"));
  try {
    field_ = fieldGeometryByName(field_name_);
  } catch (const std::exception& e) {
    NODELET_ERROR("field: %s; using div_b for the field lines", e.what());
    field_ = FieldGeometry::divB();
  }
  pnh.param("pose_dir", pose_dir_, std::string());
  if (pose_dir_.empty()) {
    const char* ros_home = std::getenv("ROS_HOME");
    const char* home = std::getenv("HOME");
    pose_dir_ = ros_home ? ros_home : std::string(home ? home : "/tmp") + "/.ros";
  }
  std::vector<std::string> namespaces;
  if (!pnh.getParam("cameras", namespaces) || namespaces.empty()) namespaces = {"/camera_0"};

  it_ = std::make_unique<image_transport::ImageTransport>(nh);
  for (std::size_t i = 0; i < namespaces.size(); ++i) {
    auto cam = std::make_unique<Camera>(live_rate);
    Camera* c = cam.get();
    c->ns = namespaces[i];
    c->id = cameraIdOf(c->ns, static_cast<int>(i));
    c->image_sub = it_->subscribe(c->ns + "/image_raw", 1, [c](const sensor_msgs::ImageConstPtr& image) {
      std::lock_guard<std::mutex> lock(c->mutex);  // only stores the pointer: never delays the pipeline
      c->recent.push_back(image);
      if (c->recent.size() > kRecentFrames) c->recent.pop_front();
      ++c->frames;
    });
    c->blobs_sub = nh.subscribe<BlobArray>(c->ns + "/blobs", 2, [c](const BlobArrayConstPtr& blobs) {
      std::lock_guard<std::mutex> lock(c->mutex);
      c->recent_blobs.push_back(blobs);
      if (c->recent_blobs.size() > kRecentFrames) c->recent_blobs.pop_front();
    });
    c->info_sub = nh.subscribe<sensor_msgs::CameraInfo>(c->ns + "/camera_info", 1,
                                                        [c](const sensor_msgs::CameraInfoConstPtr& info) {
                                                          std::lock_guard<std::mutex> lock(c->mutex);
                                                          c->info = info;
                                                        });
    cameras_.push_back(std::move(cam));
  }
  robots_sub_ = nh.subscribe<RobotPoseArray>("robots", 2, [this](const RobotPoseArrayConstPtr& m) {
    std::lock_guard<std::mutex> lock(state_mutex_);
    robots_ = m;
  });
  ball_sub_ = nh.subscribe<BallPoseArray>("balls", 2, [this](const BallPoseArrayConstPtr& m) {
    std::lock_guard<std::mutex> lock(state_mutex_);
    balls_ = m;
  });
  diagnostics_sub_ = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 20, [this](const diagnostic_msgs::DiagnosticArrayConstPtr& m) {
        std::lock_guard<std::mutex> lock(state_mutex_);
        for (const auto& s : m->status) diagnostics_[s.name] = s;
      });
  tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_);
  housekeeping_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) {
    updateClassificationSubscriptions();
    updater_->update();
  });
  updater_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
  updater_->setHardwareID("calibration UI");
  updater_->add("calibration UI", this, &CalibrationUiNodelet::diagnostics);

  server_ = std::make_unique<CalibrationUiServer>(settings, *this);
  try {
    server_->start();
    pnh.setParam("bound_port", server_->port());
    NODELET_INFO("calibration UI on http://%s:%d/%s", settings.address.c_str(), server_->port(),
                 server_->access().changesEnabled() ? "" : " (read-only: no ui_token)");
    if (!server_->access().changesEnabled()) NODELET_WARN("%s", server_->access().readOnlyReason().c_str());
  } catch (const std::exception& e) {
    server_error_ = e.what();
    server_.reset();
    NODELET_ERROR("calibration UI not started: %s", e.what());
  }
}

CalibrationUiNodelet::Camera& CalibrationUiNodelet::camera(int id) {
  for (auto& c : cameras_)
    if (c->id == id) return *c;
  throw UiRequestError(404, "no camera " + std::to_string(id));
}

std::string CalibrationUiNodelet::toJpeg(const sensor_msgs::ImageConstPtr& image) {
  try {
    return encodeJpeg(cv_bridge::toCvShare(image, "bgr8")->image, jpeg_quality_);
  } catch (const cv_bridge::Exception& e) {
    throw UiRequestError(503, std::string("cannot show a ") + image->encoding + " image: " + e.what());
  }
}

std::string CalibrationUiNodelet::liveJpeg(int id) {
  Camera& c = camera(id);
  sensor_msgs::ImageConstPtr image;
  {
    std::lock_guard<std::mutex> lock(c.mutex);
    if (!c.recent.empty()) image = c.recent.back();
  }
  if (!image) throw UiRequestError(503, "no frame yet on " + c.ns + "/image_raw");
  return c.live.get(image->header.stamp.toSec(), [&] { return toJpeg(image); });
}

std::string CalibrationUiNodelet::frozenJpeg(int id) {
  Camera& c = camera(id);
  sensor_msgs::ImageConstPtr image;
  {
    std::lock_guard<std::mutex> lock(c.mutex);
    image = c.frozen;
  }
  if (!image) throw UiRequestError(409, "no frozen frame: freeze one first");
  return toJpeg(image);
}

std::string CalibrationUiNodelet::classificationJpeg(int id) {
  Camera& c = camera(id);
  sensor_msgs::ImageConstPtr image;
  {
    std::lock_guard<std::mutex> lock(c.mutex);
    c.classification_wanted = ros::WallTime::now();
    if (!c.classification_sub) {
      // Subscribing makes the Segmentation classify every pixel: only while a browser asks.
      Camera* cp = &c;
      c.classification_sub =
          it_->subscribe(c.ns + "/debug/classification", 1, [cp](const sensor_msgs::ImageConstPtr& m) {
            std::lock_guard<std::mutex> l(cp->mutex);
            cp->classification = m;
          });
    }
    image = c.classification;
  }
  if (!image) throw UiRequestError(503, "no classification yet on " + c.ns + "/debug/classification");
  return c.classification_jpeg.get(image->header.stamp.toSec(), [&] { return toJpeg(image); });
}

void CalibrationUiNodelet::updateClassificationSubscriptions() {
  const ros::WallTime now = ros::WallTime::now();
  for (auto& c : cameras_) {
    std::lock_guard<std::mutex> lock(c->mutex);
    if (c->classification_sub && (now - c->classification_wanted).toSec() > 3.0) {
      c->classification_sub.shutdown();
      c->classification.reset();
    }
  }
}

std::optional<CameraModel> CalibrationUiNodelet::currentModel(Camera& c, const std::string& frame_id) {
  sensor_msgs::CameraInfoConstPtr info;
  {
    std::lock_guard<std::mutex> lock(c.mutex);
    info = c.info;
  }
  if (!info || frame_id.empty()) return std::nullopt;
  try {
    const auto t = tf_buffer_->lookupTransform("field", frame_id, ros::Time(0));
    return CameraModel(intrinsicsFromCameraInfo(*info), fromTransform(t.transform));
  } catch (const std::exception&) {
    return std::nullopt;  // no pose yet: no field lines, no robots
  }
}

nlohmann::json CalibrationUiNodelet::overlay(int id, bool frozen) {
  Camera& c = camera(id);
  sensor_msgs::ImageConstPtr image;
  BlobArrayConstPtr blobs;
  std::optional<CameraPoseSolution> solved;
  {
    std::lock_guard<std::mutex> lock(c.mutex);
    image = frozen ? c.frozen : (c.recent.empty() ? nullptr : c.recent.back());
    blobs = frozen ? c.frozen_blobs : (c.recent_blobs.empty() ? nullptr : c.recent_blobs.back());
    solved = c.solved;
  }
  nlohmann::json out = {{"camera", id}};
  if (!image) return out;
  out["stamp"] = image->header.stamp.toSec();
  out["width"] = image->width;
  out["height"] = image->height;
  nlohmann::json regions = nlohmann::json::array();
  if (blobs) {
    for (const Blob& b : blobs->blobs)
      regions.push_back({{"color", std::string(colorClassName(static_cast<ColorClass>(b.color)))},
                         {"cx", b.cx},
                         {"cy", b.cy},
                         {"area", b.area},
                         {"box", {b.x0, b.y0, b.width, b.height}}});
  }
  out["regions"] = regions;
  std::optional<CameraModel> model = currentModel(c, image->header.frame_id);
  out["pose"] = model ? "tf" : "none";
  if (frozen && solved) {
    model = solved->model();
    out["pose"] = "solved";
  }
  if (!model) return out;
  out["field_lines"] = toJson(projectFieldMarkings(*model, field_));
  nlohmann::json landmarks = nlohmann::json::array();
  for (const LandmarkSuggestion& s : suggestLandmarks(field_, &*model))
    landmarks.push_back({{"field", {s.field.x(), s.field.y(), s.field.z()}},
                         {"pixel", s.pixel ? toJson(*s.pixel) : nlohmann::json()}});
  out["landmarks"] = landmarks;
  if (frozen) return out;
  RobotPoseArrayConstPtr robots;
  BallPoseArrayConstPtr balls;
  {
    std::lock_guard<std::mutex> lock(state_mutex_);
    robots = robots_;
    balls = balls_;
  }
  // The robots are drawn at their marker plane. The UI is given no pattern: both teams at the
  // default plane (a team 2 cm lower is drawn a few pixels off near the image's edge).
  const double marker_height = PatternSet().robot_height;
  nlohmann::json robot_list = nlohmann::json::array();
  if (robots) {
    for (const RobotPose& r : robots->robots) {
      const Eigen::Vector3d centre(r.x, r.y, marker_height);
      const auto p = model->projectInImage(centre);
      if (!p) continue;
      nlohmann::json j = {{"team", r.team == RobotPose::TEAM_BLUE ? "blue" : "yellow"},
                          {"id", r.id == 255 ? -1 : r.id},
                          {"pixel", toJson(*p)},
                          {"visible", r.visible}};
      if (std::isfinite(r.theta)) {
        const auto nose =
            model->project(centre + 0.09 * Eigen::Vector3d(std::cos(r.theta), std::sin(r.theta), 0));
        if (nose) j["heading_pixel"] = toJson(*nose);
      }
      robot_list.push_back(j);
    }
  }
  out["robots"] = robot_list;
  nlohmann::json ball_list = nlohmann::json::array();
  if (balls) {
    for (const BallPose& b : balls->balls) {
      const auto p = model->projectInImage(Eigen::Vector3d(b.x, b.y, b.z));
      if (p) ball_list.push_back({{"pixel", toJson(*p)}, {"visible", b.visible}});
    }
  }
  out["balls"] = ball_list;
  return out;
}

nlohmann::json CalibrationUiNodelet::freeze(int id) {
  Camera& c = camera(id);
  std::lock_guard<std::mutex> lock(c.mutex);
  if (c.recent.empty()) throw UiRequestError(503, "no frame yet on " + c.ns + "/image_raw");
  // The newest frame whose regions have arrived, so the frozen view can show them too.
  c.frozen = c.recent.back();
  c.frozen_blobs.reset();
  for (auto b = c.recent_blobs.rbegin(); b != c.recent_blobs.rend() && !c.frozen_blobs; ++b) {
    for (const auto& image : c.recent) {
      if (image->header.stamp == (*b)->header.stamp) {
        c.frozen = image;
        c.frozen_blobs = *b;
        break;
      }
    }
  }
  c.solved.reset();
  c.refined.reset();
  return {
      {"stamp", c.frozen->header.stamp.toSec()}, {"width", c.frozen->width}, {"height", c.frozen->height}};
}

nlohmann::json CalibrationUiNodelet::calibrateColors(int id, const nlohmann::json& body) {
  Camera& c = camera(id);
  sensor_msgs::ImageConstPtr frozen;
  {
    std::lock_guard<std::mutex> lock(c.mutex);
    frozen = c.frozen;
  }
  if (!frozen) throw UiRequestError(409, "no frozen frame: freeze one and paint samples on it");
  const ColorSamples samples = parseSamplesRequest(body, static_cast<int>(frozen->width),
                                                   static_cast<int>(frozen->height), UiRequestLimits());
  const auto save = body.find("save");
  if (save != body.end() && !save->is_boolean()) throw UiRequestError(400, "`save` is not true or false");
  const auto replace = body.find("replace");
  if (replace != body.end() && !replace->is_boolean())
    throw UiRequestError(400, "`replace` is not true or false");
  Calibrate srv;
  srv.request.samples_yaml = toYaml(samples);
  srv.request.save = save != body.end() && save->get<bool>();
  srv.request.replace = replace != body.end() && replace->get<bool>();
  srv.request.image = *frozen;
  const std::string service = c.ns + "/segmentation/calibrate";
  if (!ros::service::waitForService(service, ros::Duration(0.5)))
    throw UiRequestError(503, "the service " + service + " is not available");
  const bool called = ros::service::call(service, srv);
  std::lock_guard<std::mutex> lock(state_mutex_);
  ++calibrations_;
  if (!called || !srv.response.success) ++calibrations_failed_;
  if (!called) throw UiRequestError(503, "the call of " + service + " failed");
  return {{"success", static_cast<bool>(srv.response.success)},
          {"message", srv.response.message},
          {"saved", srv.request.save && srv.response.success}};
}

nlohmann::json CalibrationUiNodelet::solvePose(int id, const nlohmann::json& body) {
  Camera& c = camera(id);
  sensor_msgs::ImageConstPtr frozen;
  sensor_msgs::CameraInfoConstPtr info;
  {
    std::lock_guard<std::mutex> lock(c.mutex);
    frozen = c.frozen;
    info = c.info;
  }
  if (!frozen) throw UiRequestError(409, "no frozen frame: freeze one and click the landmarks on it");
  if (!info) throw UiRequestError(503, "no camera_info yet on " + c.ns + "/camera_info");
  const std::vector<FieldCorrespondence> points = parseCorrespondencesRequest(
      body, static_cast<int>(frozen->width), static_cast<int>(frozen->height), UiRequestLimits());
  CameraPoseSolution solution;
  try {
    solution = solveCameraPose(intrinsicsFromCameraInfo(*info), points);
  } catch (const std::exception& e) {
    throw UiRequestError(400, std::string("cannot solve the pose: ") + e.what());
  }
  // The clicks start a fit to the frozen frame's field lines (as calibrate_field --image
  // --points); where the lines confirm it, its pose is the one drawn and saved.
  LineRefinement refinement;
  try {
    refinement =
        refinePoseOnFieldLines(cv_bridge::toCvShare(frozen, "bgr8")->image, field_, solution.model());
  } catch (const cv_bridge::Exception& e) {
    refinement.reason = std::string("the frozen frame cannot be read as BGR: ") + e.what();
  }
  nlohmann::json lines = {{"refined", refinement.fit.has_value()}};
  if (refinement.fit) {
    const Eigen::Vector3d moved = refinement.fit->camera.cameraCentre() - solution.model().cameraCentre();
    solution.field_T_camera = refinement.fit->camera.fieldTCamera();
    lines["rms_px"] = refinement.fit->rms_px;
    lines["pixels"] = refinement.fit->pixels_paired;
    lines["moved_mm"] = 1000 * moved.norm();
    lines["advice"] = refinement.advice;
  } else {
    lines["reason"] = refinement.reason;
  }
  {
    std::lock_guard<std::mutex> lock(c.mutex);
    c.solved = solution;
    c.refined = refinement.fit;
  }
  const Eigen::Vector3d t = solution.field_T_camera.translation();
  const Eigen::Quaterniond q(solution.field_T_camera.rotation());
  return {{"rms_px", solution.rms_px},
          {"max_px", solution.max_px},
          {"errors_px", solution.errors_px},
          {"lines", lines},
          {"translation", {t.x(), t.y(), t.z()}},
          {"rotation", {q.x(), q.y(), q.z(), q.w()}},
          {"field_lines", toJson(projectFieldMarkings(solution.model(), field_))}};
}

nlohmann::json CalibrationUiNodelet::savePose(int id) {
  Camera& c = camera(id);
  std::optional<CameraPoseSolution> solved;
  std::optional<FieldLineFit> refined;
  {
    std::lock_guard<std::mutex> lock(c.mutex);
    solved = c.solved;
    refined = c.refined;
  }
  if (!solved) throw UiRequestError(409, "no solved pose: click at least 4 landmarks and solve first");
  CameraPoseFile file;
  file.camera_id = c.id;
  file.child_frame_id = "camera_" + std::to_string(c.id) + "_optical";
  file.field_T_camera = solved->field_T_camera;
  // The residual of what fixed the pose: the line pixels' when the lines refined it (as
  // calibrate_field --image writes), else the clicked points'.
  file.rms_error_px = refined ? refined->rms_px : solved->rms_px;
  file.points = refined ? refined->pixels_within_3px : static_cast<int>(solved->errors_px.size());
  file.intrinsics = solved->intrinsics;
  const std::string path = pose_dir_ + "/camera_pose_" + std::to_string(c.id) + ".yaml";
  try {
    saveCameraPoseFile(path, file);
  } catch (const std::exception& e) {
    throw UiRequestError(500, std::string("cannot save the pose: ") + e.what());
  }
  NODELET_INFO("camera %d pose saved to %s (RMS %.2f px%s)", c.id, path.c_str(), file.rms_error_px,
               refined ? ", field lines" : ", points");
  return {{"path", path}, {"rms_px", file.rms_error_px}, {"refined_on_lines", refined.has_value()}};
}

nlohmann::json CalibrationUiNodelet::info() {
  nlohmann::json cams = nlohmann::json::array();
  for (auto& c : cameras_) cams.push_back({{"id", c->id}, {"namespace", c->ns}});
  return {{"cameras", cams}, {"field", field_.name}};
}

nlohmann::json CalibrationUiNodelet::status() {
  nlohmann::json list = nlohmann::json::array();
  std::lock_guard<std::mutex> lock(state_mutex_);
  for (const auto& [name, s] : diagnostics_) {
    nlohmann::json values = nlohmann::json::object();
    for (const auto& kv : s.values) values[kv.key] = kv.value;
    list.push_back(
        {{"name", name}, {"level", static_cast<int>(s.level)}, {"message", s.message}, {"values", values}});
  }
  return {{"diagnostics", list}};
}

void CalibrationUiNodelet::diagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  if (!server_) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "not serving: " + server_error_);
    return;
  }
  if (!server_->access().changesEnabled())
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "read-only: " + server_->access().readOnlyReason());
  else
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "serving");
  stat.add("port", server_->port());
  stat.add("requests", server_->requests());
  stat.add("refused: no or wrong token", server_->refused());
  stat.add("failed requests", server_->failed());
  std::lock_guard<std::mutex> lock(state_mutex_);
  stat.add("colour calibrations", calibrations_);
  stat.add("colour calibrations failed", calibrations_failed_);
}

}  // namespace soccer_vision

PLUGINLIB_EXPORT_CLASS(soccer_vision::CalibrationUiNodelet, nodelet::Nodelet)
