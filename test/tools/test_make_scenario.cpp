// make_scenario end to end: the bag holds every topic with equal capture stamps, and the
// exchange files next to it agree with the bag and with the camera model.
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include "soccer_vision/BallPoseArray.h"
#include "soccer_vision/RobotPoseArray.h"
#include "soccer_vision/common/camera_model.h"
#include "soccer_vision/common/exchange_formats.h"
#include "soccer_vision/common/field_geometry.h"

using namespace soccer_vision;

namespace {
const std::string kDir = ::testing::TempDir() + "/make_scenario_test";
constexpr int kFrames = 6;

class MakeScenario : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    ASSERT_EQ(std::system(("rm -rf " + kDir + " && mkdir -p " + kDir).c_str()), 0);
    const std::string cmd = std::string(MAKE_SCENARIO_BIN) + " --preset " + SOCCER_VISION_SOURCE_DIR +
                            "/config/scenarios/uneven_drift.yaml --frames " + std::to_string(kFrames) +
                            " --width 640 --height 512 --cameras 0,1 --out " + kDir + "/s.bag";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  }
};
}  // namespace

TEST_F(MakeScenario, BagHasAllTopicsWithEqualStamps) {
  rosbag::Bag bag(kDir + "/s.bag", rosbag::bagmode::Read);
  std::map<std::string, std::vector<ros::Time>> stamps;
  rosbag::View view(bag);
  for (const auto& m : view) {
    ros::Time stamp;
    if (auto img = m.instantiate<sensor_msgs::Image>()) {
      EXPECT_EQ(img->width, 640u);
      EXPECT_EQ(img->height, 512u);
      EXPECT_EQ(img->encoding, "bgr8");
      EXPECT_EQ(img->data.size(), 640u * 512u * 3u);
      stamp = img->header.stamp;
    } else if (auto info = m.instantiate<sensor_msgs::CameraInfo>()) {
      EXPECT_EQ(info->distortion_model, "plumb_bob");
      stamp = info->header.stamp;
    } else if (auto robots = m.instantiate<RobotPoseArray>()) {
      EXPECT_EQ(robots->robots.size(), 10u);
      EXPECT_EQ(robots->header.frame_id, "field");
      stamp = robots->header.stamp;
    } else if (auto balls = m.instantiate<BallPoseArray>()) {
      EXPECT_EQ(balls->balls.size(), 1u);
      stamp = balls->header.stamp;
    } else {
      continue;
    }
    EXPECT_EQ(stamp, m.getTime()) << m.getTopic();
    stamps[m.getTopic()].push_back(stamp);
  }
  for (const std::string cam : {"/camera_0", "/camera_1"}) {
    for (const std::string topic :
         {"/image_raw", "/camera_info", "/ground_truth/robots", "/ground_truth/balls"}) {
      ASSERT_EQ(stamps[cam + topic].size(), static_cast<std::size_t>(kFrames)) << cam + topic;
      EXPECT_EQ(stamps[cam + topic], stamps["/camera_0/image_raw"]) << cam + topic;
    }
  }
  // 60 fps: consecutive stamps 1/60 s apart.
  const auto& s = stamps["/camera_0/image_raw"];
  for (std::size_t i = 1; i < s.size(); ++i) EXPECT_NEAR((s[i] - s[i - 1]).toSec(), 1.0 / 60, 1e-6);
}

TEST_F(MakeScenario, TruthFileAgreesWithTheBag) {
  const auto truth = readJsonLines(kDir + "/truth.jsonl");
  ASSERT_EQ(truth.size(), static_cast<std::size_t>(kFrames));
  rosbag::Bag bag(kDir + "/s.bag", rosbag::bagmode::Read);
  rosbag::View view(bag, rosbag::TopicQuery("/camera_1/ground_truth/robots"));
  std::size_t i = 0;
  int visible = 0;
  for (const auto& m : view) {
    const auto robots = m.instantiate<RobotPoseArray>();
    ASSERT_LT(i, truth.size());
    EXPECT_NEAR(truth[i].stamp, robots->header.stamp.toSec(), 1e-6);
    ASSERT_EQ(truth[i].robots.size(), robots->robots.size());
    for (std::size_t k = 0; k < robots->robots.size(); ++k) {
      EXPECT_NEAR(truth[i].robots[k].x, robots->robots[k].x, 1e-4);
      EXPECT_NEAR(truth[i].robots[k].y, robots->robots[k].y, 1e-4);
      ASSERT_TRUE(truth[i].robots[k].visible);
      // Visible in the truth file means seen by at least one camera.
      if (robots->robots[k].visible) {
        EXPECT_TRUE(*truth[i].robots[k].visible);
      }
      visible += *truth[i].robots[k].visible;
    }
    ++i;
  }
  EXPECT_EQ(i, truth.size());
  EXPECT_GE(visible, kFrames * 9);  // two cameras see (nearly) every robot
}

TEST_F(MakeScenario, SamplesAndFieldPointsMatchTheFirstFrame) {
  const auto samples = loadColorSamples(kDir + "/samples.yaml");
  for (auto c : {ColorClass::Blue, ColorClass::Yellow, ColorClass::Carpet, ColorClass::RobotTop}) {
    EXPECT_TRUE(samples.count(c)) << colorClassName(c);
  }
  const cv::Mat first = cv::imread(kDir + "/first_frame.png");
  ASSERT_EQ(first.cols, 640);
  // Team-colour sample polygons lie on team-coloured pixels: blue dominates at the centre.
  for (const auto& poly : samples.at(ColorClass::Blue)) {
    Eigen::Vector2d c(0, 0);
    for (const auto& p : poly) c += p / poly.size();
    const cv::Vec3b bgr =
        first.at<cv::Vec3b>(static_cast<int>(std::lround(c.y())), static_cast<int>(std::lround(c.x())));
    EXPECT_GT(bgr[0], bgr[2] + 40) << "pixel " << c.transpose();
  }
  const auto points = loadFieldCorrespondences(kDir + "/field_points.yaml");
  ASSERT_GE(points.size(), 4u);
  const auto camera = CameraModel::defaultCamera(FieldGeometry{}, 0, 640, 512);
  for (const auto& p : points) {
    EXPECT_LT((*camera.project(p.field) - p.pixel).norm(), 1e-6);
  }
  EXPECT_GE(loadFieldCorrespondences(kDir + "/field_points_camera_1.yaml").size(), 4u);
}

// --calibration-frame auto: a user calibrates on a frame that shows every colour. The
// chosen frame's samples hold every marker colour of the robots camera 0 shows during the
// recording, and calibration_frame.png is that frame (frame 0 here shows only some).
TEST(MakeScenarioCli, CalibrationFrameAutoShowsEveryColourInView) {
  const std::string dir = ::testing::TempDir() + "/make_scenario_calibration_frame";
  ASSERT_EQ(std::system(("rm -rf " + dir + " && mkdir -p " + dir).c_str()), 0);
  const std::string cmd =
      std::string(MAKE_SCENARIO_BIN) + " --preset " + SOCCER_VISION_SOURCE_DIR +
      "/config/scenarios/rand_wide_angle.yaml --seed 36 --frames 100 --width 640 --height 512 " +
      "--sample-inset 2 --calibration-frame auto --out " + dir + "/s.bag > " + dir + "/log.txt";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream log(dir + "/log.txt");
  std::string line, chosen;
  while (std::getline(log, line)) {
    if (line.rfind("camera 0: calibration frame: ", 0) == 0) chosen = line;
  }
  ASSERT_FALSE(chosen.empty());
  int frame = -1;
  std::size_t shown = 0, in_view = 0;
  ASSERT_EQ(std::sscanf(chosen.c_str(), "camera 0: calibration frame: %d (shows %zu of the %zu", &frame,
                        &shown, &in_view),
            3)
      << chosen;
  EXPECT_GT(frame, 0);  // frame 0 lacks a colour in this game
  EXPECT_EQ(shown, in_view);
  const auto samples = loadColorSamples(dir + "/samples.yaml");
  std::size_t marker_colours = 0;
  for (const auto& [c, polygons] : samples) marker_colours += isMarkerColor(c);
  EXPECT_EQ(marker_colours, in_view);
  EXPECT_EQ(cv::imread(dir + "/calibration_frame.png").cols, 640);
  // An index past the recording is refused.
  EXPECT_EQ(
      WEXITSTATUS(std::system((std::string(MAKE_SCENARIO_BIN) + " --preset uneven_drift --frames 3 --out " +
                               dir + "/t.bag --calibration-frame 3 > /dev/null 2>&1")
                                  .c_str())),
      2);
}

// Where no frame shows every colour (frame 0 of this game lacks pink, which only frame 40 on
// shows, without another; seed 45 since the user paints robots in view up to the border,
// 2026-12-07, when seed 38's game got a frame showing them all): the colours the calibration
// frame lacks are sampled on the first frame showing them, with the carpet, as a user paints
// them on a second frame (more_samples_<k>.yaml).
TEST(MakeScenarioCli, ColoursTheCalibrationFrameLacksAreSampledOnAnotherFrame) {
  const std::string dir = ::testing::TempDir() + "/make_scenario_more_samples";
  ASSERT_EQ(std::system(("rm -rf " + dir + " && mkdir -p " + dir).c_str()), 0);
  const std::string cmd = std::string(MAKE_SCENARIO_BIN) + " --preset " + SOCCER_VISION_SOURCE_DIR +
                          "/config/scenarios/rand_fast.yaml --seed 45 --frames 60 --width 640 --height 512 " +
                          "--sample-inset 2 --calibration-frame auto --out " + dir + "/s.bag > " + dir +
                          "/log.txt";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream log(dir + "/log.txt");
  std::string line;
  int frame = -1, more_frame = -1;
  std::size_t shown = 0, in_view = 0;
  char file[512] = {};
  while (std::getline(log, line)) {
    std::sscanf(line.c_str(), "camera 0: calibration frame: %d (shows %zu of the %zu", &frame, &shown,
                &in_view);
    std::sscanf(line.c_str(), "camera 0: more samples: frame %d (%*[^)]) in %511s", &more_frame, file);
  }
  ASSERT_GE(frame, 0);
  ASSERT_LT(shown, in_view) << "this game has no frame showing every colour";
  ASSERT_GT(more_frame, frame);
  EXPECT_EQ(std::string(file), dir + "/more_samples_1_camera_0.yaml");
  const auto first = loadColorSamples(dir + "/samples.yaml");
  const auto more = loadColorSamples(dir + "/more_samples_1.yaml");
  std::size_t added = 0;
  for (const auto& [c, polygons] : more) {
    EXPECT_FALSE(polygons.empty()) << colorClassName(c);
    if (!isMarkerColor(c)) {
      EXPECT_EQ(c, ColorClass::Carpet) << "besides the missing colours only the carpet";
      continue;
    }
    EXPECT_FALSE(first.count(c)) << colorClassName(c) << " is in the calibration frame already";
    ++added;
  }
  EXPECT_TRUE(more.count(ColorClass::Carpet));
  EXPECT_EQ(added, in_view - shown);
  EXPECT_EQ(loadColorSamples(dir + "/more_samples_1_camera_0.yaml"), more);
}

// The bag's writes fail (the device is full from the first byte): the tool says so and
// exits with status 2. A disk that fills during the run also fails while the bag is closed;
// that once aborted the tool (rosbag::Bag's destructor threw while the error unwound; status
// 134 on a 14 MB tmpfs, status 2 and "Problem writing data to disk" with OutputBag, checked
// by hand: a test cannot mount one).
TEST(MakeScenarioCli, AFullDiskFailsWithAMessage) {
  const std::string dir = "/tmp/soccer_vision_test_make_scenario_full";
  ASSERT_EQ(
      std::system(
          ("rm -rf " + dir + " && mkdir -p " + dir + " && ln -s /dev/full " + dir + "/scenario.bag").c_str()),
      0);
  const std::string cmd = std::string(MAKE_SCENARIO_BIN) + " --preset even_static --frames 5 --out " + dir +
                          "/scenario.bag > " + dir + "/log.txt 2>&1";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status)) << "ended by a signal: " << cmd;
  EXPECT_EQ(WEXITSTATUS(status), 2);
  std::ifstream log(dir + "/log.txt");
  const std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("make_scenario: "), std::string::npos) << text;
  EXPECT_EQ(text.find("terminate called"), std::string::npos) << text;
}

TEST(MakeScenarioCli, BadArgumentsFailWithStatus2) {
  const std::string bin = MAKE_SCENARIO_BIN;
  EXPECT_EQ(WEXITSTATUS(std::system((bin + " --frames 3 > /dev/null 2>&1").c_str())), 2);
  EXPECT_EQ(WEXITSTATUS(std::system(
                (bin + " --preset /nonexistent.yaml --frames 3 --out /tmp/x.bag > /dev/null 2>&1").c_str())),
            2);
  EXPECT_EQ(WEXITSTATUS(std::system(
                (bin + " --preset x.yaml --frames 3 --out /tmp/x.bag --cameras 2 > /dev/null 2>&1").c_str())),
            2);
}
