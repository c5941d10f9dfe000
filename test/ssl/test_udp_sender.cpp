#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "soccer_vision/ssl/udp_sender.h"
#include "support/loopback_receiver.h"

using soccer_vision::test::LoopbackReceiver;

TEST(UdpSender, DeliversEachPayloadAsOneDatagramOnLoopback) {
  LoopbackReceiver receiver;
  ASSERT_GT(receiver.port, 0);
  soccer_vision::ssl::UdpSender sender("127.0.0.1", receiver.port);
  EXPECT_FALSE(sender.multicast());
  const std::string binary("\x0a\x00\xff packet", 10);
  ASSERT_TRUE(sender.send(binary)) << sender.lastError();
  ASSERT_TRUE(sender.send("second"));
  EXPECT_EQ(receiver.receive(), binary);
  EXPECT_EQ(receiver.receive(), "second");
}

TEST(UdpSender, RejectsBadAddressPortAndInterface) {
  using soccer_vision::ssl::UdpSender;
  EXPECT_THROW(UdpSender("224.5.23", 10006), std::runtime_error);
  EXPECT_THROW(UdpSender("127.0.0.1", 0), std::runtime_error);
  EXPECT_THROW(UdpSender("127.0.0.1", 70000), std::runtime_error);
  EXPECT_THROW(UdpSender("127.0.0.1", 10006, "no_such_interface0"), std::runtime_error);
}
