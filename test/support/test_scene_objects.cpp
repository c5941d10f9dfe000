#include <gtest/gtest.h>

#include "support/scene_objects.h"

using namespace soccer_vision;

TEST(SceneObjects, RobotsCarryWhatTheyAreGiven) {
  const RobotState s = test::robotState(Team::Yellow, 3, 1.5, -2.0, 0.25);
  EXPECT_EQ(s.team, Team::Yellow);
  EXPECT_EQ(s.id, 3);
  EXPECT_DOUBLE_EQ(s.x, 1.5);
  EXPECT_DOUBLE_EQ(s.y, -2.0);
  EXPECT_DOUBLE_EQ(s.theta, 0.25);
  EXPECT_DOUBLE_EQ(s.vx, 0.0);
  const RobotRecord r = test::robotRecord(Team::Blue, 4, 0.5, 0.75, false);
  EXPECT_EQ(r.team, Team::Blue);
  EXPECT_EQ(r.id, 4);
  EXPECT_DOUBLE_EQ(r.x, 0.5);
  EXPECT_DOUBLE_EQ(r.y, 0.75);
  EXPECT_EQ(r.visible, std::optional<bool>(false));
  EXPECT_TRUE(test::robotRecord(Team::Blue, 0, 0, 0).visible.value_or(false));
  const RobotDetection d = test::robotDetection(Team::Yellow, 2, 0.5, -0.25, 1.0, 0.7);
  EXPECT_EQ(d.team, Team::Yellow);
  EXPECT_EQ(d.id, 2);
  EXPECT_DOUBLE_EQ(d.x, 0.5);
  EXPECT_DOUBLE_EQ(d.y, -0.25);
  EXPECT_DOUBLE_EQ(d.theta, 1.0);
  EXPECT_TRUE(d.heading_valid);
  EXPECT_DOUBLE_EQ(d.confidence, 0.7);
  EXPECT_FALSE(test::robotDetection(Team::Blue, -1, 0, 0, 0).heading_valid);
}
