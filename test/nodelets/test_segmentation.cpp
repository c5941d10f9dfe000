// rostest for the Segmentation nodelet (test/nodelets/segmentation.test): one manager with the
// synthetic CameraDriver (even_static scene: nothing moves) and the Segmentation, started
// with a color_table file that does not exist. Run in the camera namespace; private
// parameters: ~dir (scratch directory for tables), ~width/~height (1280/1024), ~probe_ns
// (namespace of the zero-copy probe, "/probe").
//
// The tests run in order and build on each other (gtest keeps declaration order):
//  1. without a table, images flow and no blobs are published;
//  2. ~calibrate with samples computed from the ground truth (calibrationSamples; valid for
//     the latest frame because nothing moves) makes a table: blobs carry the image stamps
//     and frame, one team blob per visible robot of that team (± robots at the border),
//     centroids of team markers, role markers and the ball near their projections; the
//     lazy debug/classification image shows the classes;
//  3. ~calibrate without yellow samples swaps the table: yellow blobs disappear;
//     a failing ~calibrate keeps the table;
//     bad requests (NaN, huge, degenerate polygons, a class without cells, a save path
//     outside the allowed directory) are refused with their reason; a costly request does
//     not stop the blobs (it runs off the image queue); a request image (8x8, truncated)
//     is the one used;
//  4. dynamic_reconfigure color_table = a corrupt file keeps the table (blobs continue, still
//     no yellow); color_table = the saved full table brings yellow back;
//  5. a Segmentation started without its table (/late) loads it once it is whole, after a
//     read of it half written;
//  6. /diagnostics report the table, the frame rate and the processing time;
//  7. zero copy: the frame buffer address the probe CameraDriver published equals the address the
//     Segmentation of the same manager segmented.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/UInt64MultiArray.h>
#include <sys/stat.h>

#include "soccer_vision/BallPoseArray.h"
#include "soccer_vision/BlobArray.h"
#include "soccer_vision/Calibrate.h"
#include "soccer_vision/RobotPoseArray.h"
#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/exchange_formats.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/common/robot_pattern.h"
#include "soccer_vision/segmentation/color_table.h"
#include "soccer_vision/simulation/calibration_samples.h"
#include "soccer_vision/simulation/field_renderer.h"

namespace sv = soccer_vision;

namespace {

struct Recorder {
  std::mutex mutex;
  std::set<ros::Time> image_stamps;
  std::string image_frame;
  std::vector<soccer_vision::BlobArrayConstPtr> blobs;
  std::map<ros::Time, soccer_vision::RobotPoseArrayConstPtr> robots;
  std::map<ros::Time, soccer_vision::BallPoseArrayConstPtr> balls;
  std::vector<sensor_msgs::ImageConstPtr> debug;
  std::map<ros::Time, std::uint64_t> published_address, segmented_address;

  // Capture stamps from camera_info (same stamp and frame as each image, without moving
  // every frame through the test's socket).
  void image(const sensor_msgs::CameraInfoConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    image_stamps.insert(m->header.stamp);
    image_frame = m->header.frame_id;
  }
  void blobArray(const soccer_vision::BlobArrayConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    blobs.push_back(m);
  }
  void robotArray(const soccer_vision::RobotPoseArrayConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    robots[m->header.stamp] = m;
  }
  void ballArray(const soccer_vision::BallPoseArrayConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    balls[m->header.stamp] = m;
  }
  void debugImage(const sensor_msgs::ImageConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    debug.push_back(m);
  }
  static void address(std::map<ros::Time, std::uint64_t>& map, std::mutex& mutex,
                      const std_msgs::UInt64MultiArrayConstPtr& m) {
    if (m->data.size() != 3) return;
    std::lock_guard<std::mutex> l(mutex);
    map[ros::Time(static_cast<uint32_t>(m->data[0]), static_cast<uint32_t>(m->data[1]))] = m->data[2];
  }
};

int countColor(const soccer_vision::BlobArray& a, sv::ColorClass c) {
  return static_cast<int>(std::count_if(a.blobs.begin(), a.blobs.end(), [&](const auto& b) {
    return b.color == static_cast<std::uint8_t>(c);
  }));
}

class SegmentationTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    ros::NodeHandle pnh("~");
    pnh.param<std::string>("dir", dir_, "/tmp/soccer_vision_test_segmentation");
    pnh.param("width", width_, 1280);
    pnh.param("height", height_, 1024);
    pnh.param<std::string>("probe_ns", probe_ns_, "/probe");
    ASSERT_EQ(std::system(("rm -rf '" + dir_ + "' && mkdir -p '" + dir_ + "'").c_str()), 0);
    rec_ = new Recorder;
    ros::NodeHandle nh;
    subs_ = new std::vector<ros::Subscriber>;
    subs_->push_back(nh.subscribe("camera_info", 50, &Recorder::image, rec_));
    subs_->push_back(nh.subscribe("blobs", 50, &Recorder::blobArray, rec_));
    subs_->push_back(nh.subscribe("ground_truth/robots", 50, &Recorder::robotArray, rec_));
    subs_->push_back(nh.subscribe("ground_truth/balls", 50, &Recorder::ballArray, rec_));
    using AddressCallback = boost::function<void(const std_msgs::UInt64MultiArrayConstPtr&)>;
    subs_->push_back(nh.subscribe<std_msgs::UInt64MultiArray>(
        probe_ns_ + "/debug/published_address", 100,
        AddressCallback([](const std_msgs::UInt64MultiArrayConstPtr& m) {
          Recorder::address(rec_->published_address, rec_->mutex, m);
        })));
    subs_->push_back(nh.subscribe<std_msgs::UInt64MultiArray>(
        probe_ns_ + "/debug/image_data_address", 100,
        AddressCallback([](const std_msgs::UInt64MultiArrayConstPtr& m) {
          Recorder::address(rec_->segmented_address, rec_->mutex, m);
        })));
  }
  static void TearDownTestSuite() {
    delete subs_;
    delete rec_;
    EXPECT_EQ(std::system(("rm -rf '" + dir_ + "'").c_str()), 0);  // each run has its own directory
  }

  void SetUp() override { camera_ = sv::CameraModel::defaultCamera(field_, 0, width_, height_); }

  static std::size_t imageCount() {
    std::lock_guard<std::mutex> l(rec_->mutex);
    return rec_->image_stamps.size();
  }
  static void clearBlobs() {
    std::lock_guard<std::mutex> l(rec_->mutex);
    rec_->blobs.clear();
  }
  // Waits for n BlobArrays received after now (skipping `skip` first ones: frames in flight
  // during a change may still use the previous table).
  static std::vector<soccer_vision::BlobArrayConstPtr> collectBlobs(std::size_t n, std::size_t skip = 2,
                                                                    double timeout = 20.0) {
    clearBlobs();
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
    while (ros::WallTime::now() < deadline) {
      {
        std::lock_guard<std::mutex> l(rec_->mutex);
        if (rec_->blobs.size() >= n + skip) break;
      }
      ros::WallDuration(0.01).sleep();
    }
    std::lock_guard<std::mutex> l(rec_->mutex);
    if (rec_->blobs.size() <= skip) return {};
    return std::vector<soccer_vision::BlobArrayConstPtr>(rec_->blobs.begin() + skip, rec_->blobs.end());
  }

  // The scene from the latest ground truth (robots and balls of one stamp).
  static bool latestScene(sv::SceneState& scene) {
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(20.0);
    while (ros::WallTime::now() < deadline) {
      {
        std::lock_guard<std::mutex> l(rec_->mutex);
        for (auto it = rec_->robots.rbegin(); it != rec_->robots.rend(); ++it) {
          auto b = rec_->balls.find(it->first);
          if (b == rec_->balls.end()) continue;
          scene = sv::SceneState();
          for (const auto& r : it->second->robots) {
            sv::RobotState s;
            s.team = r.team == soccer_vision::RobotPose::TEAM_BLUE ? sv::Team::Blue : sv::Team::Yellow;
            s.id = r.id;
            s.x = r.x;
            s.y = r.y;
            s.theta = r.theta;
            scene.robots.push_back(s);
          }
          for (const auto& p : b->second->balls) {
            sv::BallState s;
            s.x = p.x;
            s.y = p.y;
            s.z = p.z;
            scene.balls.push_back(s);
          }
          return true;
        }
      }
      ros::WallDuration(0.05).sleep();
    }
    return false;
  }

  sv::ColorSamples samples(bool with_yellow = true) {
    sv::SceneState scene;
    EXPECT_TRUE(latestScene(scene)) << "no ground truth on ground_truth/robots + balls";
    // Polygons over 80 % of each marker (the default 60 % gives the red disc of the single
    // calibration frame ~13 pixels: too few to cover its noise, the disc then breaks up).
    sv::SampleOptions options;
    options.shrink = 0.8;
    sv::ColorSamples s = sv::calibrationSamples(scene, camera_, field_, pattern_, options);
    if (!with_yellow) s.erase(sv::ColorClass::Yellow);
    return s;
  }

  static soccer_vision::Calibrate::Response calibrate(const std::string& yaml, bool save,
                                                      const std::string& path, bool replace = true) {
    soccer_vision::Calibrate srv;
    srv.request.samples_yaml = yaml;
    srv.request.save = save;
    srv.request.path = path;
    srv.request.replace = replace;
    const std::string name = ros::names::resolve("segmentation/calibrate");
    EXPECT_TRUE(ros::service::waitForService(name, ros::Duration(20.0))) << name;
    EXPECT_TRUE(ros::service::call(name, srv)) << name;
    return srv.response;
  }

  static void setColorTable(const std::string& path) {
    dynamic_reconfigure::Reconfigure srv;
    dynamic_reconfigure::StrParameter p;
    p.name = "color_table";
    p.value = path;
    srv.request.config.strs.push_back(p);
    const std::string name = ros::names::resolve("segmentation/set_parameters");
    EXPECT_TRUE(ros::service::waitForService(name, ros::Duration(20.0))) << name;
    EXPECT_TRUE(ros::service::call(name, srv)) << name;
  }

  // Pixel of a marker's centre (marker plane) of robot r.
  std::optional<Eigen::Vector2d> markerPixel(const soccer_vision::RobotPose& r,
                                             const sv::MarkerShape& m) const {
    const double c = std::cos(r.theta), s = std::sin(r.theta);
    return camera_.project(
        Eigen::Vector3d(r.x + c * m.x - s * m.y, r.y + s * m.x + c * m.y, pattern_.robot_height));
  }

  // Blob arrays against the ground truth of their stamps (stamps, counts, centroids).
  void checkBlobs(const std::vector<soccer_vision::BlobArrayConstPtr>& arrays);

  static std::string dir_, probe_ns_;
  static int width_, height_;
  static Recorder* rec_;
  static std::vector<ros::Subscriber>* subs_;
  const sv::FieldGeometry field_;
  const sv::PatternSet pattern_ = sv::PatternSet::twoTag();
  sv::CameraModel camera_;
};

std::string SegmentationTest::dir_, SegmentationTest::probe_ns_;
int SegmentationTest::width_ = 1280, SegmentationTest::height_ = 1024;
Recorder* SegmentationTest::rec_ = nullptr;
std::vector<ros::Subscriber>* SegmentationTest::subs_ = nullptr;

TEST_F(SegmentationTest, NoTableDropsFrames) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(30.0);
  while (imageCount() < 5 && ros::WallTime::now() < deadline) ros::WallDuration(0.01).sleep();
  clearBlobs();
  const std::size_t before = imageCount();
  while (imageCount() < before + 15 && ros::WallTime::now() < deadline) ros::WallDuration(0.01).sleep();
  ASSERT_GE(imageCount(), before + 15) << "too few frames (camera_info)";
  std::lock_guard<std::mutex> l(rec_->mutex);
  EXPECT_TRUE(rec_->blobs.empty()) << "no colour table (missing file): frames must be dropped";
}

TEST_F(SegmentationTest, CalibratedBlobsMatchGroundTruth) {
  ros::NodeHandle nh;
  ros::Subscriber debug_sub = nh.subscribe("debug/classification", 5, &Recorder::debugImage, rec_);
  const soccer_vision::Calibrate::Response res = calibrate(sv::toYaml(samples()), true, dir_ + "/full.svct");
  ASSERT_TRUE(res.success) << res.message;
  std::printf("[ calibrate ] %s\n", res.message.c_str());
  EXPECT_NE(res.message.find("blue"), std::string::npos);
  EXPECT_EQ(res.message.find("clipped"), std::string::npos) << "no sample is saturated here";
  const sv::ColorTable saved = sv::ColorTable::load(dir_ + "/full.svct");
  EXPECT_GT(saved.statistics().classes[static_cast<int>(sv::ColorClass::Yellow)].valid, 0u);

  const auto arrays = collectBlobs(30);
  ASSERT_GE(arrays.size(), 30u) << "blobs must flow once a table exists";
  checkBlobs(arrays);

  // The lazily published classification image (subscribed above).
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(10.0);
  while (ros::WallTime::now() < deadline) {
    {
      std::lock_guard<std::mutex> l(rec_->mutex);
      if (!rec_->debug.empty()) break;
    }
    ros::WallDuration(0.01).sleep();
  }
  std::lock_guard<std::mutex> l(rec_->mutex);
  ASSERT_FALSE(rec_->debug.empty()) << "debug/classification while subscribed";
  const sensor_msgs::Image& dbg = *rec_->debug.back();
  EXPECT_EQ(dbg.encoding, "bgr8");
  ASSERT_EQ(static_cast<int>(dbg.width), width_);
  ASSERT_EQ(static_cast<int>(dbg.height), height_);
  EXPECT_EQ(rec_->image_stamps.count(dbg.header.stamp), 1u);
  auto rit = rec_->robots.rbegin();
  ASSERT_NE(rit, rec_->robots.rend());
  const cv::Vec3f albedo = sv::classAlbedo(sv::ColorClass::Blue);
  int shown = 0, visible = 0;
  for (const auto& r : rit->second->robots) {
    if (!r.visible || r.team != soccer_vision::RobotPose::TEAM_BLUE) continue;
    ++visible;
    const auto px = markerPixel(r, pattern_.team_marker);
    ASSERT_TRUE(px.has_value());
    const int u = static_cast<int>(std::lround(px->x())), v = static_cast<int>(std::lround(px->y()));
    const std::uint8_t* p = &dbg.data[static_cast<std::size_t>(v) * dbg.step + 3 * u];
    if (std::abs(p[0] - cv::saturate_cast<uchar>(albedo[0])) <= 1 &&
        std::abs(p[1] - cv::saturate_cast<uchar>(albedo[1])) <= 1 &&
        std::abs(p[2] - cv::saturate_cast<uchar>(albedo[2])) <= 1)
      ++shown;
  }
  EXPECT_GT(visible, 0);
  EXPECT_EQ(shown, visible) << "blue team markers drawn in blue on debug/classification";
}

void SegmentationTest::checkBlobs(const std::vector<soccer_vision::BlobArrayConstPtr>& arrays) {
  std::lock_guard<std::mutex> l(rec_->mutex);
  int frames_checked = 0, team_robots = 0, role_checked = 0, role_found = 0, balls = 0;
  double worst_team = 0, worst_role = 0, worst_ball = 0;
  std::string role_missing;
  for (const auto& a : arrays) {
    EXPECT_EQ(rec_->image_stamps.count(a->header.stamp), 1u)
        << "blob stamp " << a->header.stamp << " is no image's capture stamp";
    EXPECT_EQ(a->header.frame_id, "camera_0_optical");
    EXPECT_EQ(a->camera_id, 0);
    EXPECT_EQ(static_cast<int>(a->image_width), width_);
    EXPECT_EQ(static_cast<int>(a->image_height), height_);
    EXPECT_TRUE(a->global_search);
    EXPECT_EQ(a->cap_hits.size(), static_cast<std::size_t>(sv::kNumColorClasses));
    EXPECT_GT(a->processing_time, 0.0f);
    auto rit = rec_->robots.find(a->header.stamp);
    auto bit = rec_->balls.find(a->header.stamp);
    if (rit == rec_->robots.end() || bit == rec_->balls.end()) continue;
    ++frames_checked;
    for (sv::Team team : {sv::Team::Blue, sv::Team::Yellow}) {
      const sv::ColorClass color = sv::teamColor(team);
      int visible = 0, border = 0;
      for (const auto& r : rit->second->robots) {
        if ((r.team == soccer_vision::RobotPose::TEAM_BLUE) != (team == sv::Team::Blue)) continue;
        const auto markers = pattern_.markers(team, r.id);
        const auto px = markerPixel(r, markers.front().shape);
        if (!r.visible) {
          // Partly in the image: its team marker may or may not form a blob.
          if (px && px->x() > -20 && px->y() > -20 && px->x() < width_ + 20 && px->y() < height_ + 20)
            ++border;
          continue;
        }
        ++visible;
        ASSERT_TRUE(px.has_value());
        // Every marker of a visible robot: a blob of its colour at its projection.
        for (std::size_t k = 0; k < markers.size(); ++k) {
          const auto mp = markerPixel(r, markers[k].shape);
          double best = 1e9;
          for (const auto& b : a->blobs) {
            if (b.color != static_cast<std::uint8_t>(markers[k].color)) continue;
            best = std::min(best, std::hypot(b.cx - mp->x(), b.cy - mp->y()));
          }
          if (k == 0) {
            ++team_robots;
            worst_team = std::max(worst_team, best);
            EXPECT_LT(best, 1.0) << sv::colorClassName(color) << " robot " << int(r.id)
                                 << ": team blob centroid vs projected marker [px]";
          } else {
            ++role_checked;
            if (best < 1.5) {
              ++role_found;
            } else if (role_missing.size() < 400) {
              role_missing += std::string("\n  ") + std::string(sv::colorClassName(markers[k].color)) +
                              " of " + std::string(sv::colorClassName(color)) + " " + std::to_string(r.id) +
                              " at (" + std::to_string(mp->x()) + ", " + std::to_string(mp->y()) +
                              "): nearest " + std::to_string(best) + " px";
            }
            worst_role = std::max(worst_role, best);
          }
        }
      }
      const int blobs = countColor(*a, color);
      EXPECT_GE(blobs, visible) << sv::colorClassName(color) << " blobs at " << a->header.stamp;
      EXPECT_LE(blobs, visible + border) << sv::colorClassName(color) << " blobs at " << a->header.stamp
                                         << " (" << border << " robots at the border)";
    }
    for (const auto& ball : bit->second->balls) {
      if (!ball.visible) continue;
      const auto px = camera_.project(Eigen::Vector3d(ball.x, ball.y, ball.z));
      ASSERT_TRUE(px.has_value());
      double best = 1e9;
      for (const auto& b : a->blobs)
        if (b.color == static_cast<std::uint8_t>(sv::ColorClass::Orange))
          best = std::min(best, std::hypot(b.cx - px->x(), b.cy - px->y()));
      ++balls;
      worst_ball = std::max(worst_ball, best);
      EXPECT_LT(best, 2.0) << "ball blob centroid vs projected ball centre [px]";
    }
  }
  std::printf(
      "[ blobs ] %d frames with ground truth: %d team markers (worst %.3f px), "
      "%d of %d role markers within 1.5 px (worst %.3f px), %d balls (worst %.3f px)\n",
      frames_checked, team_robots, worst_team, role_found, role_checked, worst_role, balls, worst_ball);
  EXPECT_GE(frames_checked, 20) << "ground truth must come with the frames";
  EXPECT_GE(team_robots, 2 * frames_checked) << "too few robots in view to test anything";
  EXPECT_EQ(role_found, role_checked)
      << "every role marker of a visible robot needs its blob:" << role_missing;
}

TEST_F(SegmentationTest, CalibrateSwapsTable) {
  // Samples without yellow, merged (replace: false): yellow keeps its cells of the current
  // table, and its blobs stay.
  soccer_vision::Calibrate::Response res =
      calibrate(sv::toYaml(samples(false)), true, dir_ + "/yellow_kept.svct", false);
  ASSERT_TRUE(res.success) << res.message;
  const sv::ColorTable kept_table = sv::ColorTable::load(dir_ + "/yellow_kept.svct");
  const auto& kept = kept_table.statistics().classes[static_cast<int>(sv::ColorClass::Yellow)];
  EXPECT_GT(kept.samples, 0u) << "yellow's statistics come from the previous table";
  EXPECT_GT(kept.cells_assigned, 0u);
  auto kept_arrays = collectBlobs(15);
  ASSERT_GE(kept_arrays.size(), 15u);
  int yellow_blobs = 0;
  for (const auto& a : kept_arrays) yellow_blobs += countColor(*a, sv::ColorClass::Yellow);
  EXPECT_GT(yellow_blobs, 0) << "yellow blobs must stay when yellow was not painted";

  // The same samples with replace: a table without yellow, no yellow blobs any more, blue ones stay.
  res = calibrate(sv::toYaml(samples(false)), true, dir_ + "/no_yellow.svct");
  ASSERT_TRUE(res.success) << res.message;
  EXPECT_EQ(sv::ColorTable::load(dir_ + "/no_yellow.svct")
                .statistics()
                .classes[static_cast<int>(sv::ColorClass::Yellow)]
                .samples,
            0u);
  auto arrays = collectBlobs(15);
  ASSERT_GE(arrays.size(), 15u);
  for (const auto& a : arrays) {
    EXPECT_EQ(countColor(*a, sv::ColorClass::Yellow), 0) << "yellow blobs without yellow samples";
    EXPECT_GT(countColor(*a, sv::ColorClass::Blue), 0);
  }

  // A failing calibration (bad YAML, unknown class, polygons off the image) keeps the table.
  for (const std::string& bad :
       {std::string("pink: [[[1, 2], [3"), std::string("magenta:\n  - [[1, 1], [5, 1], [5, 5]]\n"),
        std::string("blue:\n  - [[-50, -50], [-40, -50], [-40, -40]]\n")}) {
    res = calibrate(bad, false, "");
    EXPECT_FALSE(res.success) << bad;
    EXPECT_FALSE(res.message.empty());
    std::printf("[ calibrate failure ] %s\n", res.message.c_str());
  }
  // The request's image, when given, is the frame calibrated on (the calibration UI's frozen
  // frame): polygons beyond an 8x8 image select nothing of it; a truncated one is refused.
  {
    soccer_vision::Calibrate srv;
    srv.request.samples_yaml = "blue:\n  - [[20, 20], [30, 20], [30, 30]]\n";
    srv.request.image.width = srv.request.image.height = 8;
    srv.request.image.encoding = "bgr8";
    srv.request.image.step = 24;
    srv.request.image.data.assign(24 * 8, 128);
    ASSERT_TRUE(ros::service::call(ros::names::resolve("segmentation/calibrate"), srv));
    EXPECT_FALSE(srv.response.success);
    EXPECT_NE(srv.response.message.find("(8x8)"), std::string::npos) << srv.response.message;
    srv.request.image.data.resize(24 * 7);
    ASSERT_TRUE(ros::service::call(ros::names::resolve("segmentation/calibrate"), srv));
    EXPECT_FALSE(srv.response.success);
    EXPECT_NE(srv.response.message.find("truncated"), std::string::npos) << srv.response.message;
  }
  // Save to a directory that does not exist: failure, nothing swapped.
  res = calibrate(sv::toYaml(samples()), true, dir_ + "/no/such/dir/t.svct");
  EXPECT_FALSE(res.success) << "saving to a missing directory must fail";
  arrays = collectBlobs(10);
  ASSERT_GE(arrays.size(), 10u) << "blobs continue after failed calibrations";
  for (const auto& a : arrays) EXPECT_EQ(countColor(*a, sv::ColorClass::Yellow), 0);

  // Yellow (and a carpet stroke) alone on a later frame, merged: the calibration UI's second
  // frame for a colour the first did not show. Calibrated together with the frame before
  // (the carpet's samples are both frames'), yellow is seen again and blue stays.
  const auto carpetSamples = [](const std::string& path) {
    return sv::ColorTable::load(path).statistics().classes[static_cast<int>(sv::ColorClass::Carpet)].samples;
  };
  sv::ColorSamples yellow = samples();
  for (auto it = yellow.begin(); it != yellow.end();) {
    const bool keep = it->first == sv::ColorClass::Yellow || it->first == sv::ColorClass::Carpet;
    it = keep ? std::next(it) : yellow.erase(it);
  }
  ASSERT_EQ(yellow.size(), 2u) << "yellow and the carpet in view";
  collectBlobs(3);  // a later frame than the one calibrated on
  res = calibrate(sv::toYaml(yellow), true, dir_ + "/yellow_added.svct", false);
  ASSERT_TRUE(res.success) << res.message;
  EXPECT_GT(carpetSamples(dir_ + "/yellow_added.svct"), carpetSamples(dir_ + "/no_yellow.svct"))
      << "the merge is calibrated on both frames";
  arrays = collectBlobs(15);
  ASSERT_GE(arrays.size(), 15u);
  int yellow_added = 0, blue_kept = 0;
  for (const auto& a : arrays) {
    yellow_added += countColor(*a, sv::ColorClass::Yellow) > 0;
    blue_kept += countColor(*a, sv::ColorClass::Blue) > 0;
  }
  EXPECT_GE(yellow_added, 0.8 * arrays.size()) << "frames with yellow blobs (robots may leave the view)";
  EXPECT_EQ(blue_kept, static_cast<int>(arrays.size())) << "frames with blue blobs";
  // A Bayer frame is calibrated on its quads' colours, what the classifier reads (as
  // evaluate and the synthetic calibration do), not on a demosaic: every quad of this
  // mosaic reads (R 200, G (70 + 130) / 2, B 30), which a demosaic spreads to G 70..130 at
  // its green sites. One colour: orange's hue variance is the quantisation's floor.
  {
    soccer_vision::Calibrate srv;
    srv.request.samples_yaml = "orange:\n  - [[0, 0], [64, 0], [64, 64], [0, 64]]\n";
    srv.request.save = true;
    srv.request.replace = true;
    srv.request.path = dir_ + "/bayer_quads.svct";
    sensor_msgs::Image& mosaic = srv.request.image;
    mosaic.width = mosaic.height = 64;
    mosaic.encoding = "bayer_rggb8";
    mosaic.step = 64;
    mosaic.data.resize(64 * 64);
    for (int y = 0; y < 64; ++y) {
      for (int x = 0; x < 64; ++x) {
        mosaic.data[y * 64 + x] = y % 2 == 0 ? (x % 2 == 0 ? 200 : 70) : (x % 2 == 0 ? 130 : 30);
      }
    }
    ASSERT_TRUE(ros::service::call(ros::names::resolve("segmentation/calibrate"), srv));
    ASSERT_TRUE(srv.response.success) << srv.response.message;
    const sv::ColorTable quads = sv::ColorTable::load(dir_ + "/bayer_quads.svct");
    const auto& orange = quads.statistics().classes[static_cast<int>(sv::ColorClass::Orange)];
    EXPECT_EQ(orange.samples, 64u * 64u);
    EXPECT_LT(orange.var_h, 2.0) << "hue variance of the samples: a demosaic's spread";
    EXPECT_EQ(quads.classify(30, 100, 200), sv::ColorClass::Orange);
  }
  // Yellow sampled only saturated (red and green at the ceiling, as under the brightest lamp
  // of held-out seed 9043) beside an unsaturated orange: calibrated, and the answer, which
  // the calibration UI shows, warns of yellow.
  {
    soccer_vision::Calibrate srv;
    srv.request.samples_yaml =
        "yellow:\n  - [[2, 2], [13, 2], [13, 13], [2, 13]]\norange:\n  - [[18, 2], [29, 2], [29, 13], [18, "
        "13]]\n";
    srv.request.replace = true;
    sensor_msgs::Image& image = srv.request.image;
    image.width = 32;
    image.height = 16;
    image.encoding = "bgr8";
    image.step = 96;
    image.data.resize(96 * 16);
    for (int y = 0; y < 16; ++y) {
      for (int x = 0; x < 32; ++x) {
        const std::array<std::uint8_t, 3> bgr =
            x < 16 ? std::array<std::uint8_t, 3>{58, 255, 255} : std::array<std::uint8_t, 3>{14, 161, 255};
        std::copy(bgr.begin(), bgr.end(), image.data.begin() + y * 96 + x * 3);
      }
    }
    ASSERT_TRUE(ros::service::call(ros::names::resolve("segmentation/calibrate"), srv));
    ASSERT_TRUE(srv.response.success) << srv.response.message;
    EXPECT_NE(srv.response.message.find("warning: most sample pixels of yellow are clipped"),
              std::string::npos)
        << srv.response.message;
    // And of the colours the pattern (two_tag, the default) puts on robots that this table,
    // calibrated on yellow and orange alone, has no cell for.
    EXPECT_NE(srv.response.message.find("warning: the table has no blue, pink, purple, sky_blue, green, red, "
                                        "which pattern two_tag puts on robots (ids 0, 1, 2, 3, 4)"),
              std::string::npos)
        << srv.response.message;
  }
  // Back to the table without yellow, which the next test expects.
  ASSERT_TRUE(calibrate(sv::toYaml(samples(false)), false, "").success);
}

// Requests that once crashed or stalled the manager, or wrote anywhere: each refused with
// its reason, the previous table (no yellow) stays, blobs continue.
TEST_F(SegmentationTest, BadCalibrateRequestsAreRefusedWithTheirReason) {
  std::string many = "pink:\n  - [";
  for (std::size_t i = 0; i <= sv::kMaxPolygonVertices; ++i) {
    const double a = 2 * M_PI * i / (sv::kMaxPolygonVertices + 1);
    many += (i ? ", [" : "[") + std::to_string(600 + 50 * std::cos(a)) + ", " +
            std::to_string(500 + 50 * std::sin(a)) + "]";
  }
  many += "]\n";
  // Two robot marker classes sampled on the same pixels (the same brightness variants too):
  // the Bayes decisions give every cell to one.
  sv::ColorSamples twins = samples();
  twins[sv::ColorClass::Purple] = twins.at(sv::ColorClass::Pink);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"pink:\n  - [[600, 500], [.nan, 500], [610, 510]]\n", "finite"},
      {"pink:\n  - [[600, 500], [1e300, 500], [610, 510]]\n", "finite pixel coordinate within"},
      {many, "vertices, needs 3.."},
      {"pink:\n  - [[600, 500], [605, 505], [610, 510]]\n", "no area"},
      {sv::toYaml(twins), "has no cell for"},
  };
  for (const auto& [yaml, reason] : cases) {
    const soccer_vision::Calibrate::Response res = calibrate(yaml, false, "");
    EXPECT_FALSE(res.success) << reason;
    EXPECT_NE(res.message.find(reason), std::string::npos) << res.message.substr(0, 300);
    std::printf("[ calibrate refused ] %s\n", res.message.substr(0, 200).c_str());
  }
  // Saving: only inside the directory of color_table (dir_); the first path begins with dir_'s
  // name, so a check on the string's prefix would let it through.
  const std::string outside = dir_ + "_outside.svct";
  std::remove(outside.c_str());
  for (const std::string& path : {outside, std::string("../outside.svct"), dir_ + "/../outside.svct"}) {
    const soccer_vision::Calibrate::Response res = calibrate(sv::toYaml(samples()), true, path);
    EXPECT_FALSE(res.success) << path;
    EXPECT_TRUE(res.message.find("outside the allowed directory") != std::string::npos ||
                res.message.find("'..' is not allowed") != std::string::npos)
        << res.message;
  }
  struct stat st;
  EXPECT_NE(stat(outside.c_str(), &st), 0) << "nothing may be written outside the allowed directory";
  const auto arrays = collectBlobs(10);
  ASSERT_GE(arrays.size(), 10u) << "blobs continue after refused calibrations";
  for (const auto& a : arrays)
    EXPECT_EQ(countColor(*a, sv::ColorClass::Yellow), 0) << "the previous table stays";
}

// ~calibrate runs off the image queue: a costly request (999 polygons over the whole frame,
// then refused for a class off the image) does not stop the blobs meanwhile.
TEST_F(SegmentationTest, CalibrationDoesNotStallTheFrames) {
  std::string yaml = "pink:\n";
  const std::string whole = "  - [[-1, -1], [" + std::to_string(width_) + ", -1], [" +
                            std::to_string(width_) + ", " + std::to_string(height_) + "], [-1, " +
                            std::to_string(height_) + "]]\n";
  for (std::size_t i = 0; i + 1 < sv::kMaxSamplePolygons; ++i) yaml += whole;
  yaml += "blue:\n  - [[-50, -50], [-40, -50], [-40, -40]]\n";
  clearBlobs();
  const ros::WallTime start = ros::WallTime::now();
  const soccer_vision::Calibrate::Response res = calibrate(yaml, false, "");
  const double seconds = (ros::WallTime::now() - start).toSec();
  std::size_t during = 0;
  {
    std::lock_guard<std::mutex> l(rec_->mutex);
    during = rec_->blobs.size();
  }
  EXPECT_FALSE(res.success);
  EXPECT_NE(res.message.find("select no pixel"), std::string::npos) << res.message;
  std::printf(
      "[ calibrate off the frame path ] the request took %.2f s, %zu blob arrays meanwhile (%.1f Hz)\n",
      seconds, during, during / seconds);
  ASSERT_GT(seconds, 0.5) << "the request must be costly for this test to mean something";
  // The camera runs at 30 Hz; half of that leaves room for a loaded machine.
  EXPECT_GE(static_cast<double>(during), 15.0 * (seconds - 0.3));
}

TEST_F(SegmentationTest, CorruptColorTableKeepsPrevious) {
  const std::string bad = dir_ + "/corrupt.svct";
  {
    std::ofstream f(bad, std::ios::binary);
    f << "this is not a colour table, just garbage \x01\x02\x03";
    for (int i = 0; i < 1000; ++i) f.put(static_cast<char>(i * 37));
  }
  setColorTable(bad);
  ros::WallDuration(1.0).sleep();  // the load happens in the background
  auto arrays = collectBlobs(15);
  ASSERT_GE(arrays.size(), 15u) << "a corrupt color_table must not stop the blobs";
  for (const auto& a : arrays) {
    EXPECT_EQ(countColor(*a, sv::ColorClass::Yellow), 0) << "the previous table stays";
    EXPECT_GT(countColor(*a, sv::ColorClass::Blue), 0);
  }

  // The saved full table, loaded from the file: yellow is back.
  setColorTable(dir_ + "/full.svct");
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(15.0);
  bool yellow = false;
  while (!yellow && ros::WallTime::now() < deadline) {
    arrays = collectBlobs(3, 0);
    for (const auto& a : arrays) yellow = yellow || countColor(*a, sv::ColorClass::Yellow) > 0;
  }
  EXPECT_TRUE(yellow) << "color_table = the saved full table must bring yellow blobs back";
  arrays = collectBlobs(10);
  ASSERT_GE(arrays.size(), 10u);
  for (const auto& a : arrays) EXPECT_GT(countColor(*a, sv::ColorClass::Yellow), 0);
}

// A table still being written when it is first read (most likely why a CI run of the
// four-camera demo had a camera without detections for 140 s): the Segmentation in /late started without its
// file; half of the file is written, then, 2.5 s later, the rest. Without a table a file that fails to load
// is tried again every second, so the whole one is loaded and blobs follow.
TEST_F(SegmentationTest, ATableReadHalfWrittenIsLoadedOnceWhole) {
  const std::string table = sv::readTextFile(dir_ + "/full.svct");
  ASSERT_GT(table.size(), 1000u);
  std::atomic<int> late_blobs{0};
  ros::NodeHandle nh;
  const ros::Subscriber sub = nh.subscribe<soccer_vision::BlobArray>(
      "/late/blobs", 10, [&](const soccer_vision::BlobArrayConstPtr&) { ++late_blobs; });
  const std::string path = dir_ + "/late.svct";
  {
    std::ofstream f(path, std::ios::binary);
    f.write(table.data(), static_cast<std::streamsize>(table.size() / 2));
  }
  ros::WallDuration(2.5).sleep();  // read at least twice meanwhile, and refused
  EXPECT_EQ(late_blobs.load(), 0) << "half a table must not be used";
  {
    std::ofstream f(path, std::ios::binary | std::ios::app);
    f.write(table.data() + table.size() / 2, static_cast<std::streamsize>(table.size() - table.size() / 2));
  }
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(15.0);
  while (late_blobs < 5 && ros::WallTime::now() < deadline) ros::WallDuration(0.05).sleep();
  EXPECT_GE(late_blobs.load(), 5) << "the table, whole now, was never loaded";
}

// /diagnostics of the Segmentation: OK with the table loaded last, its rate and timing.
TEST_F(SegmentationTest, Diagnostics) {
  std::mutex m;
  diagnostic_msgs::DiagnosticStatus found;
  bool have = false;
  // diagnostic_updater names a task "<node name without the leading slash>: <task>".
  const std::string name = ros::names::resolve("segmentation").substr(1) + ": segmentation";
  ros::NodeHandle nh;
  ros::Subscriber sub = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 20,
      boost::function<void(const diagnostic_msgs::DiagnosticArrayConstPtr&)>(
          [&](const diagnostic_msgs::DiagnosticArrayConstPtr& a) {
            for (const auto& st : a->status) {
              if (st.name != name) continue;
              std::lock_guard<std::mutex> l(m);
              found = st;
              have = true;
            }
          }));
  // Skip the first report: its window may include the change of table.
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(10.0);
  int reports = 0;
  while (ros::WallTime::now() < deadline && reports < 2) {
    {
      std::lock_guard<std::mutex> l(m);
      if (have) {
        have = false;
        ++reports;
      }
    }
    ros::WallDuration(0.01).sleep();
  }
  ASSERT_EQ(reports, 2) << "no diagnostics named '" << name << "'";
  std::lock_guard<std::mutex> l(m);
  std::map<std::string, std::string> values;
  for (const auto& kv : found.values) values[kv.key] = kv.value;
  EXPECT_EQ(found.level, diagnostic_msgs::DiagnosticStatus::OK) << found.message;
  EXPECT_EQ(values["colour table"], "file " + dir_ + "/full.svct");
  EXPECT_NEAR(std::stod(values["frame rate [Hz]"]), 30.0, 8.0);
  const double mean_ms = std::stod(values["processing time mean [ms]"]);
  EXPECT_GT(mean_ms, 0.0);
  EXPECT_GE(std::stod(values["processing time max [ms]"]), mean_ms);
  EXPECT_GT(std::stod(values["regions per frame blue"]), 0.0);
  EXPECT_GE(std::stoul(values["~calibrate requests refused"]), 12u)
      << "the refused requests of the tests before";
  std::printf("[ diagnostics ] %s: %.1f Hz, %.2f ms mean, %.2f ms max per frame\n", found.message.c_str(),
              std::stod(values["frame rate [Hz]"]), mean_ms, std::stod(values["processing time max [ms]"]));
}

TEST_F(SegmentationTest, ZeroCopyInOneManager) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(30.0);
  int matched = 0, equal = 0;
  while (ros::WallTime::now() < deadline) {
    {
      std::lock_guard<std::mutex> l(rec_->mutex);
      matched = equal = 0;
      for (const auto& [stamp, address] : rec_->segmented_address) {
        auto it = rec_->published_address.find(stamp);
        if (it == rec_->published_address.end()) continue;
        ++matched;
        if (it->second == address) ++equal;
      }
    }
    if (matched >= 20) break;
    ros::WallDuration(0.05).sleep();
  }
  std::printf("[ zero copy ] %d of %d frames segmented from the published buffer\n", equal, matched);
  ASSERT_GE(matched, 20) << "too few address reports from " << probe_ns_;
  EXPECT_EQ(equal, matched) << "the Segmentation must see the publisher's buffer, not a copy";
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_segmentation");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int result = RUN_ALL_TESTS();
  spinner.stop();
  ros::shutdown();
  return result;
}
