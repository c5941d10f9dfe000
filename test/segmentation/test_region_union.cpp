#include <cmath>

#include <gtest/gtest.h>

#include "identification/region_builder.h"
#include "soccer_vision/segmentation/region_union.h"

namespace sv = soccer_vision;

namespace {

// Binary moments of the whole pixels (u, v) within `reach` of `centre` that `keep` accepts:
// every sub-pixel sample of a pixel rounds to it, so coverage is 0 or 1.
template <typename Keep>
sv::Region pixelRegion(const Eigen::Vector2d& centre, int reach, Keep keep) {
  return sv::test::rasterise(sv::ColorClass::Yellow, centre, reach, [&](const Eigen::Vector2d& p) {
    return keep(static_cast<int>(std::lround(p.x())), static_cast<int>(std::lround(p.y())));
  });
}

}  // namespace

// A tilted bar cut in two along a line across it: the union of the parts is the bar.
TEST(RegionUnion, TheTwoPartsOfACutBarAreTheBar) {
  const Eigen::Vector2d centre(20, 20);
  auto inBar = [](int x, int y) {  // 6 px wide, 24 px long, tilted 30 degrees
    const double c = std::cos(0.5236), s = std::sin(0.5236);
    const double u = (x - 20) * c + (y - 20) * s, v = -(x - 20) * s + (y - 20) * c;
    return std::abs(u) <= 12 && std::abs(v) <= 3;
  };
  auto side = [&](bool first) {
    return [&, first](int x, int y) { return inBar(x, y) && ((x + y < 41) == first); };
  };
  const sv::Region whole = pixelRegion(centre, 16, inBar);
  const sv::Region a = pixelRegion(centre, 16, side(true)), b = pixelRegion(centre, 16, side(false));
  ASSERT_GT(a.area, 20u);
  ASSERT_GT(b.area, 20u);
  const sv::Region u = sv::regionUnion({&a, &b});
  EXPECT_EQ(u.color, sv::ColorClass::Yellow);
  EXPECT_EQ(u.area, whole.area);
  EXPECT_NEAR(u.cx, whole.cx, 1e-9);
  EXPECT_NEAR(u.cy, whole.cy, 1e-9);
  EXPECT_NEAR(u.mu20, whole.mu20, 1e-9);
  EXPECT_NEAR(u.mu11, whole.mu11, 1e-9);
  EXPECT_NEAR(u.mu02, whole.mu02, 1e-9);
  EXPECT_NEAR(u.orientation, whole.orientation, 1e-9);
  EXPECT_NEAR(u.orientation, 0.5236, 0.05);
  EXPECT_EQ(u.bbox, whole.bbox);
  // A part alone is off by a quarter of the bar along it.
  EXPECT_GT(std::hypot(a.cx - whole.cx, a.cy - whole.cy), 4.0);
}

TEST(RegionUnion, OnePartIsItselfAndNoPartIsAnError) {
  const sv::Region a =
      pixelRegion({5, 6}, 4, [](int u, int v) { return u >= 3 && u < 8 && v >= 4 && v < 10; });
  const sv::Region u = sv::regionUnion({&a});
  EXPECT_EQ(u.area, a.area);
  EXPECT_DOUBLE_EQ(u.cx, a.cx);
  EXPECT_DOUBLE_EQ(u.mu20, a.mu20);
  EXPECT_EQ(u.bbox, a.bbox);
  EXPECT_THROW(sv::regionUnion({}), std::invalid_argument);
}
