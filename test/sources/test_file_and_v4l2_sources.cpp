// Tests of the file sources (video, images) on files written at test time, of the V4L2
// source's pure parts (format negotiation, YUYV/UYVY/RGB/Bayer/MJPEG conversion, clocks),
// of a missing/non-V4L2 device, and of the shared settings/pacing helpers.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

#include <gtest/gtest.h>
#include <linux/videodev2.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <sys/stat.h>

#include "soccer_vision/common/bayer_encoding.h"
#include "soccer_vision/sources/frame_pacer.h"
#include "soccer_vision/sources/frame_source.h"
#include "soccer_vision/sources/images_source.h"
#include "soccer_vision/sources/source_settings.h"
#include "soccer_vision/sources/v4l2_formats.h"
#include "soccer_vision/sources/v4l2_source.h"
#include "soccer_vision/sources/video_source.h"

namespace sv = soccer_vision;

namespace {

constexpr int kWidth = 64, kHeight = 48;

// Frame `index` (0..255) as 8 blocks of 8x8 px along the top, white = bit set, on grey:
// robust to JPEG compression.
cv::Mat indexedFrame(int index) {
  cv::Mat m(kHeight, kWidth, CV_8UC3, cv::Scalar(90, 120, 150));
  for (int b = 0; b < 8; ++b)
    m(cv::Rect(b * 8, 0, 8, 8)).setTo((index >> b) & 1 ? cv::Scalar::all(255) : cv::Scalar::all(0));
  return m;
}

int decodeIndex(const cv::Mat& m) {
  cv::Mat gray;
  if (m.channels() == 3)
    cv::cvtColor(m, gray, cv::COLOR_BGR2GRAY);
  else
    gray = m;
  int index = 0;
  for (int b = 0; b < 8; ++b)
    if (gray.at<std::uint8_t>(4, b * 8 + 4) > 128) index |= 1 << b;
  return index;
}

std::string makeTempDir(const std::string& tag) {
  std::string pattern = "/tmp/sv_test_sources_" + tag + "_XXXXXX";
  std::vector<char> buf(pattern.begin(), pattern.end());
  buf.push_back('\0');
  const char* dir = ::mkdtemp(buf.data());
  return dir ? dir : "";
}

std::string framePath(const std::string& dir, int i) {
  char name[64];
  std::snprintf(name, sizeof name, "/frame_%04d.png", i);
  return dir + name;
}

struct Grabbed {
  std::vector<int> indices;
  std::vector<double> stamps;
  std::vector<std::uint64_t> sequences;
  std::vector<std::string> encodings;
  sv::GrabStatus last = sv::GrabStatus::Ok;
  bool buffer_kept = true;  // every frame written into the caller's buffer
};

// Grabs until `max_frames` frames or a status other than Ok/Timeout.
Grabbed grabAll(sv::FrameSource& source, int max_frames) {
  Grabbed g;
  const sv::FrameFormat f = source.format();
  std::vector<std::uint8_t> buffer(f.bytes());
  for (int attempts = 0; static_cast<int>(g.indices.size()) < max_frames && attempts < 10000; ++attempts) {
    cv::Mat image(f.height, f.width, f.cv_type, buffer.data(), f.step);
    sv::FrameInfo info;
    std::string error;
    g.last = source.grab(image, info, 0.5, error);
    if (g.last == sv::GrabStatus::Timeout) continue;
    if (g.last != sv::GrabStatus::Ok) break;
    g.buffer_kept = g.buffer_kept && image.data == buffer.data();
    g.indices.push_back(decodeIndex(image));
    g.stamps.push_back(info.stamp);
    g.sequences.push_back(info.sequence);
    g.encodings.push_back(info.encoding);
  }
  return g;
}

double medianInterval(const std::vector<double>& stamps) {
  std::vector<double> d;
  for (std::size_t i = 1; i < stamps.size(); ++i) d.push_back(stamps[i] - stamps[i - 1]);
  if (d.empty()) return 0;
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  return d[d.size() / 2];
}

bool strictlyIncreasing(const std::vector<double>& v) {
  for (std::size_t i = 1; i < v.size(); ++i)
    if (!(v[i] > v[i - 1])) return false;
  return true;
}

std::vector<int> range(int n, int from = 0) {
  std::vector<int> r;
  for (int i = 0; i < n; ++i) r.push_back(from + i);
  return r;
}

double wallNow() {
  using namespace std::chrono;
  return duration<double>(system_clock::now().time_since_epoch()).count();
}

class ImagesSourceTest : public ::testing::Test {
 protected:
  static constexpr int kFrames = 12;
  void SetUp() override {
    dir_ = makeTempDir("images");
    ASSERT_FALSE(dir_.empty());
    for (int i = 0; i < kFrames; ++i) ASSERT_TRUE(cv::imwrite(framePath(dir_, i), indexedFrame(i)));
    // Not a frame: the glob must leave it out; the folder listing takes it (sorted last).
    ASSERT_TRUE(cv::imwrite(dir_ + "/zz_other.png", indexedFrame(200)));
    std::ofstream(dir_ + "/notes.txt") << "not an image";
  }
  void TearDown() override { std::system(("rm -rf '" + dir_ + "'").c_str()); }
  sv::FrameSourceOptions options(const std::string& path, double fps = 50) const {
    sv::FrameSourceOptions o;
    o.fps = fps;
    o.settings["path"] = path;
    return o;
  }
  std::string dir_;
};

class VideoSourceTest : public ::testing::Test {
 protected:
  static constexpr int kFrames = 20;
  static constexpr double kFileFps = 25;
  void SetUp() override {
    dir_ = makeTempDir("video");
    ASSERT_FALSE(dir_.empty());
    file_ = dir_ + "/indexed.avi";
    cv::VideoWriter writer(file_, cv::CAP_FFMPEG, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), kFileFps,
                           cv::Size(kWidth, kHeight));
    ASSERT_TRUE(writer.isOpened()) << "OpenCV's FFmpeg back-end cannot write MJPG .avi";
    for (int i = 0; i < kFrames; ++i) writer.write(indexedFrame(i));
    writer.release();
  }
  void TearDown() override { std::system(("rm -rf '" + dir_ + "'").c_str()); }
  sv::FrameSourceOptions options(double fps = 0) const {
    sv::FrameSourceOptions o;
    o.fps = fps;
    o.settings["file"] = file_;
    return o;
  }
  std::string dir_, file_;
};

}  // namespace

TEST(FrameSourceRegistry, KnowsTheLiveAndFileSources) {
  const std::vector<std::string> names = sv::frameSourceNames();
  for (const char* n : {"aravis", "images", "synthetic", "v4l2", "video"})
    EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
  std::string error;
  auto v = sv::createFrameSource("video", error);
  ASSERT_TRUE(v);
  EXPECT_EQ(v->name(), "video");
}

TEST(SettingsReader, ParsesAndReportsTheFirstBadValue) {
  const std::map<std::string, std::string> s = {
      {"a", "true"}, {"b", "0"}, {"n", "2.5"}, {"bad", "maybe"}, {"badn", "1x"}};
  sv::SettingsReader r(s);
  EXPECT_TRUE(r.flag("a", false));
  EXPECT_FALSE(r.flag("b", true));
  EXPECT_DOUBLE_EQ(r.number("n", 0), 2.5);
  EXPECT_DOUBLE_EQ(r.number("missing", 7), 7);
  EXPECT_EQ(r.text("missing", "x"), "x");
  EXPECT_TRUE(r.ok());
  EXPECT_TRUE(r.flag("bad", true));  // fallback
  EXPECT_DOUBLE_EQ(r.number("badn", 3), 3);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.error().find("bad = 'maybe'"), std::string::npos) << r.error();
}

TEST(FramePacer, EvenStampsAndRateChange) {
  sv::FramePacer pacer;
  pacer.start(100);
  std::vector<double> stamps;
  double stamp = 0;
  for (int i = 0; i < 6; ++i) {
    ASSERT_EQ(pacer.wait(1.0, stamp), sv::FramePacer::Wait::Due);
    stamps.push_back(stamp);
  }
  EXPECT_NEAR(medianInterval(stamps), 0.01, 1e-6);  // Unix-time doubles: ~0.2 µs
  pacer.setFps(50);
  std::vector<double> slower = {stamps.back()};
  for (int i = 0; i < 5; ++i) {
    ASSERT_EQ(pacer.wait(1.0, stamp), sv::FramePacer::Wait::Due);
    slower.push_back(stamp);
  }
  EXPECT_NEAR(medianInterval(slower), 0.02, 1e-6);
  EXPECT_NEAR(pacer.fps(), 50, 1e-9);
  // A frame 0.02 s away is not due within 1 ms; interrupt() ends waiting.
  EXPECT_EQ(pacer.wait(0.001, stamp), sv::FramePacer::Wait::Timeout);
  pacer.interrupt();
  EXPECT_EQ(pacer.wait(1.0, stamp), sv::FramePacer::Wait::Interrupted);
}

TEST_F(ImagesSourceTest, FolderInOrderAtTheRateThenEnd) {
  sv::ImagesSource source;
  const sv::OpenResult r = source.open(options(dir_, 50));
  ASSERT_TRUE(r.ok) << r.error;
  const sv::FrameFormat f = source.format();
  EXPECT_EQ(f.width, kWidth);
  EXPECT_EQ(f.height, kHeight);
  EXPECT_EQ(f.encoding, "bgr8");
  EXPECT_EQ(f.cv_type, CV_8UC3);
  EXPECT_NEAR(source.fps(), 50, 1e-9);
  ASSERT_EQ(source.files().size(), static_cast<std::size_t>(kFrames + 1));  // + zz_other.png
  const double t0 = wallNow();
  const Grabbed g = grabAll(source, 100);
  const double elapsed = wallNow() - t0;
  EXPECT_EQ(g.last, sv::GrabStatus::EndOfStream);
  std::vector<int> expected = range(kFrames);
  expected.push_back(200);
  EXPECT_EQ(g.indices, expected);
  EXPECT_TRUE(g.buffer_kept);
  EXPECT_TRUE(strictlyIncreasing(g.stamps));
  EXPECT_NEAR(medianInterval(g.stamps), 0.02, 1e-6);
  EXPECT_GE(elapsed, 0.9 * (kFrames)*0.02);  // paced, not faster than the rate
  for (const std::string& e : g.encodings) EXPECT_EQ(e, "bgr8");
  for (std::size_t i = 0; i < g.sequences.size(); ++i) EXPECT_EQ(g.sequences[i], i);
}

TEST_F(ImagesSourceTest, GlobLoopsWithIncreasingSequenceAndStamps) {
  sv::ImagesSource source;
  sv::FrameSourceOptions o = options(dir_ + "/frame_*.png", 200);
  o.settings["loop"] = "true";
  ASSERT_TRUE(source.open(o).ok);
  EXPECT_EQ(source.files().size(), static_cast<std::size_t>(kFrames));
  const Grabbed g = grabAll(source, 2 * kFrames + 5);
  ASSERT_EQ(g.indices.size(), static_cast<std::size_t>(2 * kFrames + 5));
  std::vector<int> expected = range(kFrames);
  for (int i : range(kFrames)) expected.push_back(i);
  for (int i : range(5)) expected.push_back(i);
  EXPECT_EQ(g.indices, expected);
  EXPECT_TRUE(strictlyIncreasing(g.stamps));
  EXPECT_EQ(g.sequences.back(), static_cast<std::uint64_t>(2 * kFrames + 4));
}

TEST_F(ImagesSourceTest, AsFastAsPossibleAndRawBayer) {
  sv::ImagesSource source;
  sv::FrameSourceOptions o = options(dir_ + "/frame_*.png", 0);
  o.settings["realtime"] = "false";
  o.settings["encoding"] = "bayer_rggb8";
  ASSERT_TRUE(source.open(o).ok);
  EXPECT_EQ(source.fps(), 0.0);
  std::string error;
  EXPECT_FALSE(source.setFps(30, error));
  EXPECT_EQ(source.format().encoding, "bayer_rggb8");
  EXPECT_EQ(source.format().cv_type, CV_8UC1);
  const Grabbed g = grabAll(source, 100);
  EXPECT_EQ(g.indices, range(kFrames));  // grey blocks decode the same
  EXPECT_TRUE(strictlyIncreasing(g.stamps));
  for (const std::string& e : g.encodings) EXPECT_EQ(e, "bayer_rggb8");
}

TEST_F(ImagesSourceTest, ClearErrors) {
  sv::ImagesSource source;
  sv::OpenResult r = source.open(sv::FrameSourceOptions{});
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("'path'"), std::string::npos) << r.error;
  r = source.open(options(dir_ + "/nothing_*.png"));
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("no image files match"), std::string::npos) << r.error;
  const std::string empty = makeTempDir("empty");
  r = source.open(options(empty));
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("has no image files"), std::string::npos) << r.error;
  ::rmdir(empty.c_str());
  sv::FrameSourceOptions o = options(dir_);
  o.settings["encoding"] = "yuv422";
  EXPECT_FALSE(source.open(o).ok);
  o = options(dir_);
  o.settings["loop"] = "sometimes";
  r = source.open(o);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("loop"), std::string::npos) << r.error;
  EXPECT_FALSE(source.isOpen());

  // A frame of another size and a corrupt file are errors for those frames only.
  ASSERT_TRUE(cv::imwrite(framePath(dir_, 5), cv::Mat(10, 10, CV_8UC3, cv::Scalar::all(0))));
  std::ofstream(framePath(dir_, 8), std::ios::trunc) << "\x89PNG truncated";
  ASSERT_TRUE(source.open(options(dir_ + "/frame_*.png", 500)).ok);
  const sv::FrameFormat f = source.format();
  std::vector<std::uint8_t> buffer(f.bytes());
  std::vector<int> seen;
  int errors = 0;
  for (int i = 0; i < kFrames; ++i) {
    cv::Mat image(f.height, f.width, f.cv_type, buffer.data(), f.step);
    sv::FrameInfo info;
    std::string error;
    const sv::GrabStatus s = source.grab(image, info, 1.0, error);
    if (s == sv::GrabStatus::Ok) seen.push_back(decodeIndex(image));
    if (s == sv::GrabStatus::Error) {
      ++errors;
      EXPECT_TRUE(error.find("frame_0005.png' is 10x10") != std::string::npos ||
                  error.find("frame_0008.png' cannot be decoded") != std::string::npos)
          << error;
    }
  }
  EXPECT_EQ(errors, 2);
  std::vector<int> expected = range(kFrames);
  expected.erase(expected.begin() + 8);
  expected.erase(expected.begin() + 5);
  EXPECT_EQ(seen, expected);
}

TEST_F(VideoSourceTest, FileRateOrderEndOfStream) {
  sv::VideoSource source;
  const sv::OpenResult r = source.open(options());
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_NEAR(source.fileFps(), kFileFps, 1e-6);
  EXPECT_NEAR(source.fps(), kFileFps, 1e-6);
  const sv::FrameFormat f = source.format();
  EXPECT_EQ(f.width, kWidth);
  EXPECT_EQ(f.height, kHeight);
  EXPECT_EQ(f.encoding, "bgr8");
  const double t0 = wallNow();
  const Grabbed g = grabAll(source, 100);
  const double elapsed = wallNow() - t0;
  EXPECT_EQ(g.last, sv::GrabStatus::EndOfStream);
  EXPECT_EQ(g.indices, range(kFrames));
  EXPECT_TRUE(g.buffer_kept);
  EXPECT_TRUE(strictlyIncreasing(g.stamps));
  EXPECT_NEAR(medianInterval(g.stamps), 1.0 / kFileFps, 1e-6);
  EXPECT_GE(elapsed, 0.9 * (kFrames - 1) / kFileFps);
  for (const std::string& e : g.encodings) EXPECT_EQ(e, "bgr8");
}

TEST_F(VideoSourceTest, RateOverrideLoopAndRuntimeFps) {
  sv::VideoSource source;
  sv::FrameSourceOptions o = options(200);
  o.settings["loop"] = "true";
  ASSERT_TRUE(source.open(o).ok);
  EXPECT_NEAR(source.fps(), 200, 1e-9);
  Grabbed g = grabAll(source, kFrames + 7);
  std::vector<int> expected = range(kFrames);
  for (int i : range(7)) expected.push_back(i);
  EXPECT_EQ(g.indices, expected);
  EXPECT_TRUE(strictlyIncreasing(g.stamps));
  EXPECT_NEAR(medianInterval(g.stamps), 1.0 / 200, 1e-6);
  std::string error;
  ASSERT_TRUE(source.setFps(100, error)) << error;
  g = grabAll(source, 8);
  EXPECT_EQ(g.indices, range(8, 7));
  EXPECT_NEAR(medianInterval(g.stamps), 1.0 / 100, 1e-6);
  EXPECT_FALSE(source.setFps(0, error));
}

TEST_F(VideoSourceTest, AsFastAsPossible) {
  sv::VideoSource source;
  sv::FrameSourceOptions o = options();
  o.settings["realtime"] = "false";
  ASSERT_TRUE(source.open(o).ok);
  EXPECT_EQ(source.fps(), 0.0);
  const Grabbed g = grabAll(source, 100);
  EXPECT_EQ(g.last, sv::GrabStatus::EndOfStream);
  EXPECT_EQ(g.indices, range(kFrames));
  EXPECT_TRUE(strictlyIncreasing(g.stamps));
}

TEST_F(VideoSourceTest, MissingAndUndecodableFiles) {
  sv::VideoSource source;
  sv::OpenResult r = source.open(sv::FrameSourceOptions{});
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("'file'"), std::string::npos) << r.error;
  sv::FrameSourceOptions o;
  o.settings["file"] = dir_ + "/missing.avi";
  r = source.open(o);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("does not exist"), std::string::npos) << r.error;
  std::ofstream(dir_ + "/garbage.avi") << "this is not a video file at all";
  o.settings["file"] = dir_ + "/garbage.avi";
  r = source.open(o);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("garbage.avi"), std::string::npos) << r.error;
  cv::Mat image(kHeight, kWidth, CV_8UC3);
  sv::FrameInfo info;
  std::string error;
  EXPECT_EQ(source.grab(image, info, 0.1, error), sv::GrabStatus::Error);
}

// ---------------------------------------------------------------------------------------
// V4L2: pure parts.

TEST(V4l2Formats, NamesAndEncodings) {
  std::string error;
  EXPECT_EQ(sv::v4l2FourccFromName("yuyv", error), V4L2_PIX_FMT_YUYV);
  EXPECT_EQ(sv::v4l2FourccFromName("MJPEG", error), V4L2_PIX_FMT_MJPEG);
  EXPECT_EQ(sv::v4l2FourccFromName("bayer_grbg8", error), V4L2_PIX_FMT_SGRBG8);
  EXPECT_EQ(sv::v4l2FourccFromName("BA81", error), V4L2_PIX_FMT_SBGGR8);
  EXPECT_FALSE(sv::v4l2FourccFromName("H264", error));
  EXPECT_NE(error.find("H264"), std::string::npos);
  EXPECT_EQ(sv::v4l2FourccName(V4L2_PIX_FMT_YUYV), "YUYV");
  EXPECT_EQ(sv::v4l2Encoding(V4L2_PIX_FMT_YUYV), "bgr8");
  EXPECT_EQ(sv::v4l2Encoding(V4L2_PIX_FMT_MJPEG), "bgr8");
  EXPECT_EQ(sv::v4l2Encoding(V4L2_PIX_FMT_SRGGB8), "bayer_rggb8");
  EXPECT_EQ(sv::v4l2Encoding(V4L2_PIX_FMT_SBGGR8), "bayer_bggr8");
  EXPECT_EQ(sv::v4l2Encoding(V4L2_PIX_FMT_GREY), "mono8");
  EXPECT_EQ(sv::v4l2Encoding(V4L2_PIX_FMT_H264), "");
}

namespace {
// A typical UVC webcam (YUYV slow at full HD, MJPEG fast) plus a Bayer mode.
std::vector<sv::V4l2Mode> webcamModes() {
  return {{V4L2_PIX_FMT_YUYV, 640, 480, {30, 15}},    {V4L2_PIX_FMT_YUYV, 1920, 1080, {5}},
          {V4L2_PIX_FMT_MJPEG, 1920, 1080, {30, 15}}, {V4L2_PIX_FMT_MJPEG, 640, 480, {30}},
          {V4L2_PIX_FMT_H264, 1920, 1080, {60}},      {V4L2_PIX_FMT_SRGGB8, 1280, 1024, {60, 30}}};
}
sv::V4l2Choice negotiate(const sv::V4l2Request& r) {
  sv::V4l2Choice c;
  std::string error;
  EXPECT_TRUE(sv::negotiateV4l2Format(webcamModes(), r, c, error)) << error;
  return c;
}
}  // namespace

TEST(V4l2Formats, Negotiation) {
  sv::V4l2Request r;
  r.width = 1920, r.height = 1080, r.fps = 30;
  sv::V4l2Choice c = negotiate(r);  // YUYV only gives 5 Hz there: MJPEG
  EXPECT_EQ(c.fourcc, V4L2_PIX_FMT_MJPEG);
  EXPECT_EQ(c.width, 1920);
  EXPECT_DOUBLE_EQ(c.fps, 30);

  r.width = 640, r.height = 480;  // uncompressed YUYV preferred over MJPEG
  c = negotiate(r);
  EXPECT_EQ(c.fourcc, V4L2_PIX_FMT_YUYV);
  EXPECT_EQ(c.height, 480);
  EXPECT_DOUBLE_EQ(c.fps, 30);

  r.fps = 20;  // nearest listed rate at or above
  EXPECT_DOUBLE_EQ(negotiate(r).fps, 30);

  c = negotiate(sv::V4l2Request{});  // nothing asked: Bayer first, largest, fastest
  EXPECT_EQ(c.fourcc, V4L2_PIX_FMT_SRGGB8);
  EXPECT_EQ(c.width, 1280);
  EXPECT_DOUBLE_EQ(c.fps, 60);

  r = sv::V4l2Request{};
  r.fourcc = V4L2_PIX_FMT_YUYV;
  r.width = 1920, r.height = 1080, r.fps = 30;  // asked-for format wins over the rate
  c = negotiate(r);
  EXPECT_EQ(c.fourcc, V4L2_PIX_FMT_YUYV);
  EXPECT_EQ(c.width, 1920);
  EXPECT_DOUBLE_EQ(c.fps, 5);

  r = sv::V4l2Request{};
  r.fourcc = V4L2_PIX_FMT_MJPEG;
  r.width = 800, r.height = 600;  // no exact size: the nearest
  c = negotiate(r);
  EXPECT_EQ(c.width, 640);
  EXPECT_EQ(c.height, 480);

  std::string error;
  r = sv::V4l2Request{};
  r.fourcc = V4L2_PIX_FMT_GREY;
  EXPECT_FALSE(sv::negotiateV4l2Format(webcamModes(), r, c, error));
  EXPECT_NE(error.find("does not offer GREY"), std::string::npos) << error;
  EXPECT_NE(error.find("MJPG"), std::string::npos) << error;
  EXPECT_FALSE(sv::negotiateV4l2Format({{V4L2_PIX_FMT_H264, 640, 480, {30}}}, sv::V4l2Request{}, c, error));
  EXPECT_NE(error.find("no supported pixel format"), std::string::npos) << error;

  // A device without listed rates: the request is passed on.
  r = sv::V4l2Request{};
  r.fps = 42;
  ASSERT_TRUE(sv::negotiateV4l2Format({{V4L2_PIX_FMT_YUYV, 320, 240, {}}}, r, c, error));
  EXPECT_DOUBLE_EQ(c.fps, 42);
}

namespace {
// BT.601 limited range, as camera YUV is.
cv::Vec3b yuvToBgr601(int y, int u, int v) {
  const double c = 1.164 * (y - 16), d = u - 128, e = v - 128;
  auto clamp = [](double x) { return cv::saturate_cast<std::uint8_t>(std::lround(x)); };
  return {clamp(c + 2.018 * d), clamp(c - 0.391 * d - 0.813 * e), clamp(c + 1.596 * e)};
}
}  // namespace

TEST(V4l2Formats, YuyvAndUyvyToBgrWithStride) {
  // 4x2 pixels, 8 data bytes per row plus 4 bytes of padding (bytesperline 12).
  const int w = 4, h = 2, bpl = 12;
  // Per pixel pair (Y0, Y1, U, V): red, green, blue, grey-ish.
  const int pairs[4][4] = {{82, 82, 90, 240}, {145, 160, 54, 34}, {41, 41, 240, 110}, {16, 235, 128, 128}};
  std::vector<std::uint8_t> yuyv(bpl * h, 0xAB), uyvy(bpl * h, 0xCD);
  for (int row = 0; row < h; ++row)
    for (int p = 0; p < 2; ++p) {
      const int* q = pairs[row * 2 + p];
      std::uint8_t* a = &yuyv[row * bpl + p * 4];
      a[0] = q[0], a[1] = q[2], a[2] = q[1], a[3] = q[3];  // Y0 U Y1 V
      std::uint8_t* b = &uyvy[row * bpl + p * 4];
      b[0] = q[2], b[1] = q[0], b[2] = q[3], b[3] = q[1];  // U Y0 V Y1
    }
  for (std::uint32_t fourcc : {V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_UYVY}) {
    const std::vector<std::uint8_t>& data = fourcc == V4L2_PIX_FMT_YUYV ? yuyv : uyvy;
    std::vector<std::uint8_t> out(w * h * 3);
    cv::Mat dst(h, w, CV_8UC3, out.data());
    std::string error;
    ASSERT_TRUE(sv::convertV4l2Frame(fourcc, data.data(), data.size(), w, h, bpl, dst, error)) << error;
    EXPECT_EQ(dst.data, out.data());
    for (int row = 0; row < h; ++row)
      for (int x = 0; x < w; ++x) {
        const int* q = pairs[row * 2 + x / 2];
        const cv::Vec3b want = yuvToBgr601(x % 2 ? q[1] : q[0], q[2], q[3]);
        const cv::Vec3b got = dst.at<cv::Vec3b>(row, x);
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(got[c], want[c], 3)
              << sv::v4l2FourccName(fourcc) << " pixel " << x << "," << row << " channel " << c;
      }
    // The first pair is red, Y 16/235 are black/white.
    EXPECT_GT(dst.at<cv::Vec3b>(0, 0)[2], 240);
    EXPECT_LT(dst.at<cv::Vec3b>(0, 0)[1], 10);
    EXPECT_LT(dst.at<cv::Vec3b>(1, 2)[0], 3);
    EXPECT_GT(dst.at<cv::Vec3b>(1, 3)[0], 252);
    // Truncated buffer: an error, not a read past the end.
    EXPECT_FALSE(sv::convertV4l2Frame(fourcc, data.data(), bpl + 4, w, h, bpl, dst, error));
    EXPECT_NE(error.find("truncated"), std::string::npos) << error;
  }
}

TEST(V4l2Formats, BayerCopiedAsBayerAndDemosaicsRight) {
  // A uniform red scene seen through an RGGB mosaic: R sites 200, G and B sites 10.
  const int w = 8, h = 6, bpl = 10;
  std::vector<std::uint8_t> raw(bpl * h, 0xEE);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) raw[y * bpl + x] = (y % 2 == 0 && x % 2 == 0) ? 200 : 10;
  std::vector<std::uint8_t> out(w * h);
  cv::Mat dst(h, w, CV_8UC1, out.data());
  std::string error;
  ASSERT_TRUE(sv::convertV4l2Frame(V4L2_PIX_FMT_SRGGB8, raw.data(), raw.size(), w, h, bpl, dst, error))
      << error;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) ASSERT_EQ(dst.at<std::uint8_t>(y, x), raw[y * bpl + x]);
  const std::string encoding = sv::v4l2Encoding(V4L2_PIX_FMT_SRGGB8);
  cv::Mat bgr;
  cv::cvtColor(dst, bgr, sv::bayerToBgrCode(encoding));
  const cv::Vec3b centre = bgr.at<cv::Vec3b>(3, 4);
  EXPECT_NEAR(centre[2], 200, 2);  // red
  EXPECT_NEAR(centre[1], 10, 2);
  EXPECT_NEAR(centre[0], 10, 2);
  // The same bytes declared BGGR would put the red into blue: the layout matters.
  cv::cvtColor(dst, bgr, sv::bayerToBgrCode(sv::v4l2Encoding(V4L2_PIX_FMT_SBGGR8)));
  EXPECT_NEAR(bgr.at<cv::Vec3b>(3, 4)[0], 200, 2);
}

TEST(V4l2Formats, RgbMjpegAndCorruptFrames) {
  const int w = 16, h = 8;
  cv::Mat bgr(h, w, CV_8UC3);
  cv::randu(bgr, 0, 255);
  cv::GaussianBlur(bgr, bgr, cv::Size(5, 5), 0);  // JPEG-friendly
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  std::vector<std::uint8_t> out(w * h * 3);
  cv::Mat dst(h, w, CV_8UC3, out.data());
  std::string error;
  ASSERT_TRUE(sv::convertV4l2Frame(V4L2_PIX_FMT_RGB24, rgb.data, rgb.total() * 3, w, h, w * 3, dst, error));
  EXPECT_EQ(cv::norm(dst, bgr, cv::NORM_INF), 0);

  std::vector<std::uint8_t> jpeg;
  ASSERT_TRUE(cv::imencode(".jpg", bgr, jpeg, {cv::IMWRITE_JPEG_QUALITY, 95}));
  dst.setTo(0);
  ASSERT_TRUE(sv::convertV4l2Frame(V4L2_PIX_FMT_MJPEG, jpeg.data(), jpeg.size(), w, h, 0, dst, error))
      << error;
  EXPECT_EQ(dst.data, out.data());
  EXPECT_LT(cv::norm(dst, bgr, cv::NORM_L1) / (w * h * 3), 6.0);

  std::vector<std::uint8_t> corrupt(jpeg.begin(), jpeg.begin() + 20);
  EXPECT_FALSE(sv::convertV4l2Frame(V4L2_PIX_FMT_MJPEG, corrupt.data(), corrupt.size(), w, h, 0, dst, error));
  EXPECT_NE(error.find("MJPEG"), std::string::npos) << error;
  cv::Mat wrong_size(h / 2, w, CV_8UC3);
  EXPECT_FALSE(
      sv::convertV4l2Frame(V4L2_PIX_FMT_MJPEG, jpeg.data(), jpeg.size(), w, h / 2, 0, wrong_size, error));
}

TEST(V4l2Formats, MonotonicStampsOnTheWallClock) {
  // A frame captured 0.25 s before "now" on the monotonic clock.
  EXPECT_DOUBLE_EQ(sv::monotonicToWall(1000.0, 1000.25, 1.8e9), 1.8e9 - 0.25);
}

// ---------------------------------------------------------------------------------------
// V4L2: devices that are not there.

TEST(V4l2Source, MissingDeviceIsAClearErrorEveryTime) {
  sv::V4l2Source source;
  sv::FrameSourceOptions o;
  o.settings["device"] = "/dev/video99";
  for (int attempt = 0; attempt < 3; ++attempt) {  // what the driver's retry loop does
    const sv::OpenResult r = source.open(o);
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("/dev/video99"), std::string::npos) << r.error;
    EXPECT_NE(r.error.find("No such file"), std::string::npos) << r.error;
    EXPECT_FALSE(source.isOpen());
  }
  cv::Mat image(4, 4, CV_8UC3);
  sv::FrameInfo info;
  std::string error;
  EXPECT_EQ(source.grab(image, info, 0.1, error), sv::GrabStatus::Error);
  EXPECT_FALSE(error.empty());
  EXPECT_FALSE(source.format().valid());
}

TEST(V4l2Source, NotAV4l2Device) {
  sv::V4l2Source source;
  sv::FrameSourceOptions o;
  o.settings["device"] = "/dev/null";  // a character device without V4L2
  sv::OpenResult r = source.open(o);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("not a V4L2 device"), std::string::npos) << r.error;
  const std::string dir = makeTempDir("v4l2");
  const std::string file = dir + "/not_a_device";
  std::ofstream(file) << "plain file";
  o.settings["device"] = file;
  r = source.open(o);
  std::system(("rm -rf '" + dir + "'").c_str());
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("is not a device"), std::string::npos) << r.error;
  o.settings["pixel_format"] = "H264";
  r = source.open(o);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("H264"), std::string::npos) << r.error;
}
