#include <cmath>

#include <gtest/gtest.h>

#include "soccer_vision/common/angle.h"

namespace soccer_vision {

TEST(Angle, WrapsIntoMinusPiPi) {
  EXPECT_DOUBLE_EQ(wrapToPi(M_PI), M_PI);
  EXPECT_DOUBLE_EQ(wrapToPi(-M_PI), M_PI);
  EXPECT_NEAR(wrapToPi(3 * M_PI + 0.1), -M_PI + 0.1, 1e-12);
  EXPECT_NEAR(wrapToPi(-0.2 - 4 * M_PI), -0.2, 1e-12);
  EXPECT_DOUBLE_EQ(wrapToPi(0.5), 0.5);
}

TEST(Angle, DifferenceIsTheShortTurnAcrossPi) {
  // From 170 deg to -170 deg is a turn of +20 deg, not -340 deg.
  const double deg = M_PI / 180;
  EXPECT_NEAR(angleDifference(-170 * deg, 170 * deg), 20 * deg, 1e-12);
  EXPECT_NEAR(angleDifference(170 * deg, -170 * deg), -20 * deg, 1e-12);
  EXPECT_NEAR(angleDifference(0.3, 0.3 + 4 * M_PI), 0.0, 1e-12);
}

TEST(Angle, KeepsMissingValuesMissing) {
  EXPECT_TRUE(std::isnan(wrapToPi(std::nan(""))));
  EXPECT_TRUE(std::isinf(wrapToPi(INFINITY)));
}

}  // namespace soccer_vision
