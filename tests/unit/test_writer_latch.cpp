// core::WriterLatch: the first writer whose sample was accepted for a key
// holds it until it departs or (realtime) falls silent.
#include <gtest/gtest.h>

#include <chrono>

#include "pheromesh/core/writer_latch.hpp"

namespace pheromesh::core {
namespace {

using namespace std::chrono_literals;
const WriterLatch::Clock::time_point t0{};

TEST(WriterLatch, TheFirstWriterAcceptedHoldsTheKeyAndAnotherIsRefused) {
  WriterLatch latch;
  EXPECT_TRUE(latch.allows(3, 0xA, t0));
  EXPECT_TRUE(latch.allows(3, 0xB, t0));  // free: anyone may
  latch.hold(3, 0xA, t0);
  EXPECT_TRUE(latch.allows(3, 0xA, t0 + 10ms));
  EXPECT_FALSE(latch.allows(3, 0xB, t0 + 20ms));
  EXPECT_EQ(latch.holder(3), 0xAU);
  // Each key on its own: B may hold another UAV.
  EXPECT_TRUE(latch.allows(4, 0xB, t0 + 20ms));
  EXPECT_FALSE(latch.holder(4).has_value());  // allowed is not held
  latch.hold(4, 0xB, t0 + 20ms);
  EXPECT_EQ(latch.holder(4), 0xBU);
}

TEST(WriterLatch, ADepartureFreesTheKeyForTheNextWriterAccepted) {
  WriterLatch latch;
  latch.hold(3, 0xA, t0);
  latch.release(3);
  EXPECT_FALSE(latch.holder(3).has_value());
  ASSERT_TRUE(latch.allows(3, 0xB, t0 + 1ms));
  latch.hold(3, 0xB, t0 + 1ms);
  EXPECT_FALSE(latch.allows(3, 0xA, t0 + 2ms));
}

TEST(WriterLatch, AnOpenedKeyIsKeptByItsHolderUntilAnotherWriterTakesIt) {
  WriterLatch latch;
  latch.hold(3, 0xA, t0);
  latch.open(3);
  EXPECT_EQ(latch.holder(3), 0xAU);
  EXPECT_TRUE(latch.holds_any(0xA));
  EXPECT_TRUE(latch.allows(3, 0xB, t0 + 1ms));
  latch.heard(3, 0xB, t0 + 1ms);  // not its holder: changes nothing
  EXPECT_TRUE(latch.allows(3, 0xB, t0 + 1ms));
  latch.heard(3, 0xA, t0 + 2ms);  // its holder again: closed
  EXPECT_FALSE(latch.allows(3, 0xB, t0 + 3ms));
  latch.open(3);
  latch.hold(3, 0xB, t0 + 4ms);
  EXPECT_FALSE(latch.holds_any(0xA));
  EXPECT_FALSE(latch.allows(3, 0xA, t0 + 5ms)) << "taken: closed for the old holder";
}

TEST(WriterLatch, WithoutATakeoverASilentHolderKeepsTheKey) {
  WriterLatch latch;  // lockstep
  latch.hold(3, 0xA, t0);
  EXPECT_FALSE(latch.allows(3, 0xB, t0 + 1h));
  EXPECT_EQ(latch.holder(3), 0xAU);
}

TEST(WriterLatch, ARealtimeHolderSilentForTheTakeoverTimeGivesTheKeyUp) {
  WriterLatch latch(1s);
  latch.hold(3, 0xA, t0);
  latch.hold(3, 0xA, t0 + 500ms);  // heard again
  EXPECT_FALSE(latch.allows(3, 0xB, t0 + 1400ms));  // silent for 900 ms only
  // Silent since 500 ms: at 1500 ms B may take it over (a restarted UAV).
  ASSERT_TRUE(latch.allows(3, 0xB, t0 + 1500ms));
  latch.hold(3, 0xB, t0 + 1500ms);
  EXPECT_EQ(latch.holder(3), 0xBU);
  EXPECT_FALSE(latch.allows(3, 0xA, t0 + 1600ms));
}

TEST(WriterLatch, AnUnknownWriterIsAllowedAndLatchesNothing) {
  WriterLatch latch;
  EXPECT_TRUE(latch.allows(3, 0, t0));
  latch.hold(3, 0, t0);
  EXPECT_FALSE(latch.holder(3).has_value());
  latch.hold(3, 0xA, t0);
  EXPECT_TRUE(latch.allows(3, 0, t0));
  latch.hold(3, 0, t0);
  EXPECT_EQ(latch.holder(3), 0xAU);
}

TEST(WriterLatch, AHolderHeardInATakeAfterAStallIsNotSilentSoAForgedSampleQueuedAheadOfItsOwnIsRefused) {
  WriterLatch latch(1s);
  latch.hold(1, 0xA, t0);
  // The receiver stalled 3 s; its take holds a forged sample (writer B) and
  // then the holder's own. Judged by the time of the take alone, A would
  // look silent and B would take the UAV.
  const auto take = t0 + 3s;
  EXPECT_TRUE(latch.allows(1, 0xB, take)) << "without heard(): the stall reads as silence";
  latch.heard(1, 0xB, take);  // not the holder: changes nothing
  EXPECT_TRUE(latch.allows(1, 0xB, take));
  latch.heard(1, 0xA, take);
  EXPECT_FALSE(latch.allows(1, 0xB, take));
  EXPECT_TRUE(latch.allows(1, 0xA, take));
  EXPECT_EQ(latch.holder(1), 0xAU);
  // A key nobody holds is not taken by being heard.
  latch.heard(2, 0xC, take);
  EXPECT_EQ(latch.holder(2), std::nullopt);
  // And the holder silent for a lease after that gives the key up as before.
  EXPECT_TRUE(latch.allows(1, 0xB, take + 1s + 1ms));
}

}  // namespace
}  // namespace pheromesh::core
