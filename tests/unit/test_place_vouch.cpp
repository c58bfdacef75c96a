// core::PlaceVouch and core::Parked: which processes are place agents, as a
// receiver heard them, and the samples that wait for their process to be
// heard as one (issue 28: a forger writes from a process of its own).
#include <gtest/gtest.h>

#include <chrono>
#include <vector>

#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/place_vouch.hpp"
#include "pheromesh/core/writer_latch.hpp"

namespace pheromesh::core {
namespace {

using namespace std::chrono_literals;
using Clock = PlaceVouch::Clock;
const Clock::time_point t0 = Clock::time_point{} + 100s;

TEST(PlaceVouch, TheFirstProcessToClaimAPlaceIdHoldsItAndIsVouchedForAnotherIsNot) {
  PlaceVouch v(2s);
  EXPECT_FALSE(v.vouched(0xA));
  EXPECT_TRUE(v.claim(place_id(3, 0), 0xA, t0));
  EXPECT_TRUE(v.vouched(0xA));
  EXPECT_FALSE(v.claim(place_id(3, 0), 0xF, t0 + 100ms)) << "a forger's health for a held id";
  EXPECT_FALSE(v.vouched(0xF)) << "a refused claim vouches for nothing";
  EXPECT_TRUE(v.speaks_for(place_id(3, 0), 0xA));
  EXPECT_FALSE(v.speaks_for(place_id(3, 0), 0xF));
  EXPECT_TRUE(v.speaks_for(place_id(3, 1), 0xF)) << "a free id: nobody to compare with";
  // Its standby is a process of its own, and both are vouched for.
  EXPECT_TRUE(v.claim(place_id(3, 1), 0xB, t0));
  EXPECT_TRUE(v.vouched(0xB));
  // Unknown (a transport that cannot tell): always, and it holds nothing.
  EXPECT_TRUE(v.vouched(0));
  EXPECT_TRUE(v.claim(place_id(3, 0), 0, t0));
  EXPECT_TRUE(v.speaks_for(place_id(3, 0), 0xA));
}

TEST(PlaceVouch, AHolderSilentForTheTakeoverTimeGivesItsIdToTheNextProcessHeard) {
  PlaceVouch v(2s);
  ASSERT_TRUE(v.claim(7, 0xA, t0));
  v.heard(7, 0xA, t0 + 1500ms);  // it wrote: not silent
  EXPECT_FALSE(v.claim(7, 0xB, t0 + 3s)) << "1.5 s after its last sample";
  EXPECT_TRUE(v.claim(7, 0xB, t0 + 3600ms)) << "2.1 s after it";
  EXPECT_FALSE(v.vouched(0xA)) << "it held one id only";
  EXPECT_TRUE(v.vouched(0xB));
}

TEST(PlaceVouch, ALaterLifeTakesItsIdFromAHolderSilentForASecondNotSooner) {
  PlaceVouch v(10s);  // a lockstep takeover
  ASSERT_TRUE(v.claim(2, 0xA, t0));
  EXPECT_FALSE(v.claim(2, 0xB, t0 + 900ms, /*new_life=*/true)) << "its holder wrote 0.9 s ago: alive";
  EXPECT_TRUE(v.claim(2, 0xB, t0 + 1100ms, /*new_life=*/true)) << "killed and started again";
  EXPECT_TRUE(v.vouched(0xB));
  EXPECT_FALSE(v.vouched(0xA));
}

TEST(PlaceVouch, ADepartedIdGoesToTheNextProcessAndItsHolderIsVouchedForTillThen) {
  PlaceVouch v(10s);  // a lockstep takeover
  ASSERT_TRUE(v.claim(1, 0xA, t0));
  ASSERT_TRUE(v.claim(2, 0xA, t0));  // a process that writes as two ids (tests)
  v.departed(1);
  v.departed(2);
  EXPECT_TRUE(v.vouched(0xA)) << "a lapse under loss: its relays still arrive and are taken";
  EXPECT_TRUE(v.speaks_for(1, 0xA));
  // Place 1 was killed and started again: the new process takes id 1 at
  // once (no takeover time), and the old one holds id 2 only.
  EXPECT_TRUE(v.claim(1, 0xC, t0 + 1ms));
  EXPECT_FALSE(v.speaks_for(1, 0xA));
  EXPECT_TRUE(v.vouched(0xA));
  // Place 2's holder is heard again (its health): the id is closed again.
  v.heard(2, 0xA, t0 + 2ms);
  EXPECT_FALSE(v.claim(2, 0xD, t0 + 3ms)) << "its holder lives: a forger cannot take its id";
  EXPECT_TRUE(v.claim(2, 0xD, t0 + 3ms + 10s)) << "silent for the takeover time";
  EXPECT_FALSE(v.vouched(0xA));
  EXPECT_EQ(v.park_for(), 12s) << "the takeover time and 2 s";
}

TEST(WriterLatch, HoldsAnyCountsTheKeysEachWriterHoldsAcrossTakeoversAndReleases) {
  WriterLatch latch(1s);
  latch.hold(1, 0xA, t0);
  latch.hold(2, 0xA, t0);
  latch.hold(1, 0xB, t0 + 2s);  // took key 1 over
  EXPECT_TRUE(latch.holds_any(0xA));
  EXPECT_TRUE(latch.holds_any(0xB));
  latch.release(2);
  EXPECT_FALSE(latch.holds_any(0xA));
  latch.hold(1, 0xB, t0 + 3s);  // again: still one key
  latch.release(1);
  EXPECT_FALSE(latch.holds_any(0xB));
  EXPECT_TRUE(latch.holds_any(0)) << "unknown: always";
}

TEST(WriterLatch, HeldIsFalseOnceTheHolderWasSilentForTheTakeoverTime) {
  WriterLatch latch(1s);
  EXPECT_FALSE(latch.held(4, t0));
  latch.hold(4, 0xA, t0);
  EXPECT_TRUE(latch.held(4, t0 + 900ms));
  EXPECT_FALSE(latch.held(4, t0 + 1s));
  EXPECT_EQ(latch.last_heard(4), t0);
  WriterLatch forever;  // no takeover: held until released
  forever.hold(4, 0xA, t0);
  EXPECT_TRUE(forever.held(4, t0 + 1h));
}

struct Sample {
  int n = 0;
  uint64_t participant = 0;
};

TEST(Parked, ASweepTakesTheVouchedInOrderRefusesTheExpiredAndKeepsTheRest) {
  Parked<Sample> p;
  EXPECT_FALSE(p.park({1, 0xA}, t0));
  EXPECT_FALSE(p.park({2, 0xF}, t0 + 1s));
  EXPECT_FALSE(p.park({3, 0xA}, t0 + 2s));
  EXPECT_FALSE(p.park({4, 0xF}, t0 + 3s));
  std::vector<Sample> ready, expired;
  p.sweep(t0 + 3500ms, 2s, [](const Sample& s) { return s.participant == 0xA; }, ready, expired);
  ASSERT_EQ(ready.size(), 2U);
  EXPECT_EQ(ready[0].n, 1);
  EXPECT_EQ(ready[1].n, 3);
  ASSERT_EQ(expired.size(), 1U) << "sample 2 waited 2.5 s; sample 4 0.5 s";
  EXPECT_EQ(expired[0].n, 2);
  EXPECT_EQ(p.size(), 1U);
  const auto rest = p.take_all();
  ASSERT_EQ(rest.size(), 1U);
  EXPECT_EQ(rest[0].n, 4);
  EXPECT_TRUE(p.empty());
}

TEST(Parked, TheBoundPushesOutTheOldestSample) {
  Parked<Sample> p(2);
  EXPECT_FALSE(p.park({1, 0xF}, t0));
  EXPECT_FALSE(p.park({2, 0xF}, t0));
  const auto out = p.park({3, 0xF}, t0);
  ASSERT_TRUE(out.has_value());
  EXPECT_EQ(out->n, 1);
  EXPECT_EQ(p.size(), 2U);
}

}  // namespace
}  // namespace pheromesh::core
