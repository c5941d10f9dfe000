#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/tracking/global_search_policy.h"
#include "soccer_vision/tracking/search_windows.h"
#include "soccer_vision/tracking/tracker.h"

using namespace soccer_vision;

namespace {

constexpr double kT0 = 1700000000.0;

bool contains(const cv::Rect& r, const Eigen::Vector2d& p) {
  return p.x() >= r.x && p.x() <= r.x + r.width - 1 && p.y() >= r.y && p.y() <= r.y + r.height - 1;
}

const SearchWindow* windowOf(const std::vector<SearchWindow>& windows, SearchWindow::Target target) {
  for (const auto& w : windows) {
    if (w.target == target) return &w;
  }
  return nullptr;
}

struct TrackedRun {
  Tracker tracker;
  double next_stamp = 0;
  Eigen::Vector2d next_truth{0, 0};
};

// A robot (or ball) moving in a straight line at `v`, measured with noise every `interval`
// for `frames` frames; the prediction is for frame `frames`.
void drive(TrackedRun& run, bool is_ball, const Eigen::Vector2d& start, const Eigen::Vector2d& v,
           double interval, int frames) {
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.004);
  for (int k = 0; k < frames; ++k) {
    const Eigen::Vector2d p = start + v * (k * interval);
    CameraFrameDetections f;
    f.stamp = kT0 + k * interval;
    f.camera_id = 0;
    if (is_ball) {
      BallDetection b;
      b.x = p.x() + noise(rng);
      b.y = p.y() + noise(rng);
      b.confidence = 0.9;
      f.balls.push_back(b);
    } else {
      RobotDetection r;
      r.team = Team::Yellow;
      r.id = 2;
      r.x = p.x() + noise(rng);
      r.y = p.y() + noise(rng);
      r.theta = std::atan2(v.y(), v.x());
      r.confidence = 0.9;
      f.robots.push_back(r);
    }
    run.tracker.update(f);
  }
  run.next_stamp = kT0 + frames * interval;
  run.next_truth = start + v * (frames * interval);
}

struct Case {
  bool ball;
  double speed;    // m/s
  int frame_step;  // at 60 Hz
};

class NextPositionInWindow : public ::testing::TestWithParam<Case> {};

}  // namespace

TEST_P(NextPositionInWindow, ContainsTheTrueNextPosition) {
  const Case c = GetParam();
  const FieldGeometry field;
  const auto camera = CameraModel::defaultCamera(field, 0);
  const double interval = c.frame_step / 60.0;
  const Eigen::Vector2d direction(0.6, 0.8);
  // Enough frames to converge, all inside camera 0's view (x in [-4.8, 0.3]).
  const double path = 5.0;
  const int frames = std::min(30, static_cast<int>(path / (c.speed * interval)));
  TrackedRun run;
  drive(run, c.ball, {-4.4, -3.0}, direction * c.speed, interval, frames);
  const auto windows = searchWindows(run.tracker.predictions(run.next_stamp), camera, interval);
  const auto* w = windowOf(windows, c.ball ? SearchWindow::Target::Ball : SearchWindow::Target::Robot);
  ASSERT_NE(w, nullptr);
  const double height = c.ball ? 0.0215 : 0.150;
  const auto truth = camera.project({run.next_truth.x(), run.next_truth.y(), height});
  ASSERT_TRUE(truth && camera.inImage(*truth));
  const double travel_px = c.speed * interval / 0.005;  // ~5 mm per pixel
  std::printf(
      "%s at %.0f m/s, %.0f Hz (%d frames): window %dx%d, true position %.1f px from "
      "its centre (one frame of travel: %.0f px)\n",
      c.ball ? "ball" : "robot", c.speed, 60.0 / c.frame_step, frames, w->rect.width, w->rect.height,
      (*truth - w->centre).norm(), travel_px);
  EXPECT_TRUE(contains(w->rect, *truth));
  EXPECT_TRUE(w->expected);
  // The window follows the prediction, not the last position.
  EXPECT_LT((*truth - w->centre).norm(), 10.0);
  EXPECT_GE(w->rect.width, 200);
  EXPECT_LE(w->rect.width, 800);
}

INSTANTIATE_TEST_SUITE_P(Speeds, NextPositionInWindow,
                         ::testing::Values(Case{false, 5.0, 1}, Case{false, 5.0, 4}, Case{true, 15.0, 1},
                                           Case{true, 15.0, 4}));

TEST(SearchWindows, ClippedAtTheImageBorderAndDroppedOutsideIt) {
  const FieldGeometry field;
  const auto cam0 = CameraModel::defaultCamera(field, 0);
  TrackerOutput out;
  TrackedRobot edge, far;
  edge.track_id = 1;
  edge.x = -4.78;  // at the end of the carpet: the window hangs over the image border
  edge.y = 0.0;
  far.track_id = 2;
  far.x = 3.0;  // in camera 1's half
  out.robots = {edge, far};
  const auto windows = searchWindows(out, cam0, 1.0 / 60);
  ASSERT_EQ(windows.size(), 1u);
  const cv::Rect& r = windows[0].rect;
  EXPECT_EQ(windows[0].track_id, 1);
  EXPECT_GE(r.x, 0);
  EXPECT_GE(r.y, 0);
  EXPECT_LE(r.x + r.width, cam0.width());
  EXPECT_LE(r.y + r.height, cam0.height());
  EXPECT_LT(r.height, 200);  // clipped
  const auto cam1 = CameraModel::defaultCamera(field, 1);
  const auto windows1 = searchWindows(out, cam1, 1.0 / 60);
  ASSERT_EQ(windows1.size(), 1u);
  EXPECT_EQ(windows1[0].track_id, 2);
  EXPECT_EQ(windows1[0].rect.width, 200);  // unclipped: R, no uncertainty to add
  EXPECT_TRUE(windows1[0].expected);
}

TEST(SearchWindows, GrowWithUncertaintyAndBallSpeed) {
  const FieldGeometry field;
  const auto camera = CameraModel::defaultCamera(field, 0);
  TrackedRun run;
  drive(run, false, {-2.0, 0.0}, {1.0, 0.0}, 1.0 / 60, 30);
  const auto fresh = searchWindows(run.tracker.predictions(run.next_stamp), camera, 1.0 / 60);
  const auto stale = searchWindows(run.tracker.predictions(run.next_stamp + 0.4), camera, 1.0 / 60);
  ASSERT_EQ(fresh.size(), 1u);
  ASSERT_EQ(stale.size(), 1u);
  EXPECT_GT(stale[0].rect.width, fresh[0].rect.width + 20);

  TrackerOutput balls;
  TrackedBall slow, fast;
  slow.primary = true;
  slow.x = fast.x = -2.0;
  slow.vx = 0.5;
  fast.vx = 15.0;
  balls.balls = {slow};
  const auto w_slow = searchWindows(balls, camera, 4.0 / 60);
  balls.balls = {fast};
  const auto w_fast = searchWindows(balls, camera, 4.0 / 60);
  ASSERT_EQ(w_slow.size(), 1u);
  ASSERT_EQ(w_fast.size(), 1u);
  // Half of one 15 Hz frame's travel (0.5 m) on each side: ~100 px more per side.
  EXPECT_GT(w_fast[0].rect.width, w_slow[0].rect.width + 150);
  EXPECT_LE(w_fast[0].rect.width, 800);
  SearchWindowParams bad;
  bad.side_px = 0;
  EXPECT_THROW(searchWindows(balls, camera, 0.1, bad), std::invalid_argument);
}

TEST(SearchWindows, GlobalSearchWhenATargetExpectedInThisCameraIsMissing) {
  const FieldGeometry field;
  const auto cam0 = CameraModel::defaultCamera(field, 0);
  Tracker tracker;
  GlobalSearchPolicy policy({1000});  // no periodic search in this test
  auto frame = [](int k, bool with_left, bool with_right) {
    CameraFrameDetections f;
    f.stamp = kT0 + k / 60.0;
    f.camera_id = 0;
    RobotDetection left, right;
    left.team = right.team = Team::Blue;
    left.id = 0;
    left.x = -2.0;  // in camera 0's view
    right.id = 1;
    right.x = 3.0;  // in camera 1's half: camera 0 is not expected to see it
    left.confidence = right.confidence = 0.9;
    if (with_left) f.robots.push_back(left);
    if (with_right) f.robots.push_back(right);
    return f;
  };
  auto step = [&](int k, bool with_left) {
    policy.observe(tracker.update(frame(k, with_left, k == 0)));
    const auto windows = searchWindows(tracker.predictions(kT0 + (k + 1) / 60.0), cam0, 1.0 / 60);
    return policy.decide(windows, tracker.numRobotTracks() + tracker.numBallTracks());
  };
  EXPECT_EQ(step(0, true), GlobalSearchReason::First);
  for (int k = 1; k < 10; ++k)
    EXPECT_EQ(step(k, true), GlobalSearchReason::None) << k;      // blue 1 unseen: fine
  EXPECT_EQ(step(10, false), GlobalSearchReason::TargetMissing);  // blue 0 missed in its window
  EXPECT_EQ(step(11, true), GlobalSearchReason::None);
  ASSERT_EQ(tracker.numRobotTracks(), 2u);
}

// Entry bands cover exactly the pixels within band_px of the image border, once each.
TEST(EntryBands, CoverTheBorderOnce) {
  const cv::Size image(1280, 1024);
  const auto bands = entryBands(image, 48);
  ASSERT_EQ(bands.size(), 4u);
  cv::Mat1b count(image, 0);
  for (const cv::Rect& b : bands) {
    ASSERT_EQ(b & cv::Rect(cv::Point(0, 0), image), b);
    count(b) += 1;
  }
  EXPECT_EQ(cv::countNonZero(count > 1), 0);
  EXPECT_EQ(cv::countNonZero(count), 1280 * 1024 - (1280 - 96) * (1024 - 96));
  EXPECT_EQ(count(0, 640), 1);
  EXPECT_EQ(count(500, 1279), 1);
  EXPECT_EQ(count(500, 640), 0);
  EXPECT_TRUE(entryBands(image, 0).empty());
  EXPECT_EQ(entryBands(cv::Size(10, 6), 48).size(), 2u);  // bands cut to half the image
}

// A robot's window is centred where its team's marker plane puts it: a yellow robot 0.10 m
// high 2.6 m from the nadir is ~4 cm (7 px) from where the blue team's 0.15 m plane would
// put it.
TEST(SearchWindows, CentredAtEachTeamsMarkerPlane) {
  const FieldGeometry field;
  const CameraModel camera = CameraModel::defaultCamera(field, 0);
  TrackerOutput predicted;
  for (const Team team : {Team::Blue, Team::Yellow}) {
    TrackedRobot r;
    r.team = team;
    r.x = -2.25;
    r.y = 2.6;
    predicted.robots.push_back(r);
  }
  SearchWindowParams params;
  params.robot_height = {0.15, 0.10};
  const auto windows = searchWindows(predicted, camera, 1.0 / 60, params);
  ASSERT_EQ(windows.size(), 2u);
  for (const SearchWindow& w : windows) {
    const double h = w.team == Team::Blue ? 0.15 : 0.10;
    EXPECT_LT((w.centre - *camera.project({-2.25, 2.6, h})).norm(), 1e-9) << teamName(w.team);
  }
  EXPECT_GT((windows[0].centre - windows[1].centre).norm(), 5.0);
}

TEST(SquareAbout, PixelCentresWithinHalfOfThePointClippedToTheImage) {
  const cv::Size image(640, 480);
  // Pixel centres x in [300.3 - 100, 300.3 + 100): 201 .. 400, whatever the fraction.
  EXPECT_EQ(squareAbout({300.3, 200.7}, 100, image), cv::Rect(201, 101, 200, 200));
  EXPECT_EQ(squareAbout({300.5, 200.5}, 100, image), cv::Rect(201, 101, 200, 200));
  EXPECT_EQ(squareAbout({300.0, 200.0}, 100, image), cv::Rect(200, 100, 200, 200));
  EXPECT_EQ(squareAbout({10, 470}, 100, image), cv::Rect(0, 370, 110, 110));
  EXPECT_EQ(squareAbout({-99.5, 240}, 100, image), cv::Rect(0, 140, 1, 200));
  EXPECT_FALSE(squareAbout({-100, 240}, 100, image));  // [-200, 0): no pixel of the image
  EXPECT_FALSE(squareAbout({740, 240}, 100, image));
  // Far beyond the image or not a number: none, and no integer overflow on the way.
  EXPECT_FALSE(squareAbout({1e30, 240}, 100, image));
  EXPECT_FALSE(squareAbout({-1e30, -1e30}, 100, image));
  EXPECT_FALSE(squareAbout({std::nan(""), 240}, 100, image));
  EXPECT_FALSE(squareAbout({320, 240}, std::numeric_limits<double>::infinity(), image));
}
