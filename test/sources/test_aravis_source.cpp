// The aravis source against Aravis's fake GigE Vision camera (arv-fake-gv-camera-0.8,
// package aravis-tools) served on the loopback interface only: the real GigE code path
// (discovery, GVCP registers, GVSP stream, heartbeat). Frames with the configured region and
// pixel format, exposure/gain/frame rate applied and read back, and the reconnect path:
// killing the fake camera makes grab() fail, re-opening fails clearly while it is gone and
// succeeds with frames when it is back.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <signal.h>
#include <string>
#include <thread>
#include <unistd.h>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <sys/wait.h>

#include "soccer_vision/sources/aravis_source.h"
#include "soccer_vision/sources/frame_pacer.h"

namespace sv = soccer_vision;

namespace {

const std::string kSerial = "SVTEST";
// Opened by address: no discovery broadcast leaves the loopback interface.
const std::string kCameraName = "127.0.0.1";

// The fake camera process, on 127.0.0.1 only.
class FakeCamera {
 public:
  ~FakeCamera() { stop(); }
  void start() {
    ASSERT_LT(pid_, 0);
    pid_ = ::fork();
    ASSERT_GE(pid_, 0);
    if (pid_ == 0) {
      if (const char* log = std::getenv("SV_FAKE_CAMERA_LOG")) {
        std::freopen(log, "a", stdout);
        std::freopen(log, "a", stderr);
      }
      ::execl(ARV_FAKE_GV_CAMERA, ARV_FAKE_GV_CAMERA, "-i", "127.0.0.1", "-s", kSerial.c_str(),
              static_cast<char*>(nullptr));
      ::_exit(127);
    }
  }
  void stop() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGKILL);  // vanishes like an unplugged camera: no goodbye on the wire
    ::waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }

 private:
  pid_t pid_ = -1;
};

sv::FrameSourceOptions fakeOptions() {
  sv::FrameSourceOptions o;
  o.settings["camera"] = kCameraName;
  o.settings["frame_timeout"] = "2";
  return o;
}

// Opens, retrying for up to `seconds` (the fake camera needs a moment to listen).
sv::OpenResult openWithin(sv::AravisSource& source, const sv::FrameSourceOptions& o, double seconds) {
  const double deadline = sv::systemClockNow() + seconds;
  sv::OpenResult r;
  do {
    r = source.open(o);
    if (r.ok) return r;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  } while (sv::systemClockNow() < deadline);
  return r;
}

struct Frames {
  std::vector<double> stamps;
  std::vector<std::uint64_t> sequences;
  std::vector<double> means;
  sv::GrabStatus last = sv::GrabStatus::Ok;
  std::string error;
};

Frames grabFrames(sv::AravisSource& source, int n, double max_seconds = 10) {
  Frames out;
  const sv::FrameFormat f = source.format();
  std::vector<std::uint8_t> buffer(f.bytes());
  const double deadline = sv::systemClockNow() + max_seconds;
  while (static_cast<int>(out.stamps.size()) < n && sv::systemClockNow() < deadline) {
    cv::Mat image(f.height, f.width, f.cv_type, buffer.data(), f.step);
    sv::FrameInfo info;
    out.last = source.grab(image, info, 0.5, out.error);
    if (out.last == sv::GrabStatus::Timeout) continue;
    if (out.last != sv::GrabStatus::Ok) break;
    out.stamps.push_back(info.stamp);
    out.sequences.push_back(info.sequence);
    out.means.push_back(cv::mean(image)[0]);
  }
  return out;
}

double medianInterval(const std::vector<double>& stamps) {
  std::vector<double> d;
  for (std::size_t i = 1; i < stamps.size(); ++i) d.push_back(stamps[i] - stamps[i - 1]);
  if (d.empty()) return 0;
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  return d[d.size() / 2];
}

std::string stat(const sv::FrameSource& s, const std::string& key) {
  for (const auto& [k, v] : s.statistics())
    if (k == key) return v;
  return "";
}

class AravisFakeCamera : public ::testing::Test {
 protected:
  void SetUp() override {
    if (::access(ARV_FAKE_GV_CAMERA, X_OK) != 0)
      GTEST_SKIP() << "arv-fake-gv-camera-0.8 (aravis-tools) is not installed";
    fake_.start();
  }
  FakeCamera fake_;
};

}  // namespace

TEST(DeviceClockMapper, SmallestOffsetWinsAndJumpsReset) {
  sv::DeviceClockMapper m(8, 1.0);
  // Device clock 100 s behind the wall clock, latency 2..5 ms.
  EXPECT_NEAR(m.map(10.000, 110.005), 110.005, 1e-9);
  EXPECT_NEAR(m.map(10.010, 110.012), 110.012, 1e-9);  // offset 100.002: new minimum
  EXPECT_NEAR(m.map(10.020, 110.025), 110.022, 1e-9);  // late frame: mapped by the minimum
  // The camera restarted its clock: offsets jump, the mapper starts over.
  EXPECT_NEAR(m.map(0.5, 110.035), 110.035, 1e-9);
  EXPECT_NEAR(m.map(0.51, 110.048), 110.045, 1e-9);
}

TEST(AravisEncodings, GenicamNames) {
  EXPECT_EQ(sv::encodingForGenicamPixelFormat("BayerRG8"), "bayer_rggb8");
  EXPECT_EQ(sv::encodingForGenicamPixelFormat("BayerGB8"), "bayer_gbrg8");
  EXPECT_EQ(sv::encodingForGenicamPixelFormat("Mono8"), "mono8");
  EXPECT_EQ(sv::encodingForGenicamPixelFormat("RGB8"), "rgb8");
  EXPECT_EQ(sv::encodingForGenicamPixelFormat("YUV422_8"), "");
}

TEST(AravisSource, MissingCameraIsAClearError) {
  sv::AravisSource source;
  sv::FrameSourceOptions o;
  o.settings["camera"] = "127.0.0.2";  // loopback, nobody serves GigE Vision there
  const sv::OpenResult r = source.open(o);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("127.0.0.2"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("not found"), std::string::npos) << r.error;
  cv::Mat image(4, 4, CV_8UC1);
  sv::FrameInfo info;
  std::string error;
  EXPECT_EQ(source.grab(image, info, 0.1, error), sv::GrabStatus::Error);
}

TEST_F(AravisFakeCamera, FramesWithTheConfiguredRegionFormatAndRate) {
  sv::AravisSource source;
  sv::FrameSourceOptions o = fakeOptions();
  o.settings["pixel_format"] = "BayerRG8";
  o.width = 320;
  o.height = 240;
  o.fps = 40;
  const sv::OpenResult r = openWithin(source, o, 10);
  ASSERT_TRUE(r.ok) << r.error;
  const sv::FrameFormat f = source.format();
  EXPECT_EQ(f.width, 320);
  EXPECT_EQ(f.height, 240);
  EXPECT_EQ(f.encoding, "bayer_rggb8");
  EXPECT_EQ(f.cv_type, CV_8UC1);
  EXPECT_NEAR(source.fps(), 40, 1e-6);
  EXPECT_EQ(stat(source, "pixel format"), "BayerRG8");
  EXPECT_EQ(stat(source, "camera"), kSerial);
  EXPECT_FALSE(stat(source, "packet size").empty());

  const double before = sv::systemClockNow();
  const Frames frames = grabFrames(source, 20);
  ASSERT_EQ(frames.stamps.size(), 20u) << frames.error;
  for (std::size_t i = 1; i < frames.stamps.size(); ++i) {
    EXPECT_GT(frames.stamps[i], frames.stamps[i - 1]);
    EXPECT_GT(frames.sequences[i], frames.sequences[i - 1]);
  }
  // Camera stamps on the wall clock: within the time we grabbed.
  EXPECT_GT(frames.stamps.front(), before - 1.0);
  EXPECT_LT(frames.stamps.back(), sv::systemClockNow() + 0.01);
  EXPECT_NEAR(medianInterval(frames.stamps), 1.0 / 40, 0.2 / 40);
  EXPECT_GT(frames.means.back(), 1.0);  // the fake's test pattern arrived, not zeros
  EXPECT_GE(std::stoull(stat(source, "stream completed buffers")), 20u);
  EXPECT_EQ(stat(source, "stream failures"), "0");

  // Another pixel format on re-open.
  o.settings["pixel_format"] = "Mono8";
  ASSERT_TRUE(source.open(o).ok);
  EXPECT_EQ(source.format().encoding, "mono8");
  o.settings["pixel_format"] = "YUV411";
  const sv::OpenResult bad = source.open(o);
  EXPECT_FALSE(bad.ok);
  EXPECT_NE(bad.error.find("BayerRG8"), std::string::npos) << bad.error;  // lists what exists
}

TEST_F(AravisFakeCamera, ExposureGainAndFrameRateAreAppliedAndReadBack) {
  sv::AravisSource source;
  sv::FrameSourceOptions o = fakeOptions();
  o.settings["pixel_format"] = "Mono8";
  o.fps = 50;
  const sv::OpenResult r = openWithin(source, o, 10);
  ASSERT_TRUE(r.ok) << r.error;
  const std::vector<std::string> controls = source.controls();
  ASSERT_NE(std::find(controls.begin(), controls.end(), "exposure"), controls.end());
  ASSERT_NE(std::find(controls.begin(), controls.end(), "gain"), controls.end());

  std::string error;
  ASSERT_TRUE(source.setControl("exposure", 2500, error)) << error;
  ASSERT_TRUE(source.setControl("gain", 4, error)) << error;
  EXPECT_NEAR(*source.control("exposure"), 2500, 1e-9);  // queued for the next frame
  EXPECT_FALSE(source.setControl("gain", 1e6, error));
  EXPECT_NE(error.find("range"), std::string::npos) << error;
  EXPECT_FALSE(source.setControl("brightness", 1, error));
  Frames frames = grabFrames(source, 3);
  ASSERT_EQ(frames.stamps.size(), 3u) << frames.error;
  ASSERT_TRUE(source.control("exposure"));
  EXPECT_NEAR(*source.control("exposure"), 2500, 1);  // read back from the camera
  EXPECT_NEAR(*source.control("gain"), 4, 1e-3);

  ASSERT_TRUE(source.setFps(10, error)) << error;
  grabFrames(source, 2);  // frames queued at the old rate
  frames = grabFrames(source, 8);
  ASSERT_EQ(frames.stamps.size(), 8u) << frames.error;
  EXPECT_NEAR(source.fps(), 10, 1e-6);
  EXPECT_NEAR(medianInterval(frames.stamps), 0.1, 0.02);
}

TEST_F(AravisFakeCamera, VanishedCameraFailsAndFramesResumeWhenItReturns) {
  sv::AravisSource source;
  sv::FrameSourceOptions o = fakeOptions();
  o.fps = 50;
  sv::OpenResult r = openWithin(source, o, 10);
  ASSERT_TRUE(r.ok) << r.error;
  Frames frames = grabFrames(source, 5);
  ASSERT_EQ(frames.stamps.size(), 5u) << frames.error;

  fake_.stop();
  const double killed = sv::systemClockNow();
  frames = grabFrames(source, 1000, 20);
  EXPECT_EQ(frames.last, sv::GrabStatus::Error);
  EXPECT_TRUE(frames.error.find("control lost") != std::string::npos ||
              frames.error.find("no frame") != std::string::npos)
      << frames.error;
  EXPECT_LT(frames.stamps.size(), 10u);  // at most what was queued
  std::cout << "error after " << sv::systemClockNow() - killed << " s: " << frames.error << "\n";
  source.close();  // waits out the dead camera's GVCP timeouts (several seconds)
  r = source.open(o);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find(kCameraName), std::string::npos) << r.error;

  fake_.start();
  r = openWithin(source, o, 15);
  ASSERT_TRUE(r.ok) << r.error;
  frames = grabFrames(source, 5);
  EXPECT_EQ(frames.stamps.size(), 5u) << frames.error;
}
