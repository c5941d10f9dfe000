#include <gtest/gtest.h>

#include "support/loopback_receiver.h"

namespace soccer_vision::test {

TEST(LoopbackReceiver, ReceivesADatagramSentToItsPortAndSaysWhenNothingCame) {
  LoopbackReceiver receiver;
  ASSERT_GT(receiver.port, 0);
  const int out = socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  to.sin_port = htons(static_cast<std::uint16_t>(receiver.port));
  const std::string payload("packet\0with a zero", 18);
  ASSERT_EQ(sendto(out, payload.data(), payload.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to),
            static_cast<ssize_t>(payload.size()));
  close(out);
  EXPECT_EQ(receiver.receive(), payload);
  EXPECT_EQ(receiver.receive(), "(nothing within 2 s)");
}

}  // namespace soccer_vision::test
