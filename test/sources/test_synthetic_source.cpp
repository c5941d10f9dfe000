// The synthetic source: its scenario's camera layout, and the replay of frames rendered once.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "soccer_vision/sources/frame_source.h"
#include "soccer_vision/sources/synthetic_source.h"

namespace sv = soccer_vision;

namespace {

std::unique_ptr<sv::FrameSource> syntheticSource() {
  std::string error;
  auto source = sv::createFrameSource("synthetic", error);
  EXPECT_TRUE(source) << error;
  return source;
}

sv::FrameSourceOptions smallFastMotion(const std::string& replay_frames) {
  sv::FrameSourceOptions o;
  o.scenario = std::string(SOCCER_VISION_SOURCE_DIR) + "/config/scenarios/fast_motion.yaml";
  o.width = 320;
  o.height = 256;
  o.fps = 100;
  if (!replay_frames.empty()) o.settings["replay_frames"] = replay_frames;
  return o;
}

}  // namespace

TEST(SyntheticSource, OpensTheCamerasOfItsScenariosLayout) {
  auto source = syntheticSource();
  ASSERT_TRUE(source);
  sv::FrameSourceOptions o;
  o.scenario = std::string(SOCCER_VISION_SOURCE_DIR) + "/config/scenarios/div_a_four_cameras.yaml";
  o.width = 320;
  o.height = 256;
  o.camera_index = 3;
  const sv::OpenResult last = source->open(o);
  EXPECT_TRUE(last.ok) << last.error;
  source->close();
  o.camera_index = 4;
  const sv::OpenResult beyond = source->open(o);
  EXPECT_FALSE(beyond.ok);
  EXPECT_NE(beyond.error.find("has cameras 0..3, not 4"), std::string::npos) << beyond.error;
  o.scenario.clear();  // the embedded default: Division B's two cameras
  o.camera_index = 2;
  EXPECT_FALSE(source->open(o).ok);
}

// Frames 0..3 rendered once, then shown 0 1 2 3 2 1 0 1 ... by the absolute index: the same
// bytes and truth whenever the same frame comes back, the velocities reversed on the way back.
TEST(SyntheticSource, ReplaysItsRenderedFramesForthAndBack) {
  auto source = syntheticSource();
  ASSERT_TRUE(source);
  const sv::OpenResult opened = source->open(smallFastMotion("4"));
  ASSERT_TRUE(opened.ok) << opened.error;
  const sv::FrameFormat f = source->format();
  std::map<int, cv::Mat> shown;  // replay frame -> its first image
  std::map<int, sv::SceneState> truth;
  int returns = 0, backwards = 0;
  std::uint64_t last_sequence = 0;
  for (int k = 0; k < 14; ++k) {
    cv::Mat image(f.height, f.width, f.cv_type);
    sv::FrameInfo info;
    std::string error;
    sv::GrabStatus status = sv::GrabStatus::Timeout;
    while (status == sv::GrabStatus::Timeout) status = source->grab(image, info, 60.0, error);
    ASSERT_EQ(status, sv::GrabStatus::Ok) << error;
    ASSERT_TRUE(info.ground_truth);
    if (k > 0) {
      EXPECT_GT(info.sequence, last_sequence);
    }
    last_sequence = info.sequence;
    const int m = static_cast<int>(info.sequence % 6);
    const int p = m < 4 ? m : 6 - m;
    const sv::SceneState& scene = *info.ground_truth;
    EXPECT_NEAR(scene.time, p / 100.0, 1e-9);
    // The truth as on the way forth (the game's own velocities).
    sv::SceneState forth = scene;
    const bool back = m >= 4;
    for (sv::RobotState& r : forth.robots) r.vx = back ? -r.vx : r.vx;
    if (shown.count(p) == 0) {
      shown[p] = image;
      truth[p] = forth;
      continue;
    }
    ++returns;
    backwards += back;
    EXPECT_EQ(cv::norm(image, shown[p], cv::NORM_INF), 0)
        << "frame " << p << " at sequence " << info.sequence;
    ASSERT_EQ(forth.robots.size(), truth[p].robots.size());
    for (std::size_t i = 0; i < forth.robots.size(); ++i) {
      EXPECT_EQ(forth.robots[i].x, truth[p].robots[i].x);
      EXPECT_EQ(forth.robots[i].vx, truth[p].robots[i].vx);
    }
  }
  EXPECT_GE(returns, 6);
  EXPECT_GE(backwards, 2);
  EXPECT_GT(cv::norm(shown[0], shown[3], cv::NORM_L1), 0) << "the replayed frames are not all the same";
}

TEST(SyntheticSource, RefusesAReplayThatIsNotAWholeNumberOfFramesOrDoesNotFit) {
  auto source = syntheticSource();
  ASSERT_TRUE(source);
  for (const char* bad : {"1", "2.5", "-3", "many", "nan"}) {
    const sv::OpenResult r = source->open(smallFastMotion(bad));
    EXPECT_FALSE(r.ok) << bad;
    EXPECT_NE(r.error.find("replay_frames"), std::string::npos) << bad << ": " << r.error;
  }
  // 320x256 bgr8 is 240 KiB a frame: 40000 frames are 9.2 GiB.
  const sv::OpenResult too_many = source->open(smallFastMotion("40000"));
  EXPECT_FALSE(too_many.ok);
  EXPECT_NE(too_many.error.find("MiB"), std::string::npos) << too_many.error;
  EXPECT_TRUE(source->open(smallFastMotion("0")).ok);
}
