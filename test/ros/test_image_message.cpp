#include <gtest/gtest.h>

#include "soccer_vision/ros/image_message.h"

namespace soccer_vision {

namespace {

sensor_msgs::Image image(std::uint32_t width, std::uint32_t height, std::uint32_t step, std::size_t bytes) {
  sensor_msgs::Image msg;
  msg.width = width;
  msg.height = height;
  msg.step = step;
  msg.data.assign(bytes, 7);
  return msg;
}

}  // namespace

TEST(ImageMessage, AcceptsPaddedRowsAndViewsTheMessageBuffer) {
  const sensor_msgs::Image msg = image(4, 2, 16, 32);  // 12 bytes of bgr8 per row, 4 of padding
  EXPECT_TRUE(imageMessageIsConsistent(msg, PixelLayout::Bgr));
  bool malformed = true;
  const cv::Mat view = imageView(msg, PixelLayout::Bgr, &malformed);
  EXPECT_FALSE(malformed);
  EXPECT_EQ(view.cols, 4);
  EXPECT_EQ(view.rows, 2);
  EXPECT_EQ(view.step[0], 16u);
  EXPECT_EQ(view.data, msg.data.data());  // no copy
}

TEST(ImageMessage, RefusesEmptyShortOrInconsistentMessages) {
  EXPECT_FALSE(imageMessageIsConsistent(image(0, 2, 0, 0), PixelLayout::Bgr));
  EXPECT_FALSE(imageMessageIsConsistent(image(4, 2, 11, 22), PixelLayout::Bgr));  // step < 3 x width
  EXPECT_FALSE(imageMessageIsConsistent(image(4, 2, 12, 23), PixelLayout::Bgr));  // last row short
  EXPECT_TRUE(imageMessageIsConsistent(image(4, 2, 4, 8), PixelLayout::BayerRggb));
  EXPECT_FALSE(imageMessageIsConsistent(image(4, 2, 4, 8), PixelLayout::Bgr));  // bytes of a mosaic
  bool malformed = false;
  EXPECT_TRUE(imageView(image(4, 2, 11, 22), PixelLayout::Bgr, &malformed).empty());
  EXPECT_TRUE(malformed);
}

TEST(ImageMessage, RefusesBayerMosaicsOfHalfQuads) {
  EXPECT_FALSE(imageMessageIsConsistent(image(5, 2, 5, 10), PixelLayout::BayerGbrg));
  EXPECT_FALSE(imageMessageIsConsistent(image(4, 3, 4, 12), PixelLayout::BayerGbrg));
  EXPECT_TRUE(imageMessageIsConsistent(image(5, 3, 15, 45), PixelLayout::Rgb));  // odd is fine for RGB
}

TEST(ImageMessage, RefusesSidesBeyondTheLargestImage) {
  EXPECT_FALSE(imageMessageIsConsistent(image(16386, 2, 16386, 2 * 16386), PixelLayout::BayerRggb));
  EXPECT_TRUE(imageMessageIsConsistent(image(16384, 2, 16384, 2 * 16384), PixelLayout::BayerRggb));
}

}  // namespace soccer_vision
