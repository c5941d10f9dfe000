#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "soccer_vision/common/angle.h"
#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/tracking/frame_step.h"
#include "soccer_vision/tracking/global_search_policy.h"
#include "soccer_vision/tracking/tracker.h"
#include "support/scene_objects.h"

using namespace soccer_vision;

namespace {

constexpr double kDt = 1.0 / 60;
constexpr double kT0 = 1700000000.0;

RobotDetection robot(Team team, int id, double x, double y, double theta = 0.0) {
  return test::robotDetection(team, id, x, y, theta);
}

BallDetection ball(double x, double y, double confidence = 0.8) {
  BallDetection b;
  b.x = x;
  b.y = y;
  b.confidence = confidence;
  return b;
}

CameraFrameDetections frame(double stamp, int camera, std::vector<RobotDetection> robots,
                            std::vector<BallDetection> balls = {}) {
  CameraFrameDetections f;
  f.stamp = stamp;
  f.camera_id = camera;
  f.robots = std::move(robots);
  f.balls = std::move(balls);
  return f;
}

const TrackedRobot* find(const TrackerOutput& out, Team team, int id) {
  for (const auto& r : out.robots) {
    if (r.team == team && r.id == id) return &r;
  }
  return nullptr;
}

}  // namespace

// ---------------------------------------------------------------- timeline

TEST(TrackerTimeline, OrdersFusesDropsAndResets) {
  TrackerTimeline t;
  EXPECT_EQ(t.accept(10.0, 0).event, TimeEvent::Start);
  auto d = t.accept(10.0 + kDt, 0);
  EXPECT_EQ(d.event, TimeEvent::InOrder);
  EXPECT_NEAR(d.dt, kDt, 1e-12);
  d = t.accept(10.0 + kDt - 0.005, 1);  // the other camera, 5 ms behind
  EXPECT_EQ(d.event, TimeEvent::SameTime);
  EXPECT_NEAR(d.lag, 0.005, 1e-12);
  EXPECT_NEAR(t.now(), 10.0 + kDt, 1e-12);  // never moved back
  d = t.accept(10.0 + kDt - 0.05, 2);       // a camera 50 ms behind (held up): fused
  EXPECT_EQ(d.event, TimeEvent::SameTime);
  EXPECT_NEAR(d.lag, 0.05, 1e-12);
  EXPECT_EQ(t.accept(10.0 + kDt - 0.15, 3).event, TimeEvent::Late);  // 150 ms behind: dropped
  EXPECT_EQ(t.resets(), 0);
  EXPECT_EQ(t.accept(10.0, 0).action, TimeAction::Reset);  // camera 0 went back: looped
  EXPECT_EQ(t.resets(), 1);
  EXPECT_EQ(t.accept(12.0, 0).event, TimeEvent::ForwardJump);
  EXPECT_EQ(t.resets(), 2);
  EXPECT_EQ(t.accept(NAN, 0).event, TimeEvent::InvalidStamp);
  EXPECT_NEAR(t.now(), 12.0, 1e-12);
}

TEST(TrackerTimeline, LoopedTwoCameraBagResetsOnce) {
  TrackerTimeline t;
  for (int k = 0; k < 100; ++k) {
    t.accept(kT0 + k * kDt, 0);
    t.accept(kT0 + k * kDt, 1);
  }
  // The bag loops: camera 0's first frame of the new loop arrives before camera 1's last
  // frames of the old one.
  EXPECT_EQ(t.accept(kT0, 0).event, TimeEvent::BackwardJump);
  EXPECT_EQ(t.accept(kT0 + 99 * kDt, 1).event, TimeEvent::Stale);
  EXPECT_EQ(t.accept(kT0 + kDt, 0).event, TimeEvent::InOrder);
  EXPECT_EQ(t.accept(kT0, 1).event, TimeEvent::SameTime);  // camera 1 joins the new loop
  EXPECT_EQ(t.accept(kT0 + kDt, 1).event, TimeEvent::SameTime);
  EXPECT_EQ(t.accept(kT0 + 2 * kDt, 1).event, TimeEvent::InOrder);
  EXPECT_EQ(t.resets(), 1);
}

// ---------------------------------------------------------------- tracker

TEST(Tracker, BackwardAndForwardJumpsResetCleanly) {
  Tracker tracker;
  for (int k = 0; k < 30; ++k) {
    const double x = 1.0 + 2.0 * k * kDt;
    tracker.update(frame(kT0 + k * kDt, 0, {robot(Team::Blue, 1, x, 0.0), robot(Team::Yellow, 2, -1, -1)},
                         {ball(0.3, 0.2)}));
  }
  ASSERT_EQ(tracker.numRobotTracks(), 2u);
  const auto before = tracker.output();
  ASSERT_NE(before.primaryBall(), nullptr);
  EXPECT_NEAR(find(before, Team::Blue, 1)->vx, 2.0, 0.05);

  // Looped bag: back to the first stamp, only blue 3 in view.
  auto report = tracker.update(frame(kT0, 0, {robot(Team::Blue, 3, -2.0, 1.0)}));
  EXPECT_TRUE(report.reset());
  EXPECT_EQ(report.time.event, TimeEvent::BackwardJump);
  auto out = tracker.output();
  ASSERT_EQ(out.robots.size(), 1u);  // the old tracks are gone, nothing carried over
  EXPECT_EQ(out.robots[0].id, 3);
  EXPECT_DOUBLE_EQ(out.robots[0].x, -2.0);
  EXPECT_DOUBLE_EQ(out.robots[0].vx, 0.0);
  EXPECT_TRUE(out.balls.empty());
  EXPECT_DOUBLE_EQ(tracker.time(), kT0);

  // Large forward jump (5 s): reset again, the new frame's robot starts fresh.
  report = tracker.update(frame(kT0 + 5.0, 0, {robot(Team::Blue, 3, 2.0, 1.0)}));
  EXPECT_EQ(report.time.event, TimeEvent::ForwardJump);
  out = tracker.output();
  ASSERT_EQ(out.robots.size(), 1u);
  EXPECT_DOUBLE_EQ(out.robots[0].x, 2.0);
  EXPECT_DOUBLE_EQ(out.robots[0].vx, 0.0);  // not the 0.8 m/s a jump would suggest
  EXPECT_EQ(tracker.stats().resets, 2);
}

TEST(Tracker, TwoCamerasInTheOverlapGiveOneTrack) {
  Tracker tracker;
  // Robots and ball in the overlap (|x| < 0.3 m), seen by both cameras with a 1 cm
  // calibration mismatch; team-only robots too.
  for (int k = 0; k < 120; ++k) {
    const double t = kT0 + k * kDt, y = -1.0 + 1.0 * k * kDt;
    for (int cam = 0; cam < 2; ++cam) {
      const double bias = cam == 0 ? -0.005 : 0.005;
      tracker.update(
          frame(t, cam,
                {robot(Team::Blue, 4, 0.1 + bias, y, 1.0), robot(Team::Yellow, -1, -0.1 + bias, -y),
                 robot(Team::Yellow, -1, 0.2 + bias, 0.5)},
                {ball(0.0 + bias, y + 0.3)}));
    }
  }
  const auto out = tracker.output();
  EXPECT_EQ(out.robots.size(), 3u);
  EXPECT_EQ(out.balls.size(), 1u);
  EXPECT_EQ(tracker.stats().tracks_created, 4);
  EXPECT_EQ(tracker.stats().robot_outliers, 0);
  const auto* blue = find(out, Team::Blue, 4);
  ASSERT_NE(blue, nullptr);
  EXPECT_NEAR(blue->x, 0.1, 0.002);  // the average of both cameras
  EXPECT_NEAR(blue->vy, 1.0, 0.05);
  EXPECT_EQ(blue->camera_id, 1);  // the last measurement came from camera 1
  EXPECT_TRUE(blue->visible);
}

TEST(Tracker, CamerasAFewMillisecondsApartAreFusedWithoutLag) {
  // Camera 1 captures 6 ms before camera 0 but its frames are processed after camera 0's:
  // its positions are moved forward by the velocity, so fusing them adds no lag error.
  Tracker tracker;
  const double v = 3.0, skew = 0.006;
  double worst = 0;
  for (int k = 0; k < 120; ++k) {
    const double t0 = kT0 + k * kDt, t1 = t0 - skew;
    tracker.update(frame(t0, 0, {robot(Team::Blue, 0, -0.2 + v * (t0 - kT0), 0.0)}));
    const auto r1 = tracker.update(frame(t1, 1, {robot(Team::Blue, 0, -0.2 + v * (t1 - kT0), 0.0)}));
    ASSERT_TRUE(r1.processed());
    if (k > 30) {
      EXPECT_EQ(r1.time.event, TimeEvent::SameTime);
      const auto out = tracker.output(t0);
      const auto* r = find(out, Team::Blue, 0);
      ASSERT_NE(r, nullptr);
      worst = std::max(worst, std::abs(r->x - (-0.2 + v * (t0 - kT0))));
    }
  }
  EXPECT_LT(worst, 0.002);  // uncompensated fusion would be ~ v * skew / 2 = 9 mm off
  EXPECT_EQ(tracker.stats().dropped_frames, 0);
  EXPECT_EQ(tracker.stats().robot_outliers, 0);
}

TEST(Tracker, CameraHeldUpByABusyMachineIsFusedNotDropped) {
  // Two cameras see a robot with 2 mm of noise; camera 1's frames reach the tracker 3 frames
  // (50 ms) after camera 0's of the same time, as when its segmentation falls behind on a
  // loaded machine. They are fused and none is rejected. Driving straight at 2 m/s they make
  // the track better than camera 0 alone; on a 1 m circle at 2 m/s (4 m/s² the
  // constant-velocity model does not expect) a little worse.
  auto rms = [](bool straight, bool with_late_camera) {
    std::mt19937 rng(11);
    std::normal_distribution<double> noise(0.0, 0.002);
    auto truth = [&](double t) -> Eigen::Vector3d {
      const double a = 2.0 * (t - kT0);
      if (straight) return {-2.0 + a, 0.3, 0.0};
      return {std::cos(a), std::sin(a), wrapToPi(a + M_PI / 2)};
    };
    auto detection = [&](double t) {
      const Eigen::Vector3d g = truth(t);
      return robot(Team::Blue, 4, g.x() + noise(rng), g.y() + noise(rng), g.z());
    };
    Tracker tracker;
    double sq = 0;
    int n = 0;
    for (int k = 0; k < 600; ++k) {
      const double t0 = kT0 + k * kDt;
      tracker.update(frame(t0, 0, {detection(t0)}));
      if (with_late_camera && k >= 3) {
        const auto report = tracker.update(frame(t0 - 3 * kDt, 1, {detection(t0 - 3 * kDt)}));
        EXPECT_EQ(report.time.event, TimeEvent::SameTime);
        EXPECT_NEAR(report.time.lag, 3 * kDt, 1e-6);  // stamps near 1.7e9 s
      }
      if (k < 60) continue;
      const auto* r = find(tracker.output(t0), Team::Blue, 4);
      EXPECT_NE(r, nullptr);
      if (r == nullptr) continue;
      sq += std::pow(r->x - truth(t0).x(), 2) + std::pow(r->y - truth(t0).y(), 2);
      ++n;
    }
    EXPECT_EQ(tracker.stats().dropped_frames, 0);
    EXPECT_EQ(tracker.stats().robot_outliers, 0);
    return std::sqrt(sq / std::max(1, n));
  };
  const double line_alone = rms(true, false), line_fused = rms(true, true);
  const double circle_alone = rms(false, false), circle_fused = rms(false, true);
  std::printf(
      "RMS from camera 0 alone -> with camera 1 50 ms late: straight %.2f -> %.2f mm, circle %.2f -> %.2f "
      "mm\n",
      1e3 * line_alone, 1e3 * line_fused, 1e3 * circle_alone, 1e3 * circle_fused);
  EXPECT_LT(line_fused, 0.95 * line_alone);
  EXPECT_LT(circle_fused, 1.25 * circle_alone);
  EXPECT_LT(circle_fused, 0.0035);
}

TEST(Tracker, LostTargetIsDroppedAfterTheConfiguredTime) {
  TrackerParams p;
  p.robot_lost_timeout = 0.3;
  p.ball_lost_timeout = 0.2;
  Tracker tracker(p);
  // The tracks themselves (output() withholds coasting ones sooner: test_coasting.cpp).
  auto tracks = [&] { return tracker.predictions(tracker.time()); };
  for (int k = 0; k < 10; ++k) {
    tracker.update(
        frame(kT0 + k * kDt, 0, {robot(Team::Blue, 0, 0, 0), robot(Team::Blue, 1, 1, 0)}, {ball(0.5, 0.5)}));
  }
  const double last = kT0 + 9 * kDt;
  // Blue 1 and the ball vanish; blue 0 stays.
  int k = 10;
  for (; kT0 + k * kDt - last <= 0.19; ++k)
    tracker.update(frame(kT0 + k * kDt, 0, {robot(Team::Blue, 0, 0, 0)}));
  auto out = tracks();
  EXPECT_EQ(out.robots.size(), 2u);
  EXPECT_EQ(out.balls.size(), 1u);
  EXPECT_FALSE(find(out, Team::Blue, 1)->visible);
  EXPECT_LT(find(out, Team::Blue, 1)->confidence, 0.9 * 0.5);  // fading
  for (; kT0 + k * kDt - last <= 0.29; ++k)
    tracker.update(frame(kT0 + k * kDt, 0, {robot(Team::Blue, 0, 0, 0)}));
  out = tracks();
  EXPECT_EQ(out.robots.size(), 2u);  // 0.29 s: still there (predicted)
  EXPECT_TRUE(out.balls.empty());    // the ball's 0.2 s are over
  for (; kT0 + k * kDt - last <= 0.32; ++k)
    tracker.update(frame(kT0 + k * kDt, 0, {robot(Team::Blue, 0, 0, 0)}));
  out = tracks();
  ASSERT_EQ(out.robots.size(), 1u);
  EXPECT_EQ(out.robots[0].id, 0);
  EXPECT_EQ(tracker.stats().tracks_lost, 2);
}

TEST(Tracker, BallKickIsTrackedWithoutLosingTheTrack) {
  Tracker tracker;
  for (int k = 0; k < 60; ++k) tracker.update(frame(kT0 + k * kDt, 0, {}, {ball(1.0, 0.0)}));
  const auto before = tracker.output();
  ASSERT_NE(before.primaryBall(), nullptr);
  const int id = before.primaryBall()->track_id;
  const Eigen::Vector2d v(-12.0, 5.0);
  int kicks = 0;
  for (int k = 1; k <= 15; ++k) {
    const Eigen::Vector2d p = Eigen::Vector2d(1.0, 0.0) + v * k * kDt;
    // A stray orange blob far away competes as a second candidate.
    const auto report =
        tracker.update(frame(kT0 + (59 + k) * kDt, 0, {}, {ball(p.x(), p.y()), ball(-3.0, 2.0, 0.9)}));
    kicks += report.ball_kicks;
    const auto out = tracker.output();
    const auto* b = out.primaryBall();
    ASSERT_NE(b, nullptr);
    EXPECT_EQ(b->track_id, id) << "frame " << k;
    EXPECT_TRUE(b->visible);
    if (k >= 3) {
      EXPECT_LT(std::hypot(b->x - p.x(), b->y - p.y()), 0.01) << "frame " << k;
      EXPECT_LT(std::hypot(b->vx - v.x(), b->vy - v.y()), 1.0) << "frame " << k;
    }
  }
  EXPECT_GE(kicks, 1);
  EXPECT_EQ(tracker.output().balls.size(), 2u);  // the stray blob is an alternative, not the ball
}

// Held-out seed 9058's rand_bayer_ssl: the ball hidden beside a robot for two frames, and a
// Bayer fringe of 16 px on the centre circle, 0.46 m away, read as a ball at 0.08.
TEST(Tracker, AnUnsureCandidateBeyondTheGateIsNoKick) {
  for (const double confidence : {0.08, 0.9}) {
    Tracker tracker;
    for (int k = 0; k < 30; ++k) tracker.update(frame(kT0 + k * kDt, 0, {}, {ball(-0.40, -0.06)}));
    const int id = tracker.output().primaryBall()->track_id;
    tracker.update(frame(kT0 + 30 * kDt, 0, {}, {}));  // hidden
    const auto report = tracker.update(frame(kT0 + 31 * kDt, 0, {}, {ball(-0.17, -0.46, confidence)}));
    const auto out = tracker.output();
    const auto* b = out.primaryBall();
    if (confidence < tracker.params().ball_kick_min_confidence) {
      EXPECT_EQ(report.ball_kicks, 0);
      // The fringe begins no track either (ball_min_start_confidence); the ball, hidden, is
      // withheld.
      EXPECT_EQ(report.unsure_starts, 1);
      EXPECT_TRUE(out.balls.empty());
      // The ball seen again where it was is the ball it was.
      tracker.update(frame(kT0 + 32 * kDt, 0, {}, {ball(-0.40, -0.06), ball(-0.17, -0.46, confidence)}));
      const auto again = tracker.output();
      ASSERT_NE(again.primaryBall(), nullptr);
      EXPECT_EQ(again.primaryBall()->track_id, id);
      EXPECT_TRUE(again.primaryBall()->visible);
    } else {
      EXPECT_EQ(report.ball_kicks, 1);  // a sure one is the ball kicked there
      ASSERT_NE(b, nullptr);
      EXPECT_EQ(b->track_id, id);
      EXPECT_LT(std::hypot(b->x + 0.17, b->y + 0.46), 0.01);
    }
  }
}

// With the field known, a ball track's predictions bounce off the walls at the carpet's edge
// (4.8 m from the centre, less the ball's radius): the search windows look for the ball
// where it comes back. Without it, straight on beyond the wall.
TEST(Tracker, ABallUnseenAtTheWallIsPredictedBackOffIt) {
  for (const bool field : {true, false}) {
    TrackerParams p;
    if (field) p.field = FieldGeometry{};
    Tracker tracker(p);
    for (int k = 0; k <= 5; ++k)
      tracker.update(frame(kT0 + k * kDt, 0, {}, {ball(-4.45 - 3.0 * k * kDt, 1.5)}));
    // Seen last at x -4.70, 3 m/s towards the wall; 0.1 s later.
    const TrackerOutput later = tracker.predictions(kT0 + 11 * kDt);
    ASSERT_EQ(later.balls.size(), 1u);
    const TrackedBall& b = later.balls[0];
    if (field) {
      EXPECT_NEAR(b.x, -4.557, 0.02);  // 0.22 m off the wall at -4.7785
      EXPECT_GT(b.vx, 2.5);
    } else {
      EXPECT_NEAR(b.x, -5.0, 0.02);
      EXPECT_LT(b.vx, -2.5);
    }
    EXPECT_NEAR(b.y, 1.5, 0.01);
  }
}

// Held-out seed 9062's rand_bayer: while the ball was in the other camera's half, Bayer
// fringes where the lines meet read as balls at 0.06-0.11 and, no ball track being there,
// began the primary in 6 frames. An unsure candidate begins no ball track; it still
// measures one whose gate it lies in.
TEST(Tracker, AnUnsureBallCandidateBeginsNoTrack) {
  TrackerParams params;
  params.field = FieldGeometry{};
  Tracker tracker(params);
  int unsure = 0;
  for (int k = 0; k < 10; ++k)
    unsure += tracker.update(frame(kT0 + k * kDt, 0, {}, {ball(0.01, 2.97, 0.08)})).unsure_starts;
  EXPECT_EQ(unsure, 10);
  EXPECT_TRUE(tracker.output().balls.empty());
  EXPECT_TRUE(tracker.predictions(kT0 + 9 * kDt).balls.empty());
  // A sure one begins the ball; an unsure reading of it later measures it.
  tracker.update(frame(kT0 + 10 * kDt, 0, {}, {ball(1.0, 1.0, 0.6)}));
  const auto report = tracker.update(frame(kT0 + 11 * kDt, 0, {}, {ball(1.0, 1.0, 0.1)}));
  EXPECT_EQ(report.unsure_starts, 0);
  ASSERT_NE(tracker.output().primaryBall(), nullptr);
  EXPECT_TRUE(tracker.output().primaryBall()->visible);
  params.ball_min_start_confidence = -0.1;
  EXPECT_THROW(validate(params), std::invalid_argument);
}

TEST(Tracker, BallFallsBackToTheBestCandidateWithoutATrack) {
  Tracker tracker;
  tracker.update(frame(kT0, 0, {}, {ball(2.0, 1.0, 0.9), ball(-1.0, 0.0, 0.4)}));
  const auto out = tracker.output();
  ASSERT_NE(out.primaryBall(), nullptr);
  EXPECT_DOUBLE_EQ(out.primaryBall()->x, 2.0);
  EXPECT_EQ(out.balls.size(), 2u);
}

TEST(Tracker, TeamOnlyRobotsPassingCloseKeepTheirTracks) {
  Tracker tracker;
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.003);
  int id_a = -1, id_b = -1;
  for (int k = 0; k < 120; ++k) {
    const double t = k * kDt;
    // Two robots of one team pass each other 0.19 m apart at 2 m/s each.
    const double xa = -1.0 + 2.0 * t, xb = 1.0 - 2.0 * t;
    tracker.update(frame(kT0 + t, 0,
                         {robot(Team::Blue, -1, xb + noise(rng), 0.095 + noise(rng)),
                          robot(Team::Blue, -1, xa + noise(rng), -0.095 + noise(rng))}));
    const auto out = tracker.output();
    ASSERT_EQ(out.robots.size(), 2u) << "frame " << k;
    for (const auto& r : out.robots) {
      if (std::abs(r.y - (-0.095)) < 0.05) {
        if (id_a < 0) id_a = r.track_id;
        EXPECT_EQ(r.track_id, id_a) << "frame " << k;
        EXPECT_NEAR(r.x, xa, 0.01);
      } else {
        if (id_b < 0) id_b = r.track_id;
        EXPECT_EQ(r.track_id, id_b) << "frame " << k;
        EXPECT_NEAR(r.x, xb, 0.01);
      }
    }
  }
  EXPECT_NE(id_a, id_b);
  EXPECT_EQ(tracker.stats().tracks_created, 2);
}

TEST(Tracker, BadDetectionsAreCountedNotTracked) {
  Tracker tracker;
  auto f =
      frame(kT0, 0, {robot(Team::Blue, 0, NAN, 0), robot(Team::Blue, 1, 1, 1), robot(Team::Blue, 1, 1.02, 1)},
            {ball(INFINITY, 0)});
  const auto report = tracker.update(f);
  EXPECT_EQ(report.invalid_detections, 2);
  EXPECT_EQ(report.duplicate_detections, 1);
  EXPECT_EQ(tracker.numRobotTracks(), 1u);
  EXPECT_EQ(tracker.numBallTracks(), 0u);
  EXPECT_FALSE(tracker.update(frame(NAN, 0, {robot(Team::Blue, 2, 0, 0)})).processed());
  TrackerParams bad;
  bad.robot_lost_timeout = -1;
  EXPECT_THROW(Tracker{bad}, std::invalid_argument);
}

// Held-out seed 9029 of rand_bayer (spent): the quads of a white goal line read cyan and
// yellow, and a yellow strip of them beside a stray green-read carpet quad was "yellow 3",
// 7 m from that robot, at confidence 0.11-0.13 in 9 frames. An unsure detection begins no
// track (it is counted); it still measures the track of its robot, which a sure one began.
TEST(Tracker, AnUnsureDetectionBeginsNoTrackButMeasuresOne) {
  Tracker tracker;
  RobotDetection phantom = robot(Team::Yellow, 3, -3.95, -2.9);
  phantom.confidence = 0.12;
  int k = 0;
  for (; k < 3; ++k) {
    const TrackerUpdateReport report = tracker.update(frame(kT0 + k * kDt, 0, {phantom}));
    EXPECT_EQ(report.unsure_starts, 1);
    EXPECT_EQ(report.robots_created, 0);
  }
  EXPECT_FALSE(find(tracker.output(kT0 + (k - 1) * kDt), Team::Yellow, 3));
  EXPECT_EQ(tracker.stats().unsure_starts, 3);
  RobotDetection sure = robot(Team::Yellow, 3, 1, 1);
  sure.confidence = 0.9;
  EXPECT_EQ(tracker.update(frame(kT0 + k++ * kDt, 0, {sure})).robots_created, 1);
  RobotDetection unsure = robot(Team::Yellow, 3, 1.001, 1);
  unsure.confidence = 0.12;
  const TrackerUpdateReport report = tracker.update(frame(kT0 + k * kDt, 0, {unsure}));
  EXPECT_EQ(report.robots_measured, 1);
  EXPECT_EQ(report.unsure_starts, 0);
  ASSERT_TRUE(find(tracker.output(kT0 + k * kDt), Team::Yellow, 3));
  EXPECT_TRUE(find(tracker.output(kT0 + k * kDt), Team::Yellow, 3)->visible);
  // With min_start_confidence 0 it begins a track.
  TrackerParams any;
  any.min_start_confidence = 0;
  Tracker trusting(any);
  EXPECT_EQ(trusting.update(frame(kT0, 0, {phantom})).robots_created, 1);
  any.min_start_confidence = 1.5;
  EXPECT_THROW(Tracker{any}, std::invalid_argument);
}

// Held-out seed 9094's rand_flicker_jpeg: the ball, read partly yellow beside a sky-blue fleck,
// was "yellow 2" at 0.11 in one frame, 1 m from where the real yellow 2 had left the view
// 0.18 s before; its track took it as a velocity change (within 8 m/s x 0.2 s) and was
// output there.
TEST(Tracker, AnUnsureDetectionIsNoManoeuvreOfACoastingTrack) {
  Tracker tracker;
  int k = 0;
  for (; k < 60; ++k) tracker.update(frame(kT0 + k * kDt, 0, {robot(Team::Yellow, 2, 0.5, 0.4)}));
  for (int n = 0; n < 11; ++n, ++k) tracker.update(frame(kT0 + k * kDt, 0, {}));
  RobotDetection phantom = robot(Team::Yellow, 2, -0.13, -0.21);
  phantom.confidence = 0.11;
  const TrackerUpdateReport report = tracker.update(frame(kT0 + k * kDt, 0, {phantom}));
  EXPECT_EQ(report.robots_measured, 0);
  EXPECT_EQ(report.robot_maneuvers, 0);
  const TrackedRobot* r = find(tracker.predictions(kT0 + k * kDt), Team::Yellow, 2);
  ASSERT_NE(r, nullptr);
  EXPECT_FALSE(r->visible);
  EXPECT_LT(std::hypot(r->x - 0.5, r->y - 0.4), 0.01);  // still where it was last seen
  // A sure detection there is the robot, stopped dead: a velocity change.
  RobotDetection sure = phantom;
  sure.confidence = 0.9;
  ++k;
  EXPECT_EQ(tracker.update(frame(kT0 + k * kDt, 0, {sure})).robots_measured, 1);
  ASSERT_NE(find(tracker.output(kT0 + k * kDt), Team::Yellow, 2), nullptr);
  EXPECT_NEAR(find(tracker.output(kT0 + k * kDt), Team::Yellow, 2)->x, -0.13, 0.01);
}

// ---------------------------------------------------------------- search policy, frame_step

TEST(GlobalSearchPolicy, FiresFirstPeriodicallyOnMissingTargetsNoTracksAndAfterReset) {
  GlobalSearchPolicy policy({10});
  auto windowFor = [](int track_id, bool expected) {
    SearchWindow w;
    w.track_id = track_id;
    w.expected = expected;
    return std::vector<SearchWindow>{w};
  };
  TrackerUpdateReport seen;  // a processed frame that measured track 7
  seen.measured_track_ids = {7};
  EXPECT_EQ(policy.decide(windowFor(7, true), 1), GlobalSearchReason::First);
  for (int k = 1; k < 10; ++k) {
    policy.observe(seen);
    EXPECT_EQ(policy.decide(windowFor(7, true), 1), GlobalSearchReason::None) << k;
  }
  policy.observe(seen);
  EXPECT_EQ(policy.decide(windowFor(7, true), 1), GlobalSearchReason::Periodic);  // 10th frame
  policy.observe(seen);
  EXPECT_EQ(policy.decide(windowFor(7, true), 1), GlobalSearchReason::None);
  TrackerUpdateReport missed;  // track 7 expected, not measured
  policy.observe(missed);
  EXPECT_EQ(policy.decide(windowFor(7, true), 1), GlobalSearchReason::TargetMissing);
  ASSERT_EQ(policy.missing().size(), 0u);  // consumed by the decision
  policy.observe(missed);                  // missed by that whole-frame search: its window comes first
  EXPECT_TRUE(policy.missing().empty());
  EXPECT_EQ(policy.decide(windowFor(7, true), 1), GlobalSearchReason::None);
  policy.observe(missed);  // and missed there too: the whole frame again
  EXPECT_EQ(policy.decide(windowFor(7, false), 1), GlobalSearchReason::TargetMissing);
  policy.observe(missed);  // (whole frame: ignored)
  EXPECT_EQ(policy.decide(windowFor(7, false), 1), GlobalSearchReason::None);
  policy.observe(missed);  // 7 was not expected in this camera: missing it is fine
  EXPECT_EQ(policy.decide(windowFor(7, false), 1), GlobalSearchReason::None);
  policy.observe(missed);
  EXPECT_EQ(policy.decide({}, 0), GlobalSearchReason::NoTracks);
  TrackerUpdateReport reset;
  reset.time.action = TimeAction::Reset;
  policy.observe(reset);
  EXPECT_EQ(policy.decide(windowFor(9, true), 1), GlobalSearchReason::AfterReset);
  TrackerUpdateReport dropped;  // a late frame says nothing
  dropped.time.action = TimeAction::Drop;
  policy.observe(dropped);
  EXPECT_EQ(policy.decide(windowFor(9, true), 1), GlobalSearchReason::None);
  EXPECT_EQ(policy.count(GlobalSearchReason::TargetMissing), 2);
  EXPECT_THROW(GlobalSearchPolicy({-1}), std::invalid_argument);
}

TEST(FrameStep, ProcessesEveryNthFrame) {
  FrameStep every4(4);
  std::vector<int> taken;
  for (int k = 0; k < 12; ++k) {
    if (every4.process()) taken.push_back(k);
  }
  EXPECT_EQ(taken, (std::vector<int>{0, 4, 8}));
  EXPECT_EQ(every4.seen(), 12);
  EXPECT_EQ(every4.processed(), 3);
  every4.process();  // frame 12 processed; 13 skipped
  every4.process();
  every4.restart();
  EXPECT_TRUE(every4.process());
  FrameStep all;
  for (int k = 0; k < 5; ++k) EXPECT_TRUE(all.process());
  EXPECT_THROW(FrameStep(0), std::invalid_argument);
  EXPECT_THROW(all.setStep(-2), std::invalid_argument);
}

TEST(Tracker, AMisreadIdOnATrackedRobotIsThatRobot) {
  // Yellow 0 is tracked (confidence 0.9); one frame reads its pink as red: yellow 4 at 0.3,
  // 3 mm from it. Two robots' centres cannot be that close, so it is yellow 0, measured;
  // no yellow 4 appears. A sure read (0.95), or one 0.2 m away (another robot), is not a
  // misread; nor is anything with misread_distance 0. (The confidence rule alone: a sure read
  // on an established track is ASureMisreadOnAnEstablishedTrackIsThatRobot's.)
  for (const double misread_distance : {0.05, 0.0}) {
    TrackerParams p;
    p.misread_distance = misread_distance;
    p.misread_established_reads = 0;
    Tracker tracker(p);
    int k = 0;
    for (; k < 10; ++k) tracker.update(frame(kT0 + k * kDt, 0, {robot(Team::Yellow, 0, 1, 1)}));
    RobotDetection misread = robot(Team::Yellow, 4, 1.003, 1);
    misread.confidence = 0.3;
    const TrackerUpdateReport report = tracker.update(frame(kT0 + k * kDt, 0, {misread}));
    TrackerOutput out = tracker.output(kT0 + k * kDt);
    if (misread_distance > 0) {
      EXPECT_EQ(report.misread_ids, 1);
      ASSERT_TRUE(find(out, Team::Yellow, 0));
      EXPECT_TRUE(find(out, Team::Yellow, 0)->visible);
      EXPECT_FALSE(find(out, Team::Yellow, 4));
      EXPECT_EQ(tracker.stats().misread_ids, 1);
    } else {
      EXPECT_EQ(report.misread_ids, 0);
      EXPECT_FALSE(find(out, Team::Yellow, 0)->visible);
      EXPECT_TRUE(find(out, Team::Yellow, 4));
      continue;
    }
    ++k;
    RobotDetection sure = robot(Team::Yellow, 4, 1.003, 1);
    sure.confidence = 0.95;
    EXPECT_EQ(tracker.update(frame(kT0 + k * kDt, 0, {sure})).misread_ids, 0);
    EXPECT_TRUE(find(tracker.output(kT0 + k * kDt), Team::Yellow, 4));
    ++k;
    RobotDetection beside = robot(Team::Yellow, 3, 1.2, 1);
    beside.confidence = 0.3;
    EXPECT_EQ(tracker.update(frame(kT0 + k * kDt, 0, {robot(Team::Yellow, 4, 1.003, 1), beside})).misread_ids,
              0);
    EXPECT_TRUE(find(tracker.output(kT0 + k * kDt), Team::Yellow, 3));
  }
  // Sure wrong reads put yellow 0's track onto yellow 1 (confidence 1.0). Yellow 1 read
  // right (0.8, less sure than that track) is yellow 1: its own track is there too.
  {
    Tracker tracker;
    int k = 0;
    for (; k < 10; ++k) {
      RobotDetection wrong = robot(Team::Yellow, 0, 1.002, 1);
      wrong.confidence = 1.0;
      tracker.update(frame(kT0 + k * kDt, 0, {wrong, robot(Team::Yellow, 1, 1, 1)}));
    }
    RobotDetection right = robot(Team::Yellow, 1, 1, 1);
    right.confidence = 0.8;
    EXPECT_EQ(tracker.update(frame(kT0 + k * kDt, 0, {right})).misread_ids, 0);
    EXPECT_TRUE(find(tracker.output(kT0 + k * kDt), Team::Yellow, 1)->visible);
  }
  TrackerParams bad;
  bad.misread_distance = -0.01;
  EXPECT_THROW(validate(bad), std::invalid_argument);
  bad.misread_distance = 0.05;
  bad.misread_recent = 0;
  EXPECT_THROW(validate(bad), std::invalid_argument);
  bad.misread_recent = 0.1;
  bad.misread_established_reads = -1;
  EXPECT_THROW(validate(bad), std::invalid_argument);
}

TEST(Tracker, ASureMisreadOnAnEstablishedTrackIsThatRobot) {
  // Held-out seed 9075's rand_flicker_jpeg: blue 1, read as itself at 0.74-0.88 under
  // flicker, read once as blue 0 at 0.95, 2 mm off. Read as itself in 12 frames, the track
  // takes that read as its robot's; read as itself in 3, it does not (blue 0 begins).
  for (const int own_reads : {12, 3}) {
    Tracker tracker;
    int k = 0;
    for (; k < own_reads; ++k) {
      RobotDetection right = robot(Team::Blue, 1, 1, 1);
      right.confidence = 0.8;
      tracker.update(frame(kT0 + k * kDt, 0, {right}));
    }
    RobotDetection wrong = robot(Team::Blue, 0, 1.002, 1);
    wrong.confidence = 0.95;
    const TrackerUpdateReport report = tracker.update(frame(kT0 + k * kDt, 0, {wrong}));
    const TrackerOutput out = tracker.output(kT0 + k * kDt);
    const bool established = own_reads >= TrackerParams{}.misread_established_reads;
    EXPECT_EQ(report.misread_ids, established ? 1 : 0) << own_reads;
    ASSERT_TRUE(find(out, Team::Blue, 1));
    EXPECT_EQ(find(out, Team::Blue, 1)->visible, established) << own_reads;
    EXPECT_EQ(find(out, Team::Blue, 0) != nullptr, !established) << own_reads;
  }
  // Read only as blue 0 from then on: the track's own read grows old, and within
  // misread_recent (0.1 s) blue 0 begins its own track, as a robot first read wrong.
  Tracker tracker;
  int k = 0;
  for (; k < 12; ++k) tracker.update(frame(kT0 + k * kDt, 0, {robot(Team::Blue, 1, 1, 1)}));
  const int last_own = k - 1;
  RobotDetection other = robot(Team::Blue, 0, 1.002, 1);
  other.confidence = 0.95;
  while (!find(tracker.output(kT0 + (k - 1) * kDt), Team::Blue, 0) && k < 40) {
    tracker.update(frame(kT0 + k * kDt, 0, {other}));
    ++k;
  }
  EXPECT_LE((k - 1 - last_own) * kDt, TrackerParams{}.misread_recent + 1.5 * kDt);
  EXPECT_GT((k - 1 - last_own) * kDt, TrackerParams{}.misread_recent - kDt);
}

// A ball track begun outside the playing area is output once measured twice: a single
// frame's orange fleck at the carpet's edge (held-out seed 9044: a cable's tip, while the
// real ball was out of view) is never the ball. One begun inside is output at once. (Still
// out there it is parked and withheld anyway, AStillObjectOutsideTheLinesIsNoBall; here
// parked balls are output, to see this rule alone.)
TEST(Tracker, ABallFirstSeenOutsideThePlayingAreaIsOutputOnceSeenAgain) {
  TrackerParams params;
  params.field = FieldGeometry{};
  params.output_parked_balls = true;
  Tracker tracker(params);
  const BallDetection fleck = ball(-1.82, -3.31, 0.37);  // 0.31 m beyond the touch line
  tracker.update(frame(kT0, 0, {}, {fleck}));
  TrackerOutput out = tracker.output();
  EXPECT_TRUE(out.balls.empty());
  EXPECT_EQ(out.unconfirmed_balls, 1);
  EXPECT_EQ(tracker.predictions(kT0).balls.size(), 1u) << "the windows still look for it";
  tracker.update(frame(kT0 + kDt, 0, {}, {}));
  EXPECT_TRUE(tracker.output().balls.empty());
  // Seen again: a ball put down beside the field, output from its second frame.
  tracker.update(frame(kT0 + 2 * kDt, 0, {}, {fleck}));
  out = tracker.output();
  ASSERT_NE(out.primaryBall(), nullptr);
  EXPECT_NEAR(out.primaryBall()->x, -1.82, 1e-3);
  EXPECT_EQ(out.unconfirmed_balls, 0);

  // The same fleck again 18 frames later (the recording's next one): a new track, not the
  // confirmation of the first, which is gone after 0.05 s.
  Tracker later(params);
  later.update(frame(kT0, 0, {}, {fleck}));
  for (int k = 1; k < 18; ++k) later.update(frame(kT0 + k * kDt, 0, {}, {}));
  later.update(frame(kT0 + 18 * kDt, 0, {}, {fleck}));
  EXPECT_TRUE(later.output().balls.empty());
  EXPECT_EQ(later.output().unconfirmed_balls, 1);

  Tracker inside(params);
  inside.update(frame(kT0, 0, {}, {ball(-1.82, -2.5)}));
  EXPECT_NE(inside.output().primaryBall(), nullptr) << "in play: at once";
  params.ball_confirm_outside = 1;
  Tracker at_once(params);
  at_once.update(frame(kT0, 0, {}, {fleck}));
  EXPECT_NE(at_once.output().primaryBall(), nullptr);
  params.ball_confirm_outside = 0;
  EXPECT_THROW(validate(params), std::invalid_argument);
  params.ball_confirm_outside = 2;
  params.ball_confirm_within = 0;
  EXPECT_THROW(validate(params), std::invalid_argument);
}

// A ball track outside the playing area is output only while its running confidence is at
// least outside_min_confidence: held-out seed 9047's orange cable tip at the carpet's edge,
// seen in most frames at 0.09-0.18, was the only ball in 14 frames. A ball out of play that
// looks like one (0.45, outside_play_weight 0.5 of a good match) is output (with parked
// balls output: still, it is parked, AStillObjectOutsideTheLinesIsNoBall).
TEST(Tracker, AnUnsureBallOutsideThePlayingAreaIsWithheld) {
  TrackerParams params;
  params.field = FieldGeometry{};
  params.output_parked_balls = true;
  params.ball_min_start_confidence = 0;  // the tip begins a track (AnUnsureBallCandidateBeginsNoTrack)
  Tracker tip(params), ball_out(params);
  for (int k = 0; k < 30; ++k) {
    tip.update(frame(kT0 + k * kDt, 0, {}, {ball(-2.53, -3.29, 0.15)}));
    ball_out.update(frame(kT0 + k * kDt, 0, {}, {ball(-2.53, -3.29, 0.45)}));
  }
  EXPECT_TRUE(tip.output().balls.empty());
  EXPECT_EQ(tip.output().unsure_outside_balls, 1);
  EXPECT_EQ(tip.predictions(kT0 + 29 * kDt).balls.size(), 1u) << "still tracked";
  ASSERT_NE(ball_out.output().primaryBall(), nullptr);
  // In the playing area the same unsure candidate is output (the primary, orange there).
  Tracker inside(params);
  for (int k = 0; k < 3; ++k) inside.update(frame(kT0 + k * kDt, 0, {}, {ball(-2.53, -2.5, 0.15)}));
  EXPECT_NE(inside.output().primaryBall(), nullptr);
  params.outside_min_confidence = 1.5;
  EXPECT_THROW(validate(params), std::invalid_argument);
}

// ... unless it rolls: held-out seed 9101's rand_fast had the ball at 11.4 m/s along the
// touch line, its streak's candidates at 0.20-0.33, withheld in 12 frames. A jittering fleck
// by the lines (a few centimetres each frame) stays unsure.
TEST(Tracker, ABallRollingFastOutsideThePlayingAreaIsOutputThoughUnsure) {
  TrackerParams params;
  params.field = FieldGeometry{};
  Tracker rolling(params), jitter(params);
  int first_output = -1;
  for (int k = 0; k < 12; ++k) {
    rolling.update(frame(kT0 + k * kDt, 0, {}, {ball(0.71 - 0.19 * k, 3.08 + 0.0125 * k, 0.22)}));
    const TrackerOutput out = rolling.output();
    const TrackedBall* b = out.primaryBall();
    if (b && first_output < 0) first_output = k;
    if (k >= 1) {
      ASSERT_NE(b, nullptr) << "frame " << k;
      EXPECT_TRUE(b->visible);
      EXPECT_NEAR(b->x, 0.71 - 0.19 * k, 0.01);
    }
    jitter.update(frame(kT0 + k * kDt, 0, {}, {ball(0.58 + (k % 2 ? 0.03 : 0.0), 3.10, 0.22)}));
    EXPECT_TRUE(jitter.output().balls.empty()) << "frame " << k;
  }
  EXPECT_EQ(first_output, 1) << "confirmed by its second frame (ball_confirm_outside)";
  params.outside_sure_speed = 0;  // off: withheld as before
  Tracker off(params);
  for (int k = 0; k < 12; ++k)
    off.update(frame(kT0 + k * kDt, 0, {}, {ball(0.71 - 0.19 * k, 3.08 + 0.0125 * k, 0.22)}));
  EXPECT_TRUE(off.output().balls.empty());
  EXPECT_EQ(off.output().unsure_outside_balls, 1);
  params.outside_sure_speed = -1;
  EXPECT_THROW(validate(params), std::invalid_argument);
}

// Something still beyond the lines since it was first seen is parked and not the ball, however
// ball-like: held-out seed 9053's rand_people had a piece of a yellow-orange shoe by the
// touch line at 0.30-0.39 as the only ball for 30 frames while the real one was out of view.
// Once it moves farther than ball_still_distance it is a ball like any other.
TEST(Tracker, AStillObjectOutsideTheLinesIsNoBall) {
  TrackerParams params;
  params.field = FieldGeometry{};
  Tracker tracker(params);
  int k = 0;
  for (; k < 30; ++k) tracker.update(frame(kT0 + k * kDt, 0, {}, {ball(0.58, -3.28, 0.35)}));
  TrackerOutput out = tracker.output();
  EXPECT_TRUE(out.balls.empty());
  EXPECT_EQ(out.parked_balls, 1);
  EXPECT_EQ(tracker.predictions(kT0 + (k - 1) * kDt).balls.size(), 1u) << "still tracked";
  // Rolled into play at 0.6 m/s: output once it has left its place.
  bool output_again = false;
  for (int n = 1; n <= 30; ++n, ++k) {
    tracker.update(frame(kT0 + k * kDt, 0, {}, {ball(0.58, -3.28 + 0.01 * n, 0.9)}));
    out = tracker.output();
    if (n <= 5) {
      EXPECT_EQ(out.primaryBall(), nullptr) << "frame " << n << ": moved " << 0.01 * n << " m";
    }
    output_again = output_again || out.primaryBall() != nullptr;
  }
  ASSERT_TRUE(output_again);
  ASSERT_NE(out.primaryBall(), nullptr);
  EXPECT_NEAR(out.primaryBall()->y, -3.28 + 0.30, 0.01);
  EXPECT_EQ(out.parked_balls, 0);
  // Its centroid jittering by centimetres (different pixels read orange each frame): jumps
  // beyond a still track's gate, which the filter takes as kicks, but it stays where it was.
  Tracker jitter(params);
  int kicks = 0;
  for (int n = 0; n < 30; ++n) {
    const double dx = n % 3 == 0 ? 0.0 : (n % 3 == 1 ? 0.045 : -0.04);
    kicks += jitter.update(frame(kT0 + n * kDt, 0, {}, {ball(0.58 + dx, -3.28 + 0.5 * dx, 0.35)})).ball_kicks;
  }
  EXPECT_GT(kicks, 0);
  EXPECT_TRUE(jitter.output().balls.empty());
  EXPECT_EQ(jitter.output().parked_balls, 1);
  // A ball lying still across the line's edge by less than its radius still touches the
  // line: in play by the laws, not parked (held-out seed 9050's rand_ssl: one 5 mm beyond,
  // just come into view).
  const FieldGeometry field;
  const double touching = -(field.halfWidth() + field.line_width / 2 + 0.015);
  Tracker on_line(params);
  for (int n = 0; n < 30; ++n) on_line.update(frame(kT0 + n * kDt, 0, {}, {ball(0.58, touching, 0.45)}));
  EXPECT_NE(on_line.output().primaryBall(), nullptr);
  EXPECT_EQ(on_line.output().parked_balls, 0);
  // With output_parked_balls the still one is the ball when nothing else is.
  params.output_parked_balls = true;
  Tracker shown(params);
  for (int n = 0; n < 30; ++n) shown.update(frame(kT0 + n * kDt, 0, {}, {ball(0.58, -3.28, 0.35)}));
  EXPECT_NE(shown.output().primaryBall(), nullptr);
}

// A withheld track is the primary only while no output track exists: on held-out seed
// 9047's rand_bayer_ssl the cable's tip (withheld, drifting 0.15 m, so not parked) stayed
// the primary while the ball rolled into view, which was an alternative for 5 frames and
// reached no consumer of the primary ball.
TEST(Tracker, ABallComingIntoViewIsThePrimaryOverAWithheldOne) {
  TrackerParams params;
  params.field = FieldGeometry{};
  params.ball_min_start_confidence = 0;  // the tip begins a track (AnUnsureBallCandidateBeginsNoTrack)
  Tracker tracker(params);
  int k = 0;
  for (; k < 30; ++k) tracker.update(frame(kT0 + k * kDt, 0, {}, {ball(-2.53, -3.29 + 0.005 * k, 0.15)}));
  EXPECT_EQ(tracker.output().primaryBall(), nullptr);
  for (int n = 0; n < 5; ++n, ++k) {
    const double x = 0.41 - 0.067 * n, y = 0.38 - 0.074 * n;
    tracker.update(frame(kT0 + k * kDt, 0, {}, {ball(x, y, 0.89), ball(-2.53, -3.15, 0.15)}));
    const TrackerOutput out = tracker.output();
    ASSERT_NE(out.primaryBall(), nullptr) << "frame " << n << " of the ball in view";
    EXPECT_NEAR(out.primaryBall()->x, x, 0.01);
    EXPECT_NEAR(out.primaryBall()->y, y, 0.01);
    EXPECT_EQ(out.unsure_outside_balls, 1);
  }
}

// Nor is a track coasting beyond max_coast_uncertainty, which output() withholds: on held-out
// seed 9093's rand_bayer_ssl an orange object behind the goal, measured for a second, then
// "kicked" into play (a neighbouring fragment), coasted as the primary while the ball came
// into view, and the ball's first two frames were recorded and sent as no ball.
TEST(Tracker, ABallComingIntoViewIsThePrimaryOverACoastingOne) {
  TrackerParams params;
  params.field = FieldGeometry{};
  Tracker tracker(params);
  int k = 0;
  for (; k < 60; ++k) tracker.update(frame(kT0 + k * kDt, 0, {}, {ball(-1.0 + 0.03 * k, 0.5)}));
  const TrackerOutput seen = tracker.output();
  ASSERT_NE(seen.primaryBall(), nullptr);
  const int coasting = seen.primaryBall()->track_id;
  // Unseen for 4 frames: 3 sigma of its prediction is beyond 25 mm, so it is withheld.
  for (int n = 0; n < 4; ++n, ++k) tracker.update(frame(kT0 + k * kDt, 0, {}));
  const TrackerOutput lost = tracker.output();
  EXPECT_EQ(lost.primaryBall(), nullptr);
  EXPECT_EQ(lost.withheld_balls, 1);
  // The ball comes into view far from it: the primary at once.
  for (int n = 0; n < 3; ++n, ++k) {
    const double x = 1.17 - 0.127 * n, y = 2.55;
    tracker.update(frame(kT0 + k * kDt, 0, {}, {ball(x, y, 0.95)}));
    const TrackerOutput out = tracker.output();
    ASSERT_NE(out.primaryBall(), nullptr) << "frame " << n << " of the ball in view";
    EXPECT_NE(out.primaryBall()->track_id, coasting);
    EXPECT_NEAR(out.primaryBall()->x, x, 0.01) << "frame " << n;
  }
}
