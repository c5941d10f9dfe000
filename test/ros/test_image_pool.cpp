#include <gtest/gtest.h>

#include "soccer_vision/ros/image_pool.h"

namespace sv = soccer_vision;

// A message comes back only when nothing but the pool holds it: a subscriber's reference
// (here `held`) keeps it out, whatever the pool's capacity.
TEST(ImagePool, HandsOutAMessageAgainOnlyWhenNobodyElseHoldsIt) {
  sv::ImagePool pool(2);
  sensor_msgs::ImageConstPtr held = pool.acquire(100);
  const std::uint8_t* first = held->data.data();
  sensor_msgs::ImagePtr second = pool.acquire(100);
  EXPECT_NE(second->data.data(), first) << "a held message was handed out again";
  second->data[0] = 7;
  const std::uint8_t* second_data = second->data.data();
  second.reset();  // published and released by every subscriber
  sensor_msgs::ImagePtr again = pool.acquire(100);
  EXPECT_EQ(again->data.data(), second_data);
  EXPECT_EQ(again->data[0], 7) << "reused as it was, not zeroed";
  // Full and all held: new messages, outside the pool.
  sensor_msgs::ImagePtr extra = pool.acquire(100);
  EXPECT_NE(extra->data.data(), first);
  EXPECT_NE(extra->data.data(), second_data);
  EXPECT_EQ(pool.size(), 2u);
  held.reset();
  EXPECT_EQ(pool.acquire(100)->data.data(), first);
}

TEST(ImagePool, AnotherSizeReplacesTheMessagesOfTheOldOne) {
  sv::ImagePool pool(3);
  pool.acquire(100);
  pool.acquire(100);
  sensor_msgs::ImagePtr big = pool.acquire(300);
  EXPECT_EQ(big->data.size(), 300u);
  EXPECT_EQ(pool.size(), 1u);
  big.reset();
  EXPECT_EQ(pool.acquire(300)->data.size(), 300u);
  EXPECT_EQ(pool.size(), 1u);
}
