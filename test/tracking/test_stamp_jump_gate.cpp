// StampJumpGate: tf is not published for an isolated stamp jump, and is for a confirmed one.
#include <limits>

#include <gtest/gtest.h>

#include "soccer_vision/tracking/stamp_jump_gate.h"

namespace sv = soccer_vision;

TEST(StampJumpGate, AnIsolatedFarFutureStampIsHeldAndTheTimeLineGoesOn) {
  sv::StampJumpGate gate(1.0);
  for (int i = 0; i < 10; ++i) EXPECT_TRUE(gate.accept(100.0 + i / 60.0));
  EXPECT_FALSE(gate.accept(2.2e9)) << "one image stamped in 2038";
  for (int i = 10; i < 20; ++i) EXPECT_TRUE(gate.accept(100.0 + i / 60.0)) << i;
  EXPECT_EQ(gate.held(), 1u);
}

TEST(StampJumpGate, AJumpConfirmedByTheNextFrameIsAccepted) {
  sv::StampJumpGate gate(1.0);
  EXPECT_TRUE(gate.accept(500.0));
  EXPECT_FALSE(gate.accept(10.0)) << "backwards: a restarted bag, not yet confirmed";
  EXPECT_TRUE(gate.accept(10.0 + 1 / 60.0));
  EXPECT_TRUE(gate.accept(10.0 + 2 / 60.0));
  EXPECT_FALSE(gate.accept(std::numeric_limits<double>::quiet_NaN()));
  EXPECT_TRUE(gate.accept(10.0 + 3 / 60.0));
  EXPECT_EQ(gate.held(), 2u);
}
