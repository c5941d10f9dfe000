// Scoring definitions (scoring.h) on hand-made frames whose counts are known.
#include <cmath>

#include <gtest/gtest.h>

#include "soccer_vision/evaluation/scoring.h"

using namespace soccer_vision;

namespace {

FrameRecord truthFrame() {
  FrameRecord t;
  t.stamp = 10.0;
  for (int id = 0; id < 5; ++id) {
    t.robots.push_back({Team::Blue, id, -1.0 + 0.5 * id, 1.0, 0.1 * id, true, std::nullopt});
    t.robots.push_back({Team::Yellow, id, -1.0 + 0.5 * id, -1.0, -0.1 * id, true, std::nullopt});
  }
  t.robots.push_back({Team::Yellow, 7, 4.0, 0.0, 0.0, false, std::nullopt});  // out of view
  t.balls.push_back({0.5, 0.25, true, std::nullopt});
  return t;
}

}  // namespace

TEST(Scoring, PerfectResultScoresOneHundredPercent) {
  const FrameRecord truth = truthFrame();
  FrameRecord result = truth;
  result.robots.pop_back();  // the invisible robot is not reported
  for (auto& r : result.robots) r.visible.reset();
  const Score s = scoreFrame(truth, result);
  EXPECT_EQ(s.truth_robots, 10);
  EXPECT_EQ(s.matched_robots, 10);
  EXPECT_DOUBLE_EQ(s.robotDetectionRate(), 1.0);
  EXPECT_DOUBLE_EQ(s.robotPrecision(), 1.0);
  EXPECT_DOUBLE_EQ(s.robotPositionRmse(), 0.0);
  EXPECT_DOUBLE_EQ(s.ballDetectionRate(), 1.0);
  EXPECT_DOUBLE_EQ(s.ballPrecision(), 1.0);
}

// One robot with a wrong id, one displaced by 60 mm (beyond the gate), one by 30 mm, and
// a coasting track of the invisible robot: counted by hand.
TEST(Scoring, WrongIdAndDisplacedRobotsCountAsByHand) {
  const FrameRecord truth = truthFrame();
  FrameRecord result = truth;
  for (auto& r : result.robots) r.visible.reset();
  result.robots[0].id = 4;        // blue 0 reported as blue 4 (blue 4 is reported too)
  result.robots[1].x += 0.060;    // yellow 0: 60 mm off
  result.robots[2].y += 0.030;    // blue 1: 30 mm off, still a match
  result.robots[3].theta += 0.2;  // yellow 1: heading 0.2 rad off
  const Score s = scoreFrame(truth, result);
  EXPECT_EQ(s.truth_robots, 10);
  EXPECT_EQ(s.result_robots, 11);
  EXPECT_EQ(s.excused_robots, 1);  // yellow 7 out of view
  EXPECT_EQ(s.matched_robots, 8);  // all but blue 0 and yellow 0
  EXPECT_EQ(s.false_robots, 2);
  EXPECT_EQ(s.identity_errors, 1);  // the wrong id lies on blue 0
  EXPECT_DOUBLE_EQ(s.robotDetectionRate(), 0.8);
  EXPECT_DOUBLE_EQ(s.robotPrecision(), 0.8);  // 8 of 10 non-excused results
  EXPECT_NEAR(s.robotPositionRmse(), std::sqrt(0.030 * 0.030 / 8), 1e-12);
  EXPECT_NEAR(s.robotHeadingRmse(), std::sqrt(0.2 * 0.2 / 8), 1e-12);

  FrameRecord no_ball = result;
  no_ball.balls.clear();
  EXPECT_DOUBLE_EQ(scoreFrame(truth, no_ball).ballDetectionRate(), 0.0);
  FrameRecord far_ball = result;
  far_ball.balls.front().x += 1.0;
  const Score b = scoreFrame(truth, far_ball);
  EXPECT_EQ(b.false_balls, 1);
  EXPECT_DOUBLE_EQ(b.ballPrecision(), 0.0);

  // A coasting prediction (not measured) of the out-of-view robot, far from it: excused;
  // the same claimed as measured: a false positive; a prediction of a visible robot, far
  // from it: a false positive too.
  FrameRecord coasting = truth;
  coasting.robots.back().x += 0.5;
  coasting.robots.back().visible = false;
  EXPECT_EQ(scoreFrame(truth, coasting).excused_robots, 1);
  EXPECT_EQ(scoreFrame(truth, coasting).false_robots, 0);
  coasting.robots.back().visible = true;
  EXPECT_EQ(scoreFrame(truth, coasting).false_robots, 1);
  FrameRecord lagging = truth;
  lagging.robots.pop_back();
  lagging.robots[0].x += 0.2;
  lagging.robots[0].visible = false;
  EXPECT_EQ(scoreFrame(truth, lagging).false_robots, 1);
  EXPECT_EQ(scoreFrame(truth, lagging).matched_robots, 9);

  FrameRecord ball_out = truth;
  ball_out.balls.front().visible = false;
  FrameRecord coasting_ball = far_ball;
  coasting_ball.balls.front().visible = false;
  EXPECT_EQ(scoreFrame(ball_out, coasting_ball).excused_balls, 1);
  EXPECT_EQ(scoreFrame(truth, coasting_ball).false_balls, 1);  // the ball is in view: no excuse

  Score total = s;
  total.add(scoreFrame(truth, truth));
  EXPECT_EQ(total.frames, 2);
  EXPECT_EQ(total.truth_robots, 20);
}
