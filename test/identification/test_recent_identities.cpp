// RecentIdentities: the robot of a team last seen where a robot is, facing its way, and
// whether its id is one the markers allow; nothing when two robots of the team were there,
// when the sighting is too old, or after time ran backwards.
#include <cmath>

#include <gtest/gtest.h>

#include "soccer_vision/identification/recent_identities.h"
#include "support/scene_objects.h"

using namespace soccer_vision;

namespace {

constexpr double kFrame = 1.0 / 60;

}  // namespace

TEST(RecentIdentities, RecallsTheRobotSeenThereIfTheMarkersAllowItsId) {
  const RecallParams p;
  RecentIdentities recent;
  recent.remember({test::robotDetection(Team::Blue, 7, 1.0, 2.0, 0.5),
                   test::robotDetection(Team::Blue, 3, 0.0, 0.0, 0.0)},
                  10.0, p);
  EXPECT_EQ(recent.recall(Team::Blue, {5, 7}, 1.01, 2.0, 0.55, 10.0 + kFrame, p), 7);
  // Its id is no candidate, another team's robot, too far, facing away, too old.
  EXPECT_EQ(recent.recall(Team::Blue, {5, 6}, 1.01, 2.0, 0.55, 10.0 + kFrame, p), -1);
  EXPECT_EQ(recent.recall(Team::Yellow, {5, 7}, 1.01, 2.0, 0.55, 10.0 + kFrame, p), -1);
  EXPECT_EQ(recent.recall(Team::Blue, {5, 7}, 1.07, 2.0, 0.55, 10.0 + kFrame, p), -1);
  EXPECT_EQ(recent.recall(Team::Blue, {5, 7}, 1.01, 2.0, 0.5 + 0.6, 10.0 + kFrame, p), -1);
  EXPECT_EQ(recent.recall(Team::Blue, {5, 7}, 1.01, 2.0, 0.55, 10.0 + 0.11, p), -1);
  // Not from the frame it was seen in, nor off.
  EXPECT_EQ(recent.recall(Team::Blue, {5, 7}, 1.0, 2.0, 0.5, 10.0, p), -1);
  RecallParams off = p;
  off.max_age = 0;
  EXPECT_EQ(recent.recall(Team::Blue, {5, 7}, 1.01, 2.0, 0.55, 10.0 + kFrame, off), -1);
}

TEST(RecentIdentities, FollowsAMovingRobotFromItsLastTwoSightings) {
  const RecallParams p;
  RecentIdentities recent;
  // 4 m/s along x: 67 mm per frame, beyond max_distance of a still extrapolation.
  recent.remember({test::robotDetection(Team::Yellow, 2, 0.0, 0.0, 0.0)}, 0.0, p);
  recent.remember({test::robotDetection(Team::Yellow, 2, 4 * kFrame, 0.0, 0.0)}, kFrame, p);
  EXPECT_EQ(recent.recall(Team::Yellow, {2, 10}, 3 * 4 * kFrame, 0.0, 0.0, 3 * kFrame, p), 2);
  EXPECT_EQ(recent.recall(Team::Yellow, {2, 10}, 4 * kFrame, 0.0, 0.0, 3 * kFrame, p), -1);
}

TEST(RecentIdentities, TwoRobotsOfTheTeamThereMeanNeither) {
  const RecallParams p;
  RecentIdentities recent;
  recent.remember({test::robotDetection(Team::Blue, 1, 0.0, 0.0, 0.0),
                   test::robotDetection(Team::Blue, 2, 0.06, 0.0, 0.0)},
                  0.0, p);
  EXPECT_EQ(recent.recall(Team::Blue, {1, 9}, 0.03, 0.0, 0.0, kFrame, p), -1);
  // A robot of the other team there does not count.
  RecentIdentities mixed;
  mixed.remember({test::robotDetection(Team::Blue, 1, 0.0, 0.0, 0.0),
                  test::robotDetection(Team::Yellow, 2, 0.06, 0.0, 0.0)},
                 0.0, p);
  EXPECT_EQ(mixed.recall(Team::Blue, {1, 9}, 0.03, 0.0, 0.0, kFrame, p), 1);
}

TEST(RecentIdentities, ForgetsWhenTimeRunsBackwardsAndSkipsWhatItCannotPlace) {
  const RecallParams p;
  RecentIdentities recent;
  RobotDetection no_id = test::robotDetection(Team::Blue, -1, 0.5, 0.5, 0.0);
  RobotDetection no_heading = test::robotDetection(Team::Blue, 4, 0.5, 0.5, 0.0);
  no_heading.heading_valid = false;
  RobotDetection nan = test::robotDetection(Team::Blue, 5, std::nan(""), 0.5, 0.0);
  recent.remember({test::robotDetection(Team::Blue, 1, 0.0, 0.0, 0.0), no_id, no_heading, nan}, 5.0, p);
  EXPECT_EQ(recent.size(), 1u);
  recent.remember({test::robotDetection(Team::Blue, 2, 1.0, 1.0, 0.0)}, 2.0, p);  // the bag played again
  EXPECT_EQ(recent.size(), 1u);
  EXPECT_EQ(recent.recall(Team::Blue, {1, 2}, 0.0, 0.0, 0.0, 2.0 + kFrame, p), -1);
  EXPECT_EQ(recent.recall(Team::Blue, {1, 2}, 1.0, 1.0, 0.0, 2.0 + kFrame, p), 2);
}
