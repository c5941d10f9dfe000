#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "soccer_vision/common/statistics.h"

namespace soccer_vision {

TEST(Percentile, InterpolatesBetweenOrderStatistics) {
  const std::vector<double> v = {4, 1, 3, 2};  // order does not matter
  EXPECT_DOUBLE_EQ(percentile(v, 50), 2.5);
  EXPECT_DOUBLE_EQ(percentile(v, 0), 1.0);
  EXPECT_DOUBLE_EQ(percentile(v, 100), 4.0);
  EXPECT_DOUBLE_EQ(percentile(v, 25), 1.75);
}

TEST(Percentile, P99OfAHundredValuesLiesBetweenTheTopTwo) {
  std::vector<double> v;
  for (int i = 1; i <= 100; ++i) v.push_back(i);
  EXPECT_NEAR(percentile(v, 99), 99.01, 1e-12);  // nearest rank would say 100, upper median 51 for p50
  EXPECT_DOUBLE_EQ(percentile(v, 50), 50.5);
}

TEST(Percentile, SkipsMissingValuesAndIsNanWithoutAny) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_DOUBLE_EQ(percentile({nan, 5, INFINITY, 7}, 50), 6.0);
  EXPECT_TRUE(std::isnan(percentile({}, 50)));
  EXPECT_TRUE(std::isnan(percentile({nan}, 50)));
}

TEST(Percentile, RefusesPOutsideZeroToHundred) {
  EXPECT_THROW(percentile({1, 2}, -1), std::invalid_argument);
  EXPECT_THROW(percentile({1, 2}, 101), std::invalid_argument);
}

TEST(RootMeanSquare, OfTheFiniteValues) {
  EXPECT_DOUBLE_EQ(rootMeanSquare({3, -4, NAN}), std::sqrt(12.5));
  EXPECT_TRUE(std::isnan(rootMeanSquare({})));
}

}  // namespace soccer_vision
