// soccer_vision/Segmentation: the segmentation stage (paper §III-A/B) between the camera driver
// and identification: per frame of `image_raw`, illumination adaptation, colour-table lookup and
// the regions of the marker colours, in the search windows or the whole frame, as one BlobArray.
// A thin adapter over the Segmenter (src/segmentation/): this file moves parameters, tables and
// messages. Parameters, topics and services: docs/nodelets.md, generated from
// cfg/Segmentation.cfg and cfg/Segmentation.params.yaml.
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <unistd.h>
#include <vector>

#include <boost/make_shared.hpp>
#include <cv_bridge/cv_bridge.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <opencv2/imgproc.hpp>
#include <pluginlib/class_list_macros.hpp>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>
#include <std_msgs/UInt64MultiArray.h>
#include <std_srvs/Trigger.h>

#include "soccer_vision/BlobArray.h"
#include "soccer_vision/Calibrate.h"
#include "soccer_vision/SearchWindows.h"
#include "soccer_vision/SegmentationConfig.h"
#include "soccer_vision/calibration/color_calibration.h"
#include "soccer_vision/common/exchange_formats.h"
#include "soccer_vision/common/path_inside_directory.h"
#include "soccer_vision/common/robot_pattern.h"
#include "soccer_vision/ros/blob_conversions.h"
#include "soccer_vision/ros/image_message.h"
#include "soccer_vision/segmentation/color_table.h"
#include "soccer_vision/segmentation/online_calibration.h"
#include "soccer_vision/segmentation/segmenter.h"
#include "soccer_vision/tracking/frame_step.h"

namespace soccer_vision {

namespace {

SegmentationParams toSegmentationParams(const SegmentationConfig& c) {
  SegmentationParams p;
  p.illumination_k = c.illumination_k;
  p.sharpen = c.sharpen;
  p.ball_streaks = c.ball_streaks;
  p.ball_streak_floor_share = c.ball_streak_floor_share;
  p.regions.morph_kernel = c.morph_kernel;
  p.regions.min_area = c.min_area;
  p.regions.max_area = std::max(c.max_area, c.min_area);
  p.regions.max_regions_per_class = c.max_regions_per_class;
  p.regions.coverage_weighted_moments = c.coverage_weighted_moments;
  return p;
}

// Segmented frames kept for the confirmed markers Identification sends back (a few frames
// behind at most).
constexpr std::size_t kRecentFrames = 8;

// The region of `regions` a confirmed marker blob was made from (toBlob keeps colour and
// centroid exactly); -1 when none is.
int regionOf(const Blob& blob, const std::vector<Region>& regions) {
  for (std::size_t i = 0; i < regions.size(); ++i) {
    const Region& r = regions[i];
    if (static_cast<int>(r.color) == blob.color && r.cx == blob.cx && r.cy == blob.cy)
      return static_cast<int>(i);
  }
  return -1;
}

// One line per class with samples: what calibration saw and decided.
std::string summarizeTable(const ColorTable& table) {
  const ColorTableStatistics& st = table.statistics();
  std::ostringstream os;
  os.setf(std::ios::fixed);
  os.precision(1);
  for (int c = 1; c < kNumColorClasses; ++c) {
    const ClassStatistics& s = st.classes[c];
    if (s.samples == 0) continue;
    os << colorClassName(static_cast<ColorClass>(c)) << ": " << s.valid << "/" << s.samples << " valid, Lab ("
       << s.mean_lab.l << ", " << s.mean_lab.a << ", " << s.mean_lab.b << "), H " << s.mean_h << ", cells "
       << s.cells_assigned << "/" << s.cells_claimed << "; ";
  }
  os << st.overlap_cells << " overlap cells decided by Bayes";
  return os.str();
}

}  // namespace

class SegmentationNodelet : public nodelet::Nodelet {
 public:
  SegmentationNodelet() = default;
  ~SegmentationNodelet() override;

 private:
  void onInit() override;
  void imageCallback(const sensor_msgs::ImageConstPtr& image);
  void windowsCallback(const SearchWindowsConstPtr& windows);
  void reconfigure(SegmentationConfig& config, uint32_t level);
  bool calibrate(Calibrate::Request& req, Calibrate::Response& res);
  void calibrateLoop();
  std::string saveDirectory(const std::string& color_table_path) const;
  void loaderLoop();
  void requestLoad(const std::string& path);
  // The windows of the latest SearchWindows for this camera and stamp (none: whole frame),
  // and its ball_streak_windows and lost_ball_streak_windows.
  struct FrameWindows {
    std::vector<cv::Rect> windows, ball_streak, lost_ball_streak;
  };
  FrameWindows searchWindows(const ros::Time& image_stamp);
  void publishDebug(const sensor_msgs::ImageConstPtr& image, const cv::Mat& mat, PixelLayout layout,
                    const SegmentationModel& model);
  void diagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat);
  void dropFrame(std::uint64_t& counter);
  void confirmedCallback(const BlobArrayConstPtr& markers);
  bool resetOnlineCalibration(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  void stopLearning();

  std::shared_ptr<const SegmentationModel> model() {
    std::lock_guard<std::mutex> lock(model_mutex_);
    return model_;
  }
  void setModel(std::shared_ptr<const SegmentationModel> m, const std::string& source) {
    swapModel(std::move(m));
    std::lock_guard<std::mutex> lock(state_mutex_);
    table_source_ = source;
    table_error_.clear();
  }
  // The same model source, refined or reset by online calibration.
  void swapModel(std::shared_ptr<const SegmentationModel> m) {
    std::lock_guard<std::mutex> lock(model_mutex_);
    model_ = std::move(m);
  }

  // Parameters.
  int camera_id_ = 0;
  double window_max_age_ = 0.5;
  bool report_data_pointer_ = false;
  std::string calibration_save_directory_;  // "" = the color_table's directory
  // The marker pattern: ~calibrate warns of its colours the new table has no cell for.
  std::optional<PatternSet> pattern_;

  std::unique_ptr<image_transport::ImageTransport> it_;
  image_transport::Subscriber image_sub_;
  image_transport::Publisher debug_pub_;
  ros::Subscriber windows_sub_;
  ros::Publisher blobs_pub_, address_pub_;
  ros::ServiceServer calibrate_srv_, reset_online_srv_;
  // ~calibrate runs on its own queue and thread: its cost (pixels, polygons) never delays a
  // frame of the nodelet's queue.
  ros::CallbackQueue calibrate_queue_;
  std::thread calibrate_thread_;
  std::atomic<bool> calibrate_stop_{false};

  // Online self-calibration, on the calibrate thread: confirmed markers from Identification
  // meet the frame they were found in (kept here while learning), and the learned model is
  // swapped in like a calibrated one. The calibrated model stays its base.
  struct RecentFrame {
    ros::Time stamp;
    sensor_msgs::ImageConstPtr image;  // shared, never modified
    PixelLayout layout = PixelLayout::Bgr;
    BlockOffsets offsets;
    std::vector<Region> regions;
    double sharpen = 0;
  };
  ros::NodeHandle learn_nh_;  // on calibrate_queue_
  ros::Subscriber confirmed_sub_;
  std::mutex recent_mutex_;
  std::deque<RecentFrame> recent_;
  std::mutex learn_mutex_;  // learning_
  std::unique_ptr<OnlineCalibration> learning_;
  std::atomic<bool> learning_enabled_{false};

  using ReconfigureServer = dynamic_reconfigure::Server<SegmentationConfig>;
  std::unique_ptr<ReconfigureServer> reconfigure_server_;
  boost::recursive_mutex reconfigure_mutex_;

  // The current model (table + lookup + illumination reference): swapped as a whole.
  std::mutex model_mutex_;
  std::shared_ptr<const SegmentationModel> model_;

  // Image callback (serialised by the subscription): the segmenter and its result buffer.
  FrameStep frame_step_;
  Segmenter segmenter_;
  SegmentationResult result_;

  // Set by reconfigure, applied by the image callback / read by ~calibrate.
  std::mutex config_mutex_;
  SegmentationParams params_;
  int frame_step_setting_ = 1;
  bool params_changed_ = false;
  double threshold_lab_ = 20.0, threshold_h_ = 15.0;
  OnlineCalibrationParams online_params_;
  std::string color_table_path_;

  // The frames ~calibrate built the current table from, since the last replace or table
  // file: a merge calibrates on them and its own frame together.
  struct CalibratedFrame {
    ros::Time stamp;
    CalibrationImage image;
  };
  static constexpr std::size_t kMaxCalibratedFrames = 8;
  std::mutex calibrated_mutex_;
  std::vector<CalibratedFrame> calibrated_frames_;

  // Latest received frame (for ~calibrate) and latest search windows.
  std::mutex input_mutex_;
  sensor_msgs::ImageConstPtr last_image_;
  SearchWindowsConstPtr windows_;

  // Background loading of colour-table files: the latest request wins.
  std::thread loader_;
  std::mutex load_mutex_;
  std::condition_variable load_cv_;
  std::optional<std::string> pending_load_;
  bool stopping_ = false;
  std::string requested_path_;  // reconfigure thread
  std::atomic<bool> last_load_failed_{false};

  // Diagnostics.
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  ros::WallTimer diag_timer_;
  std::mutex state_mutex_;
  std::string table_source_;  // "" = no table yet
  std::string table_error_;   // last load/calibration failure
  ros::WallTime window_start_;
  std::uint64_t frames_processed_ = 0, window_frames_ = 0;
  double window_ms_sum_ = 0, window_ms_max_ = 0;
  std::array<std::uint64_t, kNumColorClasses> window_regions_{};
  std::array<std::uint64_t, kNumColorClasses> cap_hits_total_{};
  std::array<std::uint64_t, kNumColorClasses> fringes_total_{};  // Bayer colour fringes dropped
  std::uint64_t window_cap_hits_ = 0;
  std::uint64_t dropped_encoding_ = 0, dropped_bad_image_ = 0, dropped_no_table_ = 0, dropped_error_ = 0;
  std::uint64_t window_dropped_ = 0;
  std::uint64_t windowed_frames_ = 0, illumination_mismatch_ = 0, skipped_by_frame_step_ = 0;
  // The ball's streak table (ball_streaks): frames it searched, regions kept and refused.
  std::uint64_t streak_frames_ = 0, streak_regions_ = 0, streak_refused_ = 0;
  std::uint64_t calibrations_refused_ = 0;
  OnlineCalibrationStatus online_status_;
  std::uint64_t confirmed_unmatched_ = 0;  // confirmed markers whose frame was no longer kept
  std::uint64_t online_errors_ = 0;
  std::string online_error_;
  std::string last_bad_encoding_;
};

SegmentationNodelet::~SegmentationNodelet() {
  diag_timer_.stop();
  calibrate_srv_.shutdown();
  reset_online_srv_.shutdown();
  confirmed_sub_.shutdown();
  calibrate_stop_ = true;
  if (calibrate_thread_.joinable()) calibrate_thread_.join();
  {
    std::lock_guard<std::mutex> lock(load_mutex_);
    stopping_ = true;
  }
  load_cv_.notify_all();
  if (loader_.joinable()) loader_.join();
}

void SegmentationNodelet::onInit() {
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();

  pnh.param("camera_id", camera_id_, 0);
  if (camera_id_ < 0 || camera_id_ > 255) {
    NODELET_ERROR("camera_id %d out of range 0..255; using 0", camera_id_);
    camera_id_ = 0;
  }
  pnh.param("search_window_max_age", window_max_age_, 0.5);
  pnh.param("debug_report_data_pointer", report_data_pointer_, false);
  pnh.param("calibration_save_directory", calibration_save_directory_, std::string());
  std::string pattern;
  pnh.param("pattern", pattern, std::string("two_tag"));
  try {
    if (!pattern.empty()) pattern_ = patternSetByName(pattern);
  } catch (const std::exception& e) {
    NODELET_ERROR("pattern: %s; ~calibrate does not check the pattern's colours", e.what());
  }
  int queue_size = 2;
  pnh.param("queue_size", queue_size, 2);
  queue_size = std::max(1, queue_size);

  loader_ = std::thread(&SegmentationNodelet::loaderLoop, this);
  learn_nh_ = nh;
  learn_nh_.setCallbackQueue(&calibrate_queue_);

  updater_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
  updater_->setHardwareID("camera " + std::to_string(camera_id_));
  updater_->add("segmentation", this, &SegmentationNodelet::diagnostics);
  window_start_ = ros::WallTime::now();
  diag_timer_ =
      nh.createWallTimer(ros::WallDuration(0.5), [this](const ros::WallTimerEvent&) { updater_->update(); });

  // The reconfigure server reads the ~parameters and calls reconfigure() at once, which
  // applies them and requests the load of ~color_table (in the background).
  reconfigure_server_ = std::make_unique<ReconfigureServer>(reconfigure_mutex_, pnh);
  reconfigure_server_->setCallback([this](SegmentationConfig& c, uint32_t level) { reconfigure(c, level); });
  {
    std::lock_guard<std::mutex> lock(config_mutex_);
    segmenter_.setParams(params_);
    params_changed_ = false;
  }

  blobs_pub_ = nh.advertise<BlobArray>("blobs", 5);
  if (report_data_pointer_)
    address_pub_ = nh.advertise<std_msgs::UInt64MultiArray>("debug/image_data_address", 20);
  it_ = std::make_unique<image_transport::ImageTransport>(nh);
  debug_pub_ = it_->advertise("debug/classification", 1);
  windows_sub_ = nh.subscribe("search_windows", 2, &SegmentationNodelet::windowsCallback, this);
  ros::NodeHandle calibrate_nh(pnh);
  calibrate_nh.setCallbackQueue(&calibrate_queue_);
  calibrate_srv_ = calibrate_nh.advertiseService("calibrate", &SegmentationNodelet::calibrate, this);
  reset_online_srv_ = calibrate_nh.advertiseService("reset_online_calibration",
                                                    &SegmentationNodelet::resetOnlineCalibration, this);
  calibrate_thread_ = std::thread(&SegmentationNodelet::calibrateLoop, this);
  image_sub_ =
      it_->subscribe("image_raw", static_cast<uint32_t>(queue_size), &SegmentationNodelet::imageCallback,
                     this, image_transport::TransportHints("raw", ros::TransportHints(), pnh));
}

void SegmentationNodelet::reconfigure(SegmentationConfig& config, uint32_t /*level*/) {
  if (config.max_area < config.min_area) {
    NODELET_ERROR("max_area %d < min_area %d; using max_area = min_area", config.max_area, config.min_area);
    config.max_area = config.min_area;
  }
  {
    std::lock_guard<std::mutex> lock(config_mutex_);
    params_ = toSegmentationParams(config);
    frame_step_setting_ = std::max(1, config.frame_step);
    params_changed_ = true;
    threshold_lab_ = config.threshold_lab;
    threshold_h_ = config.threshold_h;
    color_table_path_ = config.color_table;
    online_params_.enabled = config.online_calibration;
    online_params_.update_period = config.online_update_period;
  }
  // Learning subscribes to Identification's confirmed markers (which it sends only then);
  // switched off, it returns to the calibrated model.
  if (config.online_calibration && !confirmed_sub_) {
    confirmed_sub_ =
        learn_nh_.subscribe("confirmed_markers", 5, &SegmentationNodelet::confirmedCallback, this);
  } else if (!config.online_calibration && confirmed_sub_) {
    confirmed_sub_.shutdown();
    stopLearning();
  }
  learning_enabled_ = config.online_calibration;
  // A new path, or the same one again after a failed load (the file may be fixed now).
  if (config.color_table != requested_path_ || last_load_failed_) {
    requested_path_ = config.color_table;
    if (!config.color_table.empty()) {
      requestLoad(config.color_table);
    } else if (!model()) {
      NODELET_WARN("no color_table given: frames are dropped until ~calibrate makes a table");
    }
  }
}

void SegmentationNodelet::requestLoad(const std::string& path) {
  {
    std::lock_guard<std::mutex> lock(load_mutex_);
    pending_load_ = path;
  }
  load_cv_.notify_all();
}

void SegmentationNodelet::loaderLoop() {
  std::unique_lock<std::mutex> lock(load_mutex_);
  std::optional<std::string> retry;  // a file not there yet or not loadable, while there is no table
  while (true) {
    auto wake = [this] { return stopping_ || pending_load_.has_value(); };
    if (retry) {
      if (!load_cv_.wait_for(lock, std::chrono::seconds(1), wake)) pending_load_ = retry;
    } else {
      load_cv_.wait(lock, wake);
    }
    if (stopping_) return;
    const std::string path = *pending_load_;
    pending_load_.reset();
    retry.reset();
    lock.unlock();
    // Without any table, a file that does not exist yet (being written by a calibration
    // started at the same time, e.g. the demo's) is waited for, with the error once.
    bool retry_after_failure = false;
    if (!model() && access(path.c_str(), F_OK) != 0) {
      if (!last_load_failed_)
        NODELET_ERROR("color_table %s does not exist (yet): waiting for it", path.c_str());
      last_load_failed_ = true;
      {
        std::lock_guard<std::mutex> state(state_mutex_);
        table_error_ = "waiting for " + path;
      }
      lock.lock();
      retry = path;
      continue;
    }
    try {
      auto table = std::make_shared<const ColorTable>(ColorTable::load(path));
      // Costly (fills the lookup tables): built here, outside every lock, then swapped.
      std::shared_ptr<const SegmentationModel> m = SegmentationModel::fromTable(table);
      setModel(std::move(m), "file " + path);
      {
        std::lock_guard<std::mutex> calibrated(calibrated_mutex_);
        calibrated_frames_.clear();
      }
      last_load_failed_ = false;
      NODELET_INFO("colour table loaded from %s%s", path.c_str(),
                   table->illuminationReference().empty() ? " (no illumination reference)" : "");
    } catch (const std::exception& e) {
      const bool have = static_cast<bool>(model());
      // Without any table it is tried again every second, the error once: a file another
      // process has not finished writing (likely why a camera of a CI run had no detections
      // for 140 s) or one the user fixes in place.
      if (have || !last_load_failed_) {
        NODELET_ERROR("cannot load color_table: %s; %s", e.what(),
                      have ? "keeping the previous table" : "no table yet: frames are dropped; trying again");
      }
      last_load_failed_ = true;
      retry_after_failure = !have;
      std::lock_guard<std::mutex> state(state_mutex_);
      table_error_ = e.what();
    }
    lock.lock();
    if (retry_after_failure) retry = path;
  }
}

void SegmentationNodelet::windowsCallback(const SearchWindowsConstPtr& windows) {
  std::lock_guard<std::mutex> lock(input_mutex_);
  windows_ = windows;
}

SegmentationNodelet::FrameWindows SegmentationNodelet::searchWindows(const ros::Time& image_stamp) {
  SearchWindowsConstPtr w;
  {
    std::lock_guard<std::mutex> lock(input_mutex_);
    w = windows_;
  }
  FrameWindows out;
  if (!w || w->camera_id != camera_id_) return out;
  if ((image_stamp - w->header.stamp).toSec() > window_max_age_) return out;
  auto append = [](const std::vector<sensor_msgs::RegionOfInterest>& rois, std::vector<cv::Rect>& rects) {
    rects.reserve(rois.size());
    for (const auto& roi : rois) {
      const cv::Rect r = fromRegionOfInterest(roi);
      if (!r.empty()) rects.push_back(r);
    }
  };
  if (!w->global_search) append(w->windows, out.windows);  // empty (no usable window): whole frame
  append(w->ball_streak_windows, out.ball_streak);
  append(w->lost_ball_streak_windows, out.lost_ball_streak);
  return out;
}

void SegmentationNodelet::dropFrame(std::uint64_t& counter) {
  std::lock_guard<std::mutex> lock(state_mutex_);
  ++counter;
  ++window_dropped_;
}

void SegmentationNodelet::imageCallback(const sensor_msgs::ImageConstPtr& image) {
  const std::optional<PixelLayout> layout = pixelLayoutForEncoding(image->encoding);
  if (!layout) {
    NODELET_ERROR_THROTTLE(5.0,
                           "image_raw encoding '%s' is not supported (bgr8, rgb8, "
                           "bayer_*8 are); frame dropped",
                           image->encoding.c_str());
    {
      std::lock_guard<std::mutex> lock(state_mutex_);
      last_bad_encoding_ = image->encoding;
    }
    dropFrame(dropped_encoding_);
    return;
  }
  if (!imageMessageIsConsistent(*image, *layout)) {
    NODELET_ERROR_THROTTLE(5.0,
                           "image_raw %ux%u %s with step %u and %zu data bytes is empty, "
                           "truncated or inconsistent; frame dropped",
                           image->width, image->height, image->encoding.c_str(), image->step,
                           image->data.size());
    dropFrame(dropped_bad_image_);
    return;
  }
  cv_bridge::CvImageConstPtr cv;
  try {
    cv = cv_bridge::toCvShare(image);  // a view of the message buffer, no copy
  } catch (const cv_bridge::Exception& e) {
    NODELET_ERROR_THROTTLE(5.0, "cv_bridge: %s; frame dropped", e.what());
    dropFrame(dropped_bad_image_);
    return;
  }
  if (report_data_pointer_) {
    auto report = boost::make_shared<std_msgs::UInt64MultiArray>();
    report->data = {image->header.stamp.sec, image->header.stamp.nsec,
                    static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(cv->image.data))};
    address_pub_.publish(report);
  }
  {
    std::lock_guard<std::mutex> lock(input_mutex_);
    last_image_ = image;  // for ~calibrate
  }
  const std::shared_ptr<const SegmentationModel> m = model();
  if (!m) {
    NODELET_ERROR_THROTTLE(5.0,
                           "no colour table yet (set color_table or call ~calibrate); "
                           "frame dropped");
    dropFrame(dropped_no_table_);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(config_mutex_);
    if (params_changed_) {
      segmenter_.setParams(params_);
      if (frame_step_.step() != frame_step_setting_) frame_step_.setStep(frame_step_setting_);
      params_changed_ = false;
    }
  }
  if (!frame_step_.process()) {
    std::lock_guard<std::mutex> lock(state_mutex_);
    ++skipped_by_frame_step_;
    return;
  }
  const FrameWindows windows = searchWindows(image->header.stamp);
  try {
    segmenter_.process(*m, cv->image, *layout, windows.windows, result_,
                       streakWindows(*layout, windows.ball_streak, windows.lost_ball_streak));
  } catch (const std::exception& e) {
    NODELET_ERROR_THROTTLE(5.0, "segmentation failed: %s; frame dropped", e.what());
    dropFrame(dropped_error_);
    return;
  }

  if (learning_enabled_) {
    std::lock_guard<std::mutex> lock(recent_mutex_);
    recent_.push_back(
        {image->header.stamp, image, *layout, result_.offsets, result_.regions, segmenter_.params().sharpen});
    while (recent_.size() > kRecentFrames) recent_.pop_front();
  }

  auto blobs = boost::make_shared<BlobArray>();
  toBlobArray(result_, image->header, camera_id_, static_cast<int>(image->width),
              static_cast<int>(image->height), isBayer(*layout), *blobs);
  blobs_pub_.publish(blobs);  // never touched after this

  {
    std::lock_guard<std::mutex> lock(state_mutex_);
    ++frames_processed_;
    ++window_frames_;
    window_ms_sum_ += result_.timings.total_ms;
    window_ms_max_ = std::max(window_ms_max_, result_.timings.total_ms);
    for (const Region& r : result_.regions) ++window_regions_[static_cast<int>(r.color)];
    for (int c = 0; c < kNumColorClasses; ++c) {
      cap_hits_total_[c] += result_.cap_hits[c];
      fringes_total_[c] += result_.fringes[c];
      window_cap_hits_ += result_.cap_hits[c];
    }
    if (!result_.global_search) ++windowed_frames_;
    if (result_.streak_windows) ++streak_frames_;
    streak_regions_ += result_.streak_regions;
    streak_refused_ += result_.streak_refused;
    if (result_.illumination_size_mismatch) ++illumination_mismatch_;
  }
  if (result_.illumination_size_mismatch)
    NODELET_ERROR_THROTTLE(5.0,
                           "the colour table's illumination reference is for another image size than "
                           "%ux%u: illumination adaptation is off; calibrate the table at this size",
                           image->width, image->height);

  if (debug_pub_.getNumSubscribers() > 0) publishDebug(image, cv->image, *layout, *m);
}

void SegmentationNodelet::publishDebug(const sensor_msgs::ImageConstPtr& image, const cv::Mat& mat,
                                       PixelLayout layout, const SegmentationModel& model) {
  try {
    const cv::Mat colors = colorizeLabels(classifyAll(model, mat, layout, segmenter_.params()));
    cv_bridge::CvImage out(image->header, sensor_msgs::image_encodings::BGR8, colors);
    debug_pub_.publish(out.toImageMsg());
  } catch (const std::exception& e) {
    NODELET_ERROR_THROTTLE(5.0, "debug/classification: %s", e.what());
  }
}

void SegmentationNodelet::confirmedCallback(const BlobArrayConstPtr& markers) {
  if (!learning_enabled_ || markers->camera_id != camera_id_) return;
  RecentFrame frame;
  bool found = false;
  {
    std::lock_guard<std::mutex> lock(recent_mutex_);
    for (const RecentFrame& f : recent_) {
      if (f.stamp == markers->header.stamp) {
        frame = f;
        found = true;
        break;
      }
    }
  }
  if (!found) {
    std::lock_guard<std::mutex> lock(state_mutex_);
    ++confirmed_unmatched_;
    return;
  }
  std::vector<int> confirmed;
  for (const Blob& b : markers->blobs) {
    const int i = regionOf(b, frame.regions);
    if (i >= 0) confirmed.push_back(i);
  }
  OnlineCalibrationParams params;
  {
    std::lock_guard<std::mutex> lock(config_mutex_);
    params = online_params_;
  }
  const std::shared_ptr<const SegmentationModel> current = model();
  if (!current) return;
  std::lock_guard<std::mutex> lock(learn_mutex_);
  try {
    // A table loaded or calibrated since: learning starts again on it.
    if (!learning_ || learning_->model() != current)
      learning_ = std::make_unique<OnlineCalibration>(current, params);
    learning_->setParams(params);
    const double stamp = frame.stamp.toSec();
    learning_->observe(frame.image ? cv_bridge::toCvShare(frame.image)->image : cv::Mat(), frame.layout,
                       frame.offsets, frame.sharpen, frame.regions, confirmed, stamp);
    // Costly (the lookup) but here, off the frame path; swapped in as a whole.
    if (auto learned = learning_->update(stamp)) swapModel(std::move(learned));
    std::lock_guard<std::mutex> state(state_mutex_);
    online_status_ = learning_->status();
  } catch (const std::exception& e) {
    NODELET_ERROR_THROTTLE(5.0, "online calibration: %s; frame not learned from", e.what());
    std::lock_guard<std::mutex> state(state_mutex_);
    ++online_errors_;
    online_error_ = e.what();
  }
}

void SegmentationNodelet::stopLearning() {
  std::lock_guard<std::mutex> lock(learn_mutex_);
  if (learning_ && model() == learning_->model()) swapModel(learning_->base());
  learning_.reset();
  {
    std::lock_guard<std::mutex> recent(recent_mutex_);
    recent_.clear();
  }
  std::lock_guard<std::mutex> state(state_mutex_);
  online_status_ = OnlineCalibrationStatus{};
}

bool SegmentationNodelet::resetOnlineCalibration(std_srvs::Trigger::Request& /*req*/,
                                                 std_srvs::Trigger::Response& res) {
  std::lock_guard<std::mutex> lock(learn_mutex_);
  if (!learning_) {
    res.success = true;
    res.message = learning_enabled_ ? "nothing learned yet" : "online_calibration is off: nothing learned";
    return true;
  }
  const std::uint32_t cells = learning_->status().learnedTotal();
  // Only when the model in use is the learned one (a table loaded since is kept).
  if (model() == learning_->model()) swapModel(learning_->base());
  learning_->reset();
  {
    std::lock_guard<std::mutex> state(state_mutex_);
    online_status_ = learning_->status();
  }
  res.success = true;
  res.message = "back to the calibrated table: " + std::to_string(cells) +
                " learned cells and the learned light forgotten";
  NODELET_INFO("~reset_online_calibration: %s", res.message.c_str());
  return true;
}

void SegmentationNodelet::calibrateLoop() {
  while (!calibrate_stop_ && ros::ok()) calibrate_queue_.callAvailable(ros::WallDuration(0.1));
}

// Where ~calibrate may save: calibration_save_directory, else the directory of the
// color_table file, else $ROS_HOME/soccer_vision (~/.ros/soccer_vision).
std::string SegmentationNodelet::saveDirectory(const std::string& color_table_path) const {
  if (!calibration_save_directory_.empty()) return calibration_save_directory_;
  if (!color_table_path.empty()) {
    const std::filesystem::path dir = std::filesystem::absolute(color_table_path).parent_path();
    return dir.string();
  }
  const char* ros_home = std::getenv("ROS_HOME");
  const char* home = std::getenv("HOME");
  const std::filesystem::path base = ros_home && *ros_home ? std::filesystem::path(ros_home)
                                     : home && *home       ? std::filesystem::path(home) / ".ros"
                                                           : std::filesystem::path("/tmp");
  return (base / "soccer_vision").string();
}

bool SegmentationNodelet::calibrate(Calibrate::Request& req, Calibrate::Response& res) {
  res.success = false;
  sensor_msgs::ImageConstPtr image;
  if (!req.image.data.empty()) {
    image = boost::make_shared<sensor_msgs::Image>(req.image);  // the frame the samples were drawn on
  } else {
    std::lock_guard<std::mutex> lock(input_mutex_);
    image = last_image_;
  }
  double threshold_lab, threshold_h;
  std::string default_path;
  {
    std::lock_guard<std::mutex> lock(config_mutex_);
    threshold_lab = req.threshold_lab > 0 ? req.threshold_lab : threshold_lab_;
    threshold_h = req.threshold_h > 0 ? req.threshold_h : threshold_h_;
    default_path = color_table_path_;
  }
  try {
    if (!image) throw std::runtime_error("no frame received yet on " + image_sub_.getTopic());
    const std::optional<PixelLayout> layout = pixelLayoutForEncoding(image->encoding);
    if (!layout) throw std::runtime_error("the frame has unsupported encoding " + image->encoding);
    if (!imageMessageIsConsistent(*image, *layout))
      throw std::runtime_error("the request's image is empty, truncated or inconsistent");
    const cv::Mat mat = cv_bridge::toCvShare(image)->image;
    // Calibration works on the colours the classifier reads (a Bayer mosaic's quads, not a
    // demosaic), as evaluate and the synthetic calibration do.
    const cv::Mat bgr = classifiedColors(mat, *layout);
    const ColorSamples samples = parseColorSamples(req.samples_yaml, "samples_yaml");
    if (samples.empty()) throw std::runtime_error("samples_yaml has no class with polygons");
    // Checked before any work: a save path outside the allowed directory is refused at once.
    std::string save_path;
    if (req.save) {
      const std::string path = req.path.empty() ? default_path : req.path;
      if (path.empty()) throw std::runtime_error("save requested without path or color_table");
      const std::string directory = saveDirectory(default_path);
      save_path = pathInsideDirectory(directory, path);
      if (calibration_save_directory_.empty() && default_path.empty())
        std::filesystem::create_directories(directory);
    }
    const ClassPixels pixels = collectSamplePixels(bgr, samples);
    for (const auto& entry : samples) {
      const auto it = pixels.find(entry.first);
      if (it == pixels.end() || it->second.empty())
        throw std::runtime_error("the polygons of class '" + std::string(colorClassName(entry.first)) +
                                 "' select no pixel of the frame (" + std::to_string(image->width) + "x" +
                                 std::to_string(image->height) + ")");
    }
    ColorTableParams params;
    params.threshold_lab = threshold_lab;
    params.threshold_h = threshold_h;
    params.validate();
    // A merge calibrates on the frames of the earlier calls too (this frame's earlier strokes
    // replaced), so colours added on a second frame share the Bayes decisions with the
    // first's; the unsampled markers of such an added frame are not background. Over a table
    // from a file, the classes without polygons keep their cells instead.
    const std::shared_ptr<const SegmentationModel> current = model();
    const bool merged = !req.replace && current;
    std::vector<CalibratedFrame> frames;
    std::optional<bool> background;  // this frame's, when it was calibrated on before
    if (merged) {
      std::lock_guard<std::mutex> lock(calibrated_mutex_);
      for (const CalibratedFrame& f : calibrated_frames_) {
        if (f.stamp == image->header.stamp)
          background = f.image.unsampled_is_background;
        else
          frames.push_back(f);
      }
    }
    const bool joint = !frames.empty();
    if (frames.size() >= kMaxCalibratedFrames) frames.erase(frames.begin());
    frames.push_back(
        {image->header.stamp, CalibrationImage{bgr.clone(), samples, background.value_or(!joint)}});
    std::vector<CalibrationImage> images;
    for (const CalibratedFrame& f : frames) images.push_back(f.image);
    // Table + illumination reference of these frames, then the lookup: outside every lock.
    // Over a table from a file the fresh table leaves the kept classes' colours alone.
    ColorTable fresh =
        calibrateColorTable(images, merged && !joint ? paramsBesideKeptClasses(params) : params);
    if (merged && !joint) fresh = keepUnsampledClasses(fresh, current->classifier->table(), samples);
    auto table = std::make_shared<const ColorTable>(std::move(fresh));
    // Swapped in only when every sampled class kept cells: a table that lost one would
    // silently stop seeing that colour.
    const std::vector<ColorClass> lost = classesWithoutCells(samples, *table);
    if (!lost.empty()) {
      throw std::runtime_error("the new table has no cell for " + colorClassNames(lost) + " (" +
                               summarizeTable(*table) + ")");
    }
    std::shared_ptr<const SegmentationModel> m = SegmentationModel::fromTable(table);
    std::string source = "~calibrate on frame " + std::to_string(image->header.stamp.toSec()) +
                         (joint    ? " and " + std::to_string(frames.size() - 1) + " earlier frame(s)"
                          : merged ? " (unsampled classes kept)"
                                   : "");
    if (req.save) {
      table->save(save_path);  // throws: the previous table stays
      source += ", saved to " + save_path;
    }
    setModel(std::move(m), source);
    {
      std::lock_guard<std::mutex> lock(calibrated_mutex_);
      calibrated_frames_ = std::move(frames);
    }
    last_load_failed_ = false;  // a failed color_table file is not retried over this table
    res.success = true;
    res.message = summarizeTable(*table);
    for (const std::string& w : calibrationWarnings(images, *table, pattern_ ? &*pattern_ : nullptr)) {
      res.message += "; warning: " + w;
      NODELET_WARN("~calibrate: %s", w.c_str());
    }
    NODELET_INFO("%s: %s", source.c_str(), res.message.c_str());
  } catch (const std::exception& e) {
    res.message = std::string("calibration failed, previous table kept: ") + e.what();
    NODELET_ERROR_THROTTLE(1.0, "~calibrate: %s", res.message.c_str());
    std::lock_guard<std::mutex> lock(state_mutex_);
    table_error_ = e.what();
    ++calibrations_refused_;
  }
  return true;  // the outcome is in the response
}

void SegmentationNodelet::diagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  std::lock_guard<std::mutex> lock(state_mutex_);
  const ros::WallTime now = ros::WallTime::now();
  const double elapsed = std::max(1e-6, (now - window_start_).toSec());
  if (table_source_.empty()) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR,
                 "no colour table" + (table_error_.empty() ? std::string(": set color_table or "
                                                                         "call ~calibrate")
                                                           : ": " + table_error_));
  } else if (window_dropped_ > 0) {
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::WARN, "%lu frames dropped",
                  static_cast<unsigned long>(window_dropped_));
  } else if (window_cap_hits_ > 0) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "region cap hit");
  } else if (window_frames_ == 0) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "no frames");
  } else {
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "segmenting");
  }
  stat.add("camera_id", camera_id_);
  stat.add("colour table", table_source_.empty() ? "none" : table_source_);
  if (!table_error_.empty()) stat.add("last table error", table_error_);
  stat.add("frame rate [Hz]", window_frames_ / elapsed);
  stat.add("processing time mean [ms]", window_frames_ ? window_ms_sum_ / window_frames_ : 0.0);
  stat.add("processing time max [ms]", window_ms_max_);
  for (int c = 1; c < kNumColorClasses; ++c) {
    if (window_regions_[c] == 0 && cap_hits_total_[c] == 0 && fringes_total_[c] == 0) continue;
    const std::string name(colorClassName(static_cast<ColorClass>(c)));
    stat.add("regions per frame " + name,
             window_frames_ ? static_cast<double>(window_regions_[c]) / window_frames_ : 0.0);
    if (cap_hits_total_[c]) stat.add("cap hits (total) " + name, cap_hits_total_[c]);
    if (fringes_total_[c]) stat.add("Bayer colour fringes dropped (total) " + name, fringes_total_[c]);
  }
  stat.add("frames processed", frames_processed_);
  stat.add("frames with search windows", windowed_frames_);
  stat.add("frames with a ball streak window", streak_frames_);
  stat.add("ball streak regions (orange from the streak table)", streak_regions_);
  stat.add("ball streak regions refused (not on the floor)", streak_refused_);
  stat.add("frames skipped by frame_step", skipped_by_frame_step_);
  stat.add("dropped: unsupported encoding", dropped_encoding_);
  if (!last_bad_encoding_.empty()) stat.add("last unsupported encoding", last_bad_encoding_);
  stat.add("dropped: empty/truncated image", dropped_bad_image_);
  stat.add("dropped: no colour table", dropped_no_table_);
  stat.add("dropped: segmentation error", dropped_error_);
  stat.add("illumination reference size mismatches", illumination_mismatch_);
  stat.add("~calibrate requests refused", calibrations_refused_);
  stat.add("online calibration", learning_enabled_ ? "on" : "off");
  if (learning_enabled_) {
    const OnlineCalibrationStatus& o = online_status_;
    std::string per_class;
    for (int c = 1; c < kNumColorClasses; ++c) {
      if (o.learned_cells[c] == 0) continue;
      per_class += (per_class.empty() ? "" : ", ") + std::string(colorClassName(static_cast<ColorClass>(c))) +
                   " " + std::to_string(o.learned_cells[c]);
    }
    stat.add("online: cells learned",
             std::to_string(o.learnedTotal()) + (per_class.empty() ? "" : " (" + per_class + ")"));
    stat.add("online: cells added / given back",
             std::to_string(o.cells_added) + " / " + std::to_string(o.cells_removed));
    stat.add("online: cells vetoed by the background (last update)", o.vetoed_cells);
    stat.add("online: cells beyond the calibrated colours (last update)", o.outside_envelope);
    stat.add("online: light moved from calibration [%]", 100.0 * o.level_deviation);
    stat.add("online: updates", o.updates);
    stat.add("online: updates that changed the model", o.models);
    stat.add("online: frames / confirmed markers learned from",
             std::to_string(o.frames) + " / " + std::to_string(o.markers));
    stat.add("online: confirmed markers too late (frame no longer kept)", confirmed_unmatched_);
    stat.add("online: errors", online_errors_);
    if (!online_error_.empty()) stat.add("online: last error", online_error_);
  }
  window_start_ = now;
  window_frames_ = 0;
  window_ms_sum_ = window_ms_max_ = 0;
  window_regions_.fill(0);
  window_cap_hits_ = 0;
  window_dropped_ = 0;
}

}  // namespace soccer_vision

PLUGINLIB_EXPORT_CLASS(soccer_vision::SegmentationNodelet, nodelet::Nodelet)
