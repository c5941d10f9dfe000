// rostest for the CameraDriver with the aravis source (test/nodelets/camera_aravis.test). This
// node runs Aravis's fake GigE camera (arv-fake-gv-camera-0.8 -i 127.0.0.1, loopback only)
// as a child process, so that it can make the camera vanish and return.
//
// Tests run in declaration order:
//  1. frames arrive: bayer_rggb8 320x240 (the configured region and format), increasing
//     stamps 1/30 s apart; the start-up exposure (5000 µs) is what dynamic_reconfigure shows;
//     /diagnostics carry the camera id and the stream statistics;
//  2. dynamic_reconfigure: exposure 3000 is accepted, gain 100 (above the fake camera's
//     maximum of 10) is refused and reset to the camera's value;
//  3. killing the camera: frames stop, the source reports an error in /diagnostics; after a
//     restart of the camera frames resume with later stamps.
#include <algorithm>
#include <cstdio>
#include <mutex>
#include <signal.h>
#include <string>
#include <unistd.h>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>
#include <sys/wait.h>

#include "soccer_vision/common/statistics.h"

namespace {

pid_t fake_pid = -1;

void startFake() {
  fake_pid = ::fork();
  if (fake_pid == 0) {
    std::freopen("/dev/null", "w", stdout);
    std::freopen("/dev/null", "w", stderr);
    ::execl(ARV_FAKE_GV_CAMERA, ARV_FAKE_GV_CAMERA, "-i", "127.0.0.1", static_cast<char*>(nullptr));
    ::_exit(127);
  }
}

void stopFake() {
  if (fake_pid <= 0) return;
  ::kill(fake_pid, SIGKILL);
  ::waitpid(fake_pid, nullptr, 0);
  fake_pid = -1;
}

struct Recorder {
  std::mutex mutex;
  std::vector<ros::Time> stamps;
  std::vector<ros::WallTime> arrivals;
  std::string encoding;
  int width = 0, height = 0;
  diagnostic_msgs::DiagnosticStatus source_status;
  bool have_status = false;

  void image(const sensor_msgs::ImageConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    stamps.push_back(m->header.stamp);
    arrivals.push_back(ros::WallTime::now());
    encoding = m->encoding;
    width = static_cast<int>(m->width);
    height = static_cast<int>(m->height);
  }
  void diag(const diagnostic_msgs::DiagnosticArrayConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    for (const auto& s : m->status)
      if (s.name.find("camera_0/camera_driver") != std::string::npos &&
          s.name.find("source") != std::string::npos) {
        source_status = s;
        have_status = true;
      }
  }
};

Recorder* rec = nullptr;

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

std::string value(const diagnostic_msgs::DiagnosticStatus& s, const std::string& key) {
  for (const auto& kv : s.values)
    if (kv.key == key) return kv.value;
  return "";
}

double medianInterval(const std::vector<ros::Time>& stamps) {
  std::vector<double> d;
  for (std::size_t i = 1; i < stamps.size(); ++i) d.push_back((stamps[i] - stamps[i - 1]).toSec());
  return d.empty() ? 0 : soccer_vision::percentile(d, 50);
}

bool reconfigure(const std::string& name, double v, dynamic_reconfigure::Config& result) {
  dynamic_reconfigure::Reconfigure srv;
  dynamic_reconfigure::DoubleParameter p;
  p.name = name;
  p.value = v;
  srv.request.config.doubles.push_back(p);
  if (!ros::service::call("/camera_0/camera_driver/set_parameters", srv)) return false;
  result = srv.response.config;
  return true;
}

double configValue(const dynamic_reconfigure::Config& c, const std::string& name) {
  for (const auto& d : c.doubles)
    if (d.name == name) return d.value;
  return -1;
}

}  // namespace

TEST(CameraAravis, FramesWithTheConfiguredFormatAndExposure) {
  ASSERT_TRUE(waitFor([] { return rec->stamps.size() >= 20; }, 40)) << "no frames";
  {
    std::lock_guard<std::mutex> l(rec->mutex);
    EXPECT_EQ(rec->encoding, "bayer_rggb8");
    EXPECT_EQ(rec->width, 320);
    EXPECT_EQ(rec->height, 240);
    for (std::size_t i = 1; i < rec->stamps.size(); ++i)
      EXPECT_GT(rec->stamps[i], rec->stamps[i - 1]) << "at " << i;
    EXPECT_NEAR(medianInterval(rec->stamps), 1.0 / 30, 0.2 / 30);
    // Camera stamps on the wall clock: at most a second before arrival.
    const double age = (ros::Time(rec->arrivals.back().toSec()) - rec->stamps.back()).toSec();
    EXPECT_GE(age, 0.0);
    EXPECT_LT(age, 1.0);
  }
  double exposure = 0;
  ASSERT_TRUE(ros::param::get("/camera_0/camera_driver/exposure", exposure));
  EXPECT_NEAR(exposure, 5000, 1);
  ASSERT_TRUE(waitFor(
      [] {  // a status from after the open (before it the driver was retrying)
        return rec->have_status && rec->source_status.level == diagnostic_msgs::DiagnosticStatus::OK &&
               value(rec->source_status, "stream completed buffers") != "" &&
               value(rec->source_status, "stream completed buffers") != "0";
      },
      10));
  std::lock_guard<std::mutex> l(rec->mutex);
  EXPECT_EQ(rec->source_status.level, diagnostic_msgs::DiagnosticStatus::OK) << rec->source_status.message;
  EXPECT_EQ(value(rec->source_status, "camera"), "GV01");
  EXPECT_EQ(value(rec->source_status, "encoding"), "bayer_rggb8");
  EXPECT_GT(std::stoull(value(rec->source_status, "stream completed buffers")), 0u);
}

TEST(CameraAravis, ControlsThroughDynamicReconfigure) {
  ASSERT_TRUE(ros::service::waitForService("/camera_0/camera_driver/set_parameters", 10000));
  dynamic_reconfigure::Config c;
  ASSERT_TRUE(reconfigure("exposure", 3000, c));
  EXPECT_NEAR(configValue(c, "exposure"), 3000, 1e-6);
  ASSERT_TRUE(reconfigure("gain", 100, c));  // the fake camera's gain is 0..10
  EXPECT_NEAR(configValue(c, "gain"), 0, 1e-6);
  EXPECT_NEAR(configValue(c, "exposure"), 3000, 1e-6);
  ros::WallDuration(0.5).sleep();  // applied by the capture thread at the next frames
}

TEST(CameraAravis, VanishedCameraIsReportedAndFramesResume) {
  ASSERT_TRUE(waitFor([] { return !rec->stamps.empty(); }, 10));
  stopFake();
  const ros::WallTime killed = ros::WallTime::now();
  ros::Time last_before;
  // Frames stop, the source reports the error.
  ASSERT_TRUE(waitFor(
      [&] {
        return rec->have_status && rec->source_status.level == diagnostic_msgs::DiagnosticStatus::ERROR &&
               (ros::WallTime::now() - rec->arrivals.back()).toSec() > 1.0;
      },
      40))
      << rec->source_status.message;
  {
    std::lock_guard<std::mutex> l(rec->mutex);
    last_before = rec->stamps.back();
    EXPECT_LT((rec->arrivals.back() - killed).toSec(), 1.0);  // nothing after the queue ran dry
    std::printf("error reported %.1f s after the kill: %s\n", (ros::WallTime::now() - killed).toSec(),
                rec->source_status.message.c_str());
  }
  startFake();
  const ros::WallTime restarted = ros::WallTime::now();
  ASSERT_TRUE(
      waitFor([&] { return rec->stamps.back() > last_before && rec->arrivals.back() > restarted; }, 40))
      << "no frames after the camera came back";
  ASSERT_TRUE(waitFor(
      [&] { return rec->stamps.size() >= 5 && rec->arrivals.back() > restarted + ros::WallDuration(0.5); },
      10));
  std::printf("frames again %.1f s after the restart\n", (ros::WallTime::now() - restarted).toSec());
  ASSERT_TRUE(waitFor([] { return rec->source_status.level == diagnostic_msgs::DiagnosticStatus::OK; }, 10));
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_camera_aravis");
  if (::access(ARV_FAKE_GV_CAMERA, X_OK) != 0) {
    std::fprintf(stderr, "%s (aravis-tools) is missing\n", ARV_FAKE_GV_CAMERA);
    return 1;
  }
  ros::NodeHandle nh;
  rec = new Recorder;
  ros::Subscriber image_sub = nh.subscribe("/camera_0/image_raw", 100, &Recorder::image, rec);
  ros::Subscriber diag_sub = nh.subscribe("/diagnostics", 100, &Recorder::diag, rec);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ros::WallDuration(1.0).sleep();  // the driver fails to open first: the retry path
  startFake();
  const int result = RUN_ALL_TESTS();
  stopFake();
  spinner.stop();
  delete rec;
  return result;
}
