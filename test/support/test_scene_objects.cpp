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
}
