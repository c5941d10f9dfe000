// The measured rate counts by hand-made frames: a robot detected with its id is measured;
// one detected under another id is a wrong id; one with only marker-coloured regions on
// its top is an identification rejected; one with nothing there was not segmented; robots
// not visible, or outside this camera's image, are not counted at all.
#include <cmath>

#include <gtest/gtest.h>

#include "soccer_vision/common/field_geometry.h"
#include "soccer_vision/evaluation/measured_rate.h"
#include "support/scene_objects.h"

using namespace soccer_vision;
using soccer_vision::test::robotRecord;

namespace {

RobotDetection detection(Team team, int id, double x, double y) {
  RobotDetection d;
  d.team = team;
  d.id = id;
  d.x = x;
  d.y = y;
  return d;
}

class MeasuredRateTest : public ::testing::Test {
 protected:
  const FieldGeometry field;
  const CameraModel camera = CameraModel::defaultCamera(field, 0);
  MeasuredRateCounter counter;

  Eigen::Vector2d pixelOf(double x, double y, double dx_m = 0) const {
    return *camera.project(Eigen::Vector3d(x + dx_m, y, 0.15));
  }
};

}  // namespace

TEST_F(MeasuredRateTest, EachRobotFallsIntoExactlyOneClass) {
  FrameRecord truth;
  truth.robots = {robotRecord(Team::Blue, 0, -2.0, 0.0),           // measured (30 mm off)
                  robotRecord(Team::Blue, 1, -2.0, 1.0),           // detected as yellow 1: wrong id
                  robotRecord(Team::Yellow, 2, -3.0, -1.0),        // a region on its top, no detection
                  robotRecord(Team::Yellow, 3, -1.0, -2.0),        // nothing at all
                  robotRecord(Team::Yellow, 4, -1.0, 2.0, false),  // not visible: not counted
                  robotRecord(Team::Blue, 3, 3.0, 0.0)};           // camera 1's half: not in this image
  const std::vector<RobotDetection> detections = {detection(Team::Blue, 0, -2.03, 0.0),
                                                  detection(Team::Yellow, 1, -2.0, 1.01),
                                                  // 60 mm off: too far to be yellow 3's
                                                  detection(Team::Yellow, 3, -1.06, -2.0)};
  // A team marker 40 mm from yellow 2's centre; none near yellow 3 (the one 0.5 m away
  // is another robot's business).
  const std::vector<MarkerRegionCentre> regions = {{pixelOf(-3.0, -1.0, 0.04), true},
                                                   {pixelOf(-1.5, -2.0), true}};
  truth.stamp = 12.5;
  counter.add(truth, camera, detections, regions, 3);

  const MeasuredRate& m = counter.total();
  EXPECT_EQ(m.visible, 4);
  EXPECT_EQ(m.measured, 1);
  EXPECT_EQ(m.wrong_id, 1);
  EXPECT_EQ(m.identification_rejected, 1);
  EXPECT_EQ(m.nothing_segmented, 1);
  EXPECT_DOUBLE_EQ(m.rate(), 0.25);
  // Per robot, and each miss where and why.
  EXPECT_EQ(counter.byRobot().at({Team::Blue, 1}).wrong_id, 1);
  EXPECT_EQ(counter.byRobot().at({Team::Yellow, 2}).identification_rejected, 1);
  EXPECT_EQ(counter.byRobot().count({Team::Yellow, 4}), 0u);  // never visible
  ASSERT_EQ(counter.misses().size(), 3u);
  const MissedRobot& rejected = counter.misses()[1];
  EXPECT_EQ(rejected.team, Team::Yellow);
  EXPECT_EQ(rejected.id, 2);
  EXPECT_STREQ(rejected.cause, "identification_rejected");
  EXPECT_DOUBLE_EQ(rejected.stamp, 12.5);
  EXPECT_EQ(rejected.camera_id, 3);
  EXPECT_LT((rejected.pixel - pixelOf(-3.0, -1.0)).norm(), 1e-9);
  EXPECT_STREQ(counter.misses()[2].cause, "nothing_segmented");
}

// A rejected team region on the robot's top says why the robot was not measured; one on
// another robot's top does not. Without one: no team region there, or one taken elsewhere.
TEST_F(MeasuredRateTest, ARejectedTeamRegionOnTheTopGivesTheMissItsCause) {
  FrameRecord truth;
  truth.robots = {robotRecord(Team::Yellow, 2, -3.0, -1.0), robotRecord(Team::Blue, 5, -2.0, 1.0)};
  const Eigen::Vector2d on_yellow = pixelOf(-3.0, -1.0, 0.02), near_blue = pixelOf(-2.0, 1.0, 0.03);
  const Eigen::Vector2d elsewhere = pixelOf(-2.5, 1.0);
  const std::vector<RejectedRobotCandidate> rejected = {{on_yellow.x(), on_yellow.y(), RejectionCause::Area},
                                                        {elsewhere.x(), elsewhere.y(), RejectionCause::Gate}};
  // On blue 5's top an id marker only (its team marker read as another colour).
  counter.add(truth, camera, {}, {{on_yellow, true}, {near_blue, false}}, 0, rejected);
  ASSERT_EQ(counter.misses().size(), 2u);
  EXPECT_STREQ(counter.misses()[0].rejection, "area");
  EXPECT_STREQ(counter.misses()[1].cause, "identification_rejected");
  EXPECT_STREQ(counter.misses()[1].rejection, "no_team_region") << "the gate rejection is 0.5 m away";
  EXPECT_EQ(counter.total().rejected_by_cause[RejectionCause::Area], 1);
  EXPECT_EQ(counter.total().rejected_by_cause.total(), 1);
  EXPECT_EQ(counter.total().no_team_region, 1);
  EXPECT_EQ(counter.byRobot().at({Team::Yellow, 2}).rejected_by_cause[RejectionCause::Area], 1);
  EXPECT_EQ(counter.byRobot().at({Team::Blue, 5}).no_team_region, 1);
  // A team region there that identification did not reject went into a robot elsewhere.
  counter.add(truth, camera, {}, {{on_yellow, true}, {near_blue, true}}, 0, rejected);
  ASSERT_EQ(counter.misses().size(), 4u);
  EXPECT_STREQ(counter.misses()[3].rejection, "team_region_used");
  EXPECT_EQ(counter.total().team_region_used, 1);
  EXPECT_EQ(counter.total().identification_rejected, 4);
}

TEST_F(MeasuredRateTest, RateAccumulatesOverFrames) {
  FrameRecord truth;
  truth.robots = {robotRecord(Team::Blue, 0, -2.0, 0.0), robotRecord(Team::Yellow, 0, -2.0, 1.0)};
  for (int frame = 0; frame < 10; ++frame) {
    std::vector<RobotDetection> detections = {detection(Team::Blue, 0, -2.0, 0.0)};
    // Yellow 0 is measured in 7 of the 10 frames.
    if (frame < 7) detections.push_back(detection(Team::Yellow, 0, -2.0, 1.0));
    counter.add(truth, camera, detections, {});
  }
  EXPECT_EQ(counter.total().visible, 20);
  EXPECT_EQ(counter.total().measured, 17);
  EXPECT_EQ(counter.total().nothing_segmented, 3);
  EXPECT_DOUBLE_EQ(counter.total().rate(), 0.85);
}

// Each team's top at its own height: a marker region near the rim of a yellow robot 0.10 m
// high (2.6 m from the nadir, the blue team's 0.15 m) lies on its top only when the top is
// placed at 0.10 m (at 0.15 m parallax puts the top ~3.5 cm farther out).
TEST_F(MeasuredRateTest, EachTeamsTopAtItsOwnHeight) {
  FrameRecord truth;
  truth.robots = {robotRecord(Team::Yellow, 1, -2.25, 2.6)};
  const std::vector<MarkerRegionCentre> regions = {
      {*camera.project(Eigen::Vector3d(-2.25, 2.6 - 0.08, 0.10)), true}};
  PatternSet patterns = PatternSet::twoTag();
  patterns.team_height[static_cast<std::size_t>(Team::Yellow)] = 0.10;
  MeasuredRateCounter per_team(patterns);
  per_team.add(truth, camera, {}, regions);
  EXPECT_EQ(per_team.total().identification_rejected, 1);
  counter.add(truth, camera, {}, regions);  // 0.15 m for both teams
  EXPECT_EQ(counter.total().nothing_segmented, 1);
}

// The robots counted are those the ground truth calls visible in this image: all their
// markers in it (markerOutlinePoints). A robot at the image's edge whose top's rim is cut
// but whose markers are all in counts (seed 9045's blue 3 was left out, and missed in every
// frame); one whose marker crosses the edge does not.
TEST_F(MeasuredRateTest, ARobotCountsWhenAllItsMarkersAreInTheImage) {
  const PatternSet patterns = PatternSet::twoTag();
  const auto markers_in_image = [&](const RobotRecord& r) {
    for (const Eigen::Vector3d& p : markerOutlinePoints(patterns, r.team, r.id, r.x, r.y, r.theta)) {
      const auto px = camera.project(p);
      if (!px || !camera.inImage(*px)) return false;
    }
    return true;
  };
  // Heading -y, towards the image's edge at +y its team tag (35 mm behind the centre), not
  // its top's rim (90 mm): walked out until a marker leaves the image.
  RobotRecord robot = robotRecord(Team::Blue, 3, -2.0, 2.5);
  robot.theta = -M_PI / 2;
  RobotRecord last_in = robot;
  for (; robot.y < 4.0 && markers_in_image(robot); robot.y += 0.002) last_in = robot;
  ASSERT_LT(robot.y, 4.0) << "no image edge found";
  const auto top = projectDisc(camera, {last_in.x, last_in.y, 0.15}, patterns.robot_radius);
  ASSERT_TRUE(top && !top->whole) << "the top's rim is in the image: not the case looked at";

  FrameRecord truth;
  truth.robots = {last_in};
  counter.add(truth, camera, {}, {});
  EXPECT_EQ(counter.total().visible, 1) << "all its markers are in the image";
  EXPECT_EQ(counter.total().nothing_segmented, 1);
  truth.robots = {robot};  // 2 mm farther: a marker's outline crosses the edge
  counter.add(truth, camera, {}, {});
  EXPECT_EQ(counter.total().visible, 1);
}
