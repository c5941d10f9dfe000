// rostest for the CameraDriver with real sources (test/nodelets/camera_sources.test): the
// `images` source on PNGs this test writes (after the driver has started on an empty folder,
// so that its open-retry path runs), and the `v4l2` source on a missing device.
// Private parameter ~dir: the folder the images driver reads.
//
// Tests run in declaration order:
//  1. the v4l2 driver on /dev/video99 reports the missing device in /diagnostics (ERROR,
//     naming the device) and keeps retrying without crashing;
//  2. once the images exist (a folder renamed into place), camera_0 publishes them in file order, looping,
//  bgr8 64x48,
//     with strictly increasing stamps 1/20 s apart and camera_info of the same stamps;
//  3. zero copy: the driver's published buffer address equals the address the Segmentation
//     of the same manager received, for the same stamps;
//  4. fps 40 through dynamic_reconfigure halves the stamp interval;
//  5. the v4l2 driver is still retrying (diagnostics keep coming), the manager is alive.
#include <algorithm>
#include <cstdio>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/UInt64MultiArray.h>
#include <sys/stat.h>

#include "soccer_vision/common/statistics.h"

namespace {

constexpr int kFrames = 10, kWidth = 64, kHeight = 48;

cv::Mat indexedFrame(int index) {
  cv::Mat m(kHeight, kWidth, CV_8UC3, cv::Scalar(90, 120, 150));
  for (int b = 0; b < 8; ++b)
    m(cv::Rect(b * 8, 0, 8, 8)).setTo((index >> b) & 1 ? cv::Scalar::all(255) : cv::Scalar::all(0));
  return m;
}

int decodeIndex(const sensor_msgs::Image& image) {
  int index = 0;
  for (int b = 0; b < 8; ++b) {
    const std::uint8_t* p = &image.data[4 * image.step + (b * 8 + 4) * 3];
    if ((p[0] + p[1] + p[2]) / 3 > 128) index |= 1 << b;
  }
  return index;
}

struct Recorder {
  std::mutex mutex;
  std::vector<std::pair<ros::Time, int>> frames;  // stamp, decoded index
  std::vector<std::string> encodings;
  std::vector<std::pair<int, int>> sizes;
  std::vector<ros::Time> info_stamps;
  std::map<ros::Time, std::uint64_t> published, received;
  std::vector<diagnostic_msgs::DiagnosticStatus> diagnostics;

  void image(const sensor_msgs::ImageConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    frames.emplace_back(m->header.stamp, decodeIndex(*m));
    encodings.push_back(m->encoding);
    sizes.emplace_back(m->width, m->height);
  }
  void info(const sensor_msgs::CameraInfoConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    info_stamps.push_back(m->header.stamp);
  }
  void diag(const diagnostic_msgs::DiagnosticArrayConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    for (const auto& s : m->status) diagnostics.push_back(s);
  }
  static void address(std::map<ros::Time, std::uint64_t>& map, std::mutex& mutex,
                      const std_msgs::UInt64MultiArrayConstPtr& m) {
    if (m->data.size() != 3) return;
    std::lock_guard<std::mutex> l(mutex);
    map[ros::Time(static_cast<uint32_t>(m->data[0]), static_cast<uint32_t>(m->data[1]))] = m->data[2];
  }
};

Recorder* rec = nullptr;
std::vector<ros::Subscriber>* subs = nullptr;
std::string dir;

template <typename Pred>
bool waitFor(Pred pred, double seconds) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::WallTime::now() < deadline) {
    {
      std::lock_guard<std::mutex> l(rec->mutex);
      if (pred()) return true;
    }
    ros::WallDuration(0.02).sleep();
  }
  std::lock_guard<std::mutex> l(rec->mutex);
  return pred();
}

double medianInterval(const std::vector<std::pair<ros::Time, int>>& frames) {
  std::vector<double> d;
  for (std::size_t i = 1; i < frames.size(); ++i)
    d.push_back((frames[i].first - frames[i - 1].first).toSec());
  return d.empty() ? 0 : soccer_vision::percentile(d, 50);
}

// The latest status of camera_1's source (name contains "camera_1" and "source").
bool v4l2Status(diagnostic_msgs::DiagnosticStatus& out) {
  for (auto it = rec->diagnostics.rbegin(); it != rec->diagnostics.rend(); ++it)
    if (it->name.find("camera_1") != std::string::npos && it->name.find("source") != std::string::npos) {
      out = *it;
      return true;
    }
  return false;
}

}  // namespace

TEST(CameraSources, MissingV4l2DeviceIsReportedAndRetried) {
  diagnostic_msgs::DiagnosticStatus status;
  ASSERT_TRUE(waitFor([&] { return v4l2Status(status); }, 30)) << "no diagnostics of camera_1";
  EXPECT_EQ(status.level, diagnostic_msgs::DiagnosticStatus::ERROR);
  EXPECT_NE(status.message.find("/dev/video99"), std::string::npos) << status.message;
  EXPECT_NE(status.message.find("No such file"), std::string::npos) << status.message;
}

TEST(CameraSources, ImagesInOrderLoopingAtTheRate) {
  // The driver has been retrying on a missing folder; now all images appear at once
  // (written elsewhere, then the folder renamed, so the driver never sees a partial set).
  const std::string staging = dir + "/staging";
  ASSERT_EQ(::mkdir(staging.c_str(), 0755), 0);
  for (int i = 0; i < kFrames; ++i) {
    char name[64];
    std::snprintf(name, sizeof name, "/frame_%03d.png", i);
    ASSERT_TRUE(cv::imwrite(staging + name, indexedFrame(i)));
  }
  ASSERT_EQ(std::rename(staging.c_str(), (dir + "/frames").c_str()), 0);
  ASSERT_TRUE(waitFor([] { return rec->frames.size() >= 2 * kFrames + 5; }, 30))
      << "only " << rec->frames.size() << " frames";
  std::lock_guard<std::mutex> l(rec->mutex);
  // Frames in file order, looping (a frame may be lost by the socket queue: then the next
  // index must still be the successor modulo the count, at most 2 steps on).
  int missing = 0;
  for (std::size_t i = 1; i < rec->frames.size(); ++i) {
    const int step = (rec->frames[i].second - rec->frames[i - 1].second + kFrames) % kFrames;
    EXPECT_GE(step, 1) << "at " << i;
    EXPECT_LE(step, 2) << "at " << i;
    missing += step - 1;
    EXPECT_GT(rec->frames[i].first, rec->frames[i - 1].first) << "stamps not increasing at " << i;
  }
  EXPECT_LE(missing, 2);
  for (const auto& f : rec->frames) EXPECT_LT(f.second, kFrames);
  EXPECT_NEAR(medianInterval(rec->frames), 0.05, 1e-3);
  for (const std::string& e : rec->encodings) EXPECT_EQ(e, "bgr8");
  for (const auto& s : rec->sizes) EXPECT_EQ(s, std::make_pair(kWidth, kHeight));
  std::size_t matched = 0;
  for (const auto& f : rec->frames)
    matched += std::count(rec->info_stamps.begin(), rec->info_stamps.end(), f.first) > 0;
  EXPECT_GE(matched, rec->frames.size() - 1);  // the last info may still be on its way
}

TEST(CameraSources, ZeroCopyIntoTheSegmentation) {
  ASSERT_TRUE(waitFor(
      [] {
        int both = 0;
        for (const auto& kv : rec->published) both += rec->received.count(kv.first) > 0;
        return both >= 10;
      },
      20));
  std::lock_guard<std::mutex> l(rec->mutex);
  int same = 0, compared = 0;
  for (const auto& [stamp, address] : rec->published) {
    auto it = rec->received.find(stamp);
    if (it == rec->received.end()) continue;
    ++compared;
    same += it->second == address;
    EXPECT_NE(address, 0u);
  }
  EXPECT_GE(compared, 10);
  EXPECT_EQ(same, compared) << "the Segmentation got copies";
}

TEST(CameraSources, FpsThroughDynamicReconfigure) {
  dynamic_reconfigure::Reconfigure srv;
  dynamic_reconfigure::DoubleParameter p;
  p.name = "fps";
  p.value = 40.0;
  srv.request.config.doubles.push_back(p);
  ASSERT_TRUE(ros::service::waitForService("/camera_0/camera_driver/set_parameters", 10000));
  ASSERT_TRUE(ros::service::call("/camera_0/camera_driver/set_parameters", srv));
  ros::WallDuration(0.3).sleep();
  {
    std::lock_guard<std::mutex> l(rec->mutex);
    rec->frames.clear();
  }
  ASSERT_TRUE(waitFor([] { return rec->frames.size() >= 15; }, 20));
  std::lock_guard<std::mutex> l(rec->mutex);
  EXPECT_NEAR(medianInterval(rec->frames), 0.025, 1e-3);
}

TEST(CameraSources, V4l2DriverStillRetryingManagerAlive) {
  {
    std::lock_guard<std::mutex> l(rec->mutex);
    rec->diagnostics.clear();
    rec->frames.clear();
  }
  diagnostic_msgs::DiagnosticStatus status;
  ASSERT_TRUE(waitFor([&] { return v4l2Status(status) && rec->frames.size() >= 5; }, 20));
  EXPECT_EQ(status.level, diagnostic_msgs::DiagnosticStatus::ERROR);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_camera_sources");
  ros::NodeHandle nh, pnh("~");
  pnh.param<std::string>("dir", dir, "/tmp/soccer_vision_test_camera_sources");
  if (std::system(("rm -rf '" + dir + "' && mkdir -p '" + dir + "'").c_str()) != 0) return 1;
  rec = new Recorder;
  subs = new std::vector<ros::Subscriber>;
  subs->push_back(nh.subscribe("/camera_0/image_raw", 100, &Recorder::image, rec));
  subs->push_back(nh.subscribe("/camera_0/camera_info", 100, &Recorder::info, rec));
  subs->push_back(nh.subscribe("/diagnostics", 100, &Recorder::diag, rec));
  using AddressCallback = boost::function<void(const std_msgs::UInt64MultiArrayConstPtr&)>;
  subs->push_back(nh.subscribe<std_msgs::UInt64MultiArray>(
      "/camera_0/debug/published_address", 100,
      AddressCallback([](const auto& m) { Recorder::address(rec->published, rec->mutex, m); })));
  subs->push_back(nh.subscribe<std_msgs::UInt64MultiArray>(
      "/camera_0/debug/image_data_address", 100,
      AddressCallback([](const auto& m) { Recorder::address(rec->received, rec->mutex, m); })));
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int result = RUN_ALL_TESTS();
  spinner.stop();
  delete subs;
  delete rec;
  return result;
}
