// bandShape: a region's length (at most) and width (at least) as a band along a curve, from
// its area and second moments: exact for straight bands, within a factor of two for a
// line's arc.
#include <cmath>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "soccer_vision/segmentation/region_extractor.h"
#include "soccer_vision/segmentation/region_moments.h"

using namespace soccer_vision;

namespace {

// The binary region of a mask's set pixels.
Region regionOf(const cv::Mat& mask) {
  const cv::Moments m = cv::moments(mask, true);
  Region r;
  r.area = static_cast<std::uint32_t>(m.m00);
  r.cx = m.m10 / m.m00;
  r.cy = m.m01 / m.m00;
  r.mu20 = m.mu20 / m.m00;
  r.mu11 = m.mu11 / m.m00;
  r.mu02 = m.mu02 / m.m00;
  r.bbox = cv::boundingRect(mask);
  return r;
}

// A band of `width` px along the circle of `radius` px about (150, 150), over [from, to] deg.
cv::Mat arc(double radius, double width, double from, double to) {
  cv::Mat mask(300, 300, CV_8U, cv::Scalar(0));
  for (int y = 0; y < mask.rows; ++y) {
    for (int x = 0; x < mask.cols; ++x) {
      double angle = std::atan2(y - 150.0, x - 150.0) * 180 / M_PI;
      if (angle < 0) angle += 360;
      mask.at<std::uint8_t>(y, x) =
          std::abs(std::hypot(x - 150.0, y - 150.0) - radius) <= width / 2 && angle >= from && angle <= to;
    }
  }
  return mask;
}

}  // namespace

TEST(RegionMoments, BandShapeIsExactForStraightBandsAndBoundsACurvedOne) {
  cv::Mat mask(300, 300, CV_8U, cv::Scalar(0));
  cv::rectangle(mask, cv::Rect(20, 40, 200, 3), cv::Scalar(1), cv::FILLED);  // a line's fringe
  EXPECT_NEAR(bandShape(regionOf(mask)).width, 3.0, 0.05);
  EXPECT_NEAR(bandShape(regionOf(mask)).length, 200.0, 0.5);
  mask.setTo(0);
  cv::rectangle(mask, cv::Rect(20, 40, 40, 30), cv::Scalar(1), cv::FILLED);  // its diagonal, w h / diagonal
  EXPECT_NEAR(bandShape(regionOf(mask)).length, 50.0, 0.5);
  EXPECT_NEAR(bandShape(regionOf(mask)).width, 24.0, 0.5);
  mask.setTo(0);
  cv::circle(mask, cv::Point(150, 150), 20, cv::Scalar(1), cv::FILLED);  // 1.22 and 0.64 diameters
  EXPECT_NEAR(bandShape(regionOf(mask)).length, std::sqrt(6.0) * 20, 1.0);
  EXPECT_NEAR(bandShape(regionOf(mask)).width, M_PI * 20 * 20 / (std::sqrt(6.0) * 20), 1.0);
  // Turned by 37°: the same as straight.
  mask.setTo(0);
  cv::Point2f corners[4];
  cv::RotatedRect(cv::Point2f(150, 150), cv::Size2f(200, 4), 37).points(corners);
  const std::vector<cv::Point> polygon(corners, corners + 4);
  cv::fillConvexPoly(mask, polygon, cv::Scalar(1));
  EXPECT_NEAR(bandShape(regionOf(mask)).length, 200.0, 2.0);
  EXPECT_NEAR(bandShape(regionOf(mask)).width, 4.0, 0.5);  // the polygon's edge pixels

  // Bands along a circle of 60 px: their length or less, their width (area / length) or
  // more, each within a factor of two.
  for (const auto& [from, to] : {std::pair{0.0, 90.0}, std::pair{100.0, 260.0}, std::pair{0.0, 360.0}}) {
    const Region band = regionOf(arc(60, 2, from, to));
    const double length = 60 * (to - from) * M_PI / 180, width = band.area / length;
    const BandShape shape = bandShape(band);
    EXPECT_LE(shape.length, length) << from << "-" << to;
    EXPECT_GE(shape.length, length / 2) << from << "-" << to;
    EXPECT_GE(shape.width, width) << from << "-" << to;
    EXPECT_LE(shape.width, 2 * width) << from << "-" << to;
  }
  EXPECT_EQ(bandShape(Region{}).length, 0.0) << "no moments: no band";
  EXPECT_EQ(bandShape(Region{}).width, 0.0);
}
