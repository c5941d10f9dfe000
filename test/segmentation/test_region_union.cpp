#include <cmath>

#include <gtest/gtest.h>

#include "soccer_vision/segmentation/region_union.h"

namespace sv = soccer_vision;

namespace {

// Binary moments of the pixels of `rect` that `keep` accepts.
template <typename Keep>
sv::Region pixelRegion(const cv::Rect& rect, Keep keep) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
  cv::Rect box;
  for (int y = rect.y; y < rect.y + rect.height; ++y) {
    for (int x = rect.x; x < rect.x + rect.width; ++x) {
      if (!keep(x, y)) continue;
      n += 1;
      sx += x;
      sy += y;
      sxx += double(x) * x;
      sxy += double(x) * y;
      syy += double(y) * y;
      box = box.empty() ? cv::Rect(x, y, 1, 1) : box | cv::Rect(x, y, 1, 1);
    }
  }
  sv::Region r;
  r.color = sv::ColorClass::Yellow;
  r.area = static_cast<std::uint32_t>(n);
  r.cx = sx / n;
  r.cy = sy / n;
  r.mu20 = sxx / n - r.cx * r.cx;
  r.mu11 = sxy / n - r.cx * r.cy;
  r.mu02 = syy / n - r.cy * r.cy;
  r.orientation = 0.5 * std::atan2(2 * r.mu11, r.mu20 - r.mu02);
  r.bbox = box;
  return r;
}

}  // namespace

// A tilted bar cut in two along a line across it: the union of the parts is the bar.
TEST(RegionUnion, TheTwoPartsOfACutBarAreTheBar) {
  const cv::Rect area(0, 0, 40, 40);
  auto inBar = [](int x, int y) {  // 6 px wide, 24 px long, tilted 30 degrees
    const double c = std::cos(0.5236), s = std::sin(0.5236);
    const double u = (x - 20) * c + (y - 20) * s, v = -(x - 20) * s + (y - 20) * c;
    return std::abs(u) <= 12 && std::abs(v) <= 3;
  };
  auto side = [&](bool first) {
    return [&, first](int x, int y) { return inBar(x, y) && ((x + y < 41) == first); };
  };
  const sv::Region whole = pixelRegion(area, inBar);
  const sv::Region a = pixelRegion(area, side(true)), b = pixelRegion(area, side(false));
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
  const sv::Region a = pixelRegion(cv::Rect(3, 4, 5, 6), [](int, int) { return true; });
  const sv::Region u = sv::regionUnion({&a});
  EXPECT_EQ(u.area, a.area);
  EXPECT_DOUBLE_EQ(u.cx, a.cx);
  EXPECT_DOUBLE_EQ(u.mu20, a.mu20);
  EXPECT_EQ(u.bbox, a.bbox);
  EXPECT_THROW(sv::regionUnion({}), std::invalid_argument);
}
