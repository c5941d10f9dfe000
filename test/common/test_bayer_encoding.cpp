#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "soccer_vision/common/bayer_encoding.h"

namespace soccer_vision {

namespace {

// A flat-coloured BGR image mosaicked as the encoding says (top-left 2x2 block first).
cv::Mat1b mosaic(const std::string& pattern, cv::Vec3b bgr, int size = 8) {
  cv::Mat1b out(size, size);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const char c = pattern[(y % 2) * 2 + (x % 2)];
      out(y, x) = c == 'b' ? bgr[0] : c == 'g' ? bgr[1] : bgr[2];
    }
  }
  return out;
}

}  // namespace

TEST(BayerEncoding, DemosaicsEveryLayoutBackToItsColour) {
  const cv::Vec3b orange(20, 120, 240);  // B, G, R all different: a swapped channel shows
  for (const std::string pattern : {"rggb", "bggr", "gbrg", "grbg"}) {
    const int code = bayerToBgrCode("bayer_" + pattern + "8");
    ASSERT_GE(code, 0) << pattern;
    cv::Mat3b bgr;
    cv::cvtColor(mosaic(pattern, orange), bgr, code);
    EXPECT_EQ(bgr(4, 4), orange) << pattern;  // an inner pixel: no border effects
  }
}

// What calibration sees of an image: bgr8 itself (no copy), rgb8 swapped, an 8-bit mosaic
// demosaiced to its colour; nothing else.
TEST(BayerEncoding, BgrOfEncodingShowsEveryLayoutAsItsColour) {
  const cv::Vec3b orange(20, 120, 240);
  const cv::Mat3b bgr(8, 8, orange);
  EXPECT_EQ(bgrOfEncoding(bgr, "bgr8").data, bgr.data);
  cv::Mat3b rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  EXPECT_EQ(cv::Mat3b(bgrOfEncoding(rgb, "rgb8"))(4, 4), orange);
  for (const std::string pattern : {"rggb", "bggr", "gbrg", "grbg"})
    EXPECT_EQ(cv::Mat3b(bgrOfEncoding(mosaic(pattern, orange), "bayer_" + pattern + "8"))(4, 4), orange)
        << pattern;
  EXPECT_THROW(bgrOfEncoding(cv::Mat1w::zeros(8, 8), "bayer_rggb16"), std::invalid_argument);
  EXPECT_THROW(bgrOfEncoding(cv::Mat1b::zeros(8, 8), "mono8"), std::invalid_argument);
}

TEST(BayerEncoding, SixteenBitNamesShareTheCodes) {
  EXPECT_EQ(bayerToBgrCode("bayer_gbrg16"), bayerToBgrCode("bayer_gbrg8"));
}

TEST(BayerEncoding, IsMinusOneForOtherEncodings) {
  EXPECT_EQ(bayerToBgrCode("bgr8"), -1);
  EXPECT_EQ(bayerToBgrCode("mono8"), -1);
  EXPECT_EQ(bayerToBgrCode("bayer_xyzw8"), -1);
}

}  // namespace soccer_vision
