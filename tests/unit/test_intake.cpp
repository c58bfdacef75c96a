// What the shells do with a received view, field chunk or home UAV state
// (core/intake.hpp), and the place agent's deposit desk (core/receipts.hpp):
// hand-worked cases on small-test (30 x 30 cells, tiles of 6, 2 x 2 regions,
// 4 UAVs, three Shao layers).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "pheromesh/core/intake.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/receipts.hpp"
#include "pheromesh/core/scenario.hpp"

namespace pheromesh::core {
namespace {

ScenarioConfig small_test() {
  auto s = load_scenario(std::string(PHEROMESH_SOURCE_DIR) + "/scenarios/small-test.textproto");
  if (!s) throw std::runtime_error(s.error().message);
  return s.value();
}

struct IntakeRig {
  ScenarioConfig s = small_test();
  MapGeometry geo = s.geometry();
  PolicyTraits traits = policy_traits(s);
  IntakeRules rules{geo, static_cast<int>(traits.layers.size()), traits.layer_ranges, s.uavs};

  TileMsg tile(uint32_t tick, float value) const {
    TileMsg t;
    t.layer = 0;
    t.tile = {1, 1};
    t.tick = tick;
    t.width = 6;
    t.height = 6;
    t.values.assign(36, value);
    return t;
  }
  UavStateMsg state(uint32_t uav, uint32_t tick) const {
    UavStateMsg st;
    st.uav = uav;
    st.tick = tick;
    st.x = 3.5;
    st.y = 3.5;
    st.view = {3, 3};
    return st;
  }
};

TEST(Intake, AViewForAnotherUavIsDroppedAndOneOfATickFarAheadIsRefused) {
  IntakeRig r;
  ViewMsg v;
  v.uav = 2;
  v.tick = 10;
  v.tiles = {r.tile(10, 0.5F)};
  EXPECT_TRUE(check_view(v, 2, 11, r.rules).taken());
  const auto other = check_view(v, 1, 11, r.rules);
  EXPECT_EQ(other.kind, IntakeVerdict::Kind::Drop);
  EXPECT_NE(other.reason.find("addressed to uav 2"), std::string::npos) << other.reason;
  const auto ahead = check_view(v, 2, 9, r.rules);
  EXPECT_EQ(ahead.kind, IntakeVerdict::Kind::Refuse);
  EXPECT_EQ(ahead.refusal, Refusal::TickFarAhead);
  v.tiles[0].values[7] = 1e30F;
  const auto range = check_view(v, 2, 11, r.rules);
  EXPECT_EQ(range.kind, IntakeVerdict::Kind::Refuse);
  EXPECT_EQ(range.refusal, Refusal::ValueOutOfRange);
}

TEST(Intake, ATileOrNeighbourInsideAViewIsJudgedAlone) {
  IntakeRig r;
  TileMsg bad = r.tile(3, 0.5F);
  bad.values.resize(35);  // 6 x 6 cells need 36 values
  EXPECT_EQ(check_view_tile(bad, r.rules).kind, IntakeVerdict::Kind::Drop);
  EXPECT_TRUE(check_view_tile(r.tile(3, 0.5F), r.rules).taken());
  EXPECT_TRUE(check_neighbour(r.state(3, 3), r.rules).taken());
  const auto stranger = check_neighbour(r.state(4, 3), r.rules);  // the swarm has UAVs 0..3
  EXPECT_EQ(stranger.kind, IntakeVerdict::Kind::Refuse);
  EXPECT_EQ(stranger.refusal, Refusal::UnknownUav);
}

TEST(Intake, AFieldChunkIsMalformedForANonexistentRegionAndRefusedWithAStranger) {
  IntakeRig r;
  FieldMsg f;
  f.region = 3;
  f.tick = 5;
  f.tiles = {r.tile(5, 0.25F)};
  f.uavs = {r.state(1, 5)};
  EXPECT_TRUE(check_field_chunk(f, 6, r.rules).taken());
  FieldMsg nowhere = f;
  nowhere.region = 4;  // 2 x 2 regions: 0..3
  EXPECT_EQ(check_field_chunk(nowhere, 6, r.rules).kind, IntakeVerdict::Kind::Drop);
  FieldMsg stranger = f;
  stranger.uavs[0].uav = 9;
  const auto v = check_field_chunk(stranger, 6, r.rules);
  EXPECT_EQ(v.kind, IntakeVerdict::Kind::Refuse);
  EXPECT_EQ(v.refusal, Refusal::UnknownUav);
  EXPECT_EQ(check_field_chunk(f, 4, r.rules).refusal, Refusal::TickFarAhead);
}

TEST(Intake, AHomeStateThatJumpsFurtherThanTheUavFliesIsRefused) {
  IntakeRig r;
  const UavStateMsg before = r.state(1, 5);
  UavStateMsg next = r.state(1, 6);
  next.x = 4.5;  // one cell in one tick
  EXPECT_TRUE(check_home_state(next, &before, {0, 0}, r.traits.max_step, 7, r.rules).taken());
  next.x = 25.5;  // 22 cells in one tick
  const auto v = check_home_state(next, &before, {0, 0}, r.traits.max_step, 7, r.rules);
  EXPECT_EQ(v.kind, IntakeVerdict::Kind::Refuse);
  EXPECT_EQ(v.refusal, Refusal::ImplausibleState);
}

DepositMsg deposit(uint32_t uav, uint32_t seq, RegionId region) {
  DepositMsg d;
  d.uav = uav;
  d.seq = seq;
  d.region = region;
  return d;
}

TEST(DepositDesk, OwnDepositsAreAppliedOthersForwardedAndCopiesDroppedOnlyWhenAsked) {
  // Region 1 of 4, 4 UAVs: UAV 1 is homed on it (uav mod regions).
  DepositDesk desk(1, 4, 4, /*drop_copies=*/true);
  EXPECT_EQ(desk.take(deposit(1, 1, 1), 0), DepositRoute::Apply);
  EXPECT_EQ(desk.take(deposit(1, 2, 3), 0), DepositRoute::Forward);
  EXPECT_EQ(desk.take(deposit(1, 2, 3), 0), DepositRoute::Copy) << "the second replica's forward";
  EXPECT_EQ(desk.take(deposit(2, 7, 9), 0), DepositRoute::Apply) << "no region 9: PlaceCore rejects it with the reason";
  EXPECT_EQ(desk.copies(), 1U);
  EXPECT_EQ(desk.taken_from(1), 2U) << "seqs 1 and 2 of its home UAV, whether applied or forwarded; the copy not again";
  EXPECT_EQ(desk.taken_from(2), 0U) << "UAV 2 is homed on region 2";
  EXPECT_EQ(desk.ack(1), 2U) << "its views confirm seq 2";
  EXPECT_EQ(desk.ack(2), 0U) << "UAV 2 is not homed here";
  DepositDesk plain(1, 4, 4, /*drop_copies=*/false);
  EXPECT_EQ(plain.take(deposit(1, 5, 1), 0), DepositRoute::Apply);
  EXPECT_EQ(plain.take(deposit(1, 5, 1), 0), DepositRoute::Apply) << "a replay: PlaceCore rejects it with its reason";
  EXPECT_EQ(plain.taken_from(1), 1U) << "a replayed seq is not a second deposit of the UAV";
}

TEST(SeenDeposits, ACopyWithinTheWindowIsSeenAndOneOlderThanItIsNot) {
  SeenDeposits seen(128);
  constexpr uint32_t kTick = 1000;  // late enough for every seq below to be reachable
  EXPECT_FALSE(seen.seen_before(3, 1000, kTick));
  EXPECT_TRUE(seen.seen_before(3, 1000, kTick));
  EXPECT_FALSE(seen.seen_before(3, 990, kTick)) << "below the highest, inside the window, new";
  EXPECT_TRUE(seen.seen_before(3, 990, kTick));
  EXPECT_FALSE(seen.seen_before(7, 1000, kTick)) << "per UAV";
  EXPECT_FALSE(seen.seen_before(3, 1100, kTick));
  EXPECT_TRUE(seen.seen_before(3, 990, kTick)) << "100 below the highest: still remembered";
  EXPECT_FALSE(seen.seen_before(3, 1118, kTick)) << "the window moves: 990's slot is free again";
  EXPECT_FALSE(seen.seen_before(3, 990, kTick)) << "128 below the highest: too old to tell";
  EXPECT_TRUE(seen.seen_before(3, 1100, kTick));
  EXPECT_FALSE(seen.seen_before(3, 1100 + 128, kTick)) << "the slot of 1100, a window later, is a new seq";
  EXPECT_FALSE(seen.seen_before(3, 100000, kTick + 400)) << "a jump past the whole window (reachable 400 ticks on) forgets all";
  EXPECT_FALSE(seen.seen_before(3, 99999, kTick + 400));
}

// seen() asks without remembering: a lockstep gateway lets a forwarded copy
// through to the desk, which drops it, and refuses a forwarded new one.
TEST(SeenDeposits, SeenAsksWithoutRemembering) {
  SeenDeposits seen(128);
  constexpr uint32_t kTick = 1000;
  EXPECT_FALSE(seen.seen(3, 1000));
  EXPECT_FALSE(seen.seen(3, 1000)) << "asking remembered nothing";
  EXPECT_FALSE(seen.seen_before(3, 1000, kTick));
  EXPECT_TRUE(seen.seen(3, 1000));
  EXPECT_FALSE(seen.seen(3, 1001)) << "above the highest";
  EXPECT_FALSE(seen.seen(3, 999));
  EXPECT_FALSE(seen.seen(4, 1000)) << "per UAV";
  EXPECT_FALSE(seen.seen_before(3, 1200, kTick));
  EXPECT_FALSE(seen.seen(3, 1000)) << "older than the window";
}

// Soaks: a place agent takes deposits for hours (issue 28); what it keeps to
// spot copies stays at window / 8 bytes per UAV however many it took.
TEST(SeenDeposits, ItsMemoryStaysBoundedByTheWindowPerUavOverALongRun) {
  SeenDeposits seen;  // the place agents' window: 4096 seqs
  constexpr uint32_t kTick = 1000;
  for (uint32_t seq = 1; seq <= 200000; ++seq) {
    for (uint32_t uav = 0; uav < 20; ++uav) {
      if ((seq + uav) % 3 != 0) {
        EXPECT_FALSE(seen.seen_before(uav, seq, kTick));
      }
    }
    if (seq == 5000) {
      EXPECT_EQ(seen.bytes(), 20U * 4096U / 8U);
    }
  }
  EXPECT_EQ(seen.bytes(), 20U * 4096U / 8U) << "4.5 MiB with a std::set of 4096 seqs per UAV";
  EXPECT_TRUE(seen.seen_before(5, 199998, kTick));  // (199998 + 5) % 3 != 0: seen above
  EXPECT_FALSE(seen.seen_before(5, 200000 - 4096, kTick));
}

// A forger's deposit as uav 0 with seq 2^32-1 (pheromesh-test-probe forge):
// refused by PlaceCore, and it must not move the window, or every real seq
// falls below it and a re-sent copy is applied again (CI: a lockstep run
// rejected a re-sent real deposit as a replay).
TEST(SeenDeposits, ASeqFurtherAheadThanTheUavCanHaveReachedIsNotRemembered) {
  SeenDeposits seen(128);
  EXPECT_FALSE(seen.seen_before(0, 4294967295U, 5)) << "forged before any real one";
  EXPECT_FALSE(seen.seen_before(0, 4294967295U, 5)) << "not remembered";
  EXPECT_FALSE(seen.seen_before(0, 40, 5));
  EXPECT_FALSE(seen.seen_before(0, 4294967295U, 6));
  EXPECT_TRUE(seen.seen_before(0, 40, 6)) << "a copy of a real deposit is still one";
  // Reachable: 256 deposits a tick at most, + 64 ticks of slack.
  EXPECT_FALSE(seen.seen_before(0, 40 + 256 * (64 + 10), 16));
  EXPECT_TRUE(seen.seen_before(0, 40 + 256 * (64 + 10), 16));
  EXPECT_FALSE(seen.seen_before(0, 40 + 256 * (64 + 10) + 256 * 64 + 257, 16)) << "too far ahead of the new top";
  EXPECT_TRUE(seen.seen_before(0, 40 + 256 * (64 + 10), 16)) << "the window did not move";
}

TEST(DepositDesk, AUavItIsTheBackupGatewayOfIsConfirmedAndCountedLikeAHomeUav) {
  // Region 2 of 4; UAV 1 (home 1) is served here once its home died.
  DepositDesk desk(2, 4, 4, true);
  EXPECT_EQ(desk.take(deposit(1, 8, 3), 0), DepositRoute::Forward);
  EXPECT_EQ(desk.ack(1), 0U) << "not served here yet";
  EXPECT_EQ(desk.taken_from(1), 0U);
  desk.serve(1);
  EXPECT_EQ(desk.take(deposit(1, 9, 2), 1), DepositRoute::Apply);
  EXPECT_EQ(desk.take(deposit(1, 10, 0), 1), DepositRoute::Forward);
  EXPECT_EQ(desk.ack(1), 10U);
  EXPECT_EQ(desk.taken_from(1), 2U);
}

TEST(Gateway, TheHomeWhileAliveThenTheNextRegionThenNone) {
  // 4 regions: UAV 6 is homed on region 2, its backup is region 3; UAV 7's
  // home is region 3 and its backup wraps to region 0.
  const auto none_dead = [](RegionId) { return false; };
  EXPECT_EQ(home_region(6, 4), 2U);
  EXPECT_EQ(backup_region(6, 4), 3U);
  EXPECT_EQ(backup_region(7, 4), 0U);
  EXPECT_EQ(gateway_region(6, 4, none_dead), std::optional<RegionId>(2));
  EXPECT_EQ(gateway_region(6, 4, [](RegionId r) { return r == 2; }), std::optional<RegionId>(3));
  EXPECT_EQ(gateway_region(7, 4, [](RegionId r) { return r == 3; }), std::optional<RegionId>(0));
  EXPECT_EQ(gateway_region(6, 4, [](RegionId r) { return r == 2 || r == 3; }), std::nullopt);
  EXPECT_EQ(gateway_region(6, 4, [](RegionId r) { return r == 3; }), std::optional<RegionId>(2)) << "home alive";
  EXPECT_EQ(gateway_region(0, 1, [](RegionId) { return true; }), std::nullopt) << "one region: no backup";
}

TEST(DepositDesk, ASequenceNumberForgedFarAheadConfirmsNothing) {
  DepositDesk desk(1, 4, 4, false);
  desk.take(deposit(1, 3, 1), 0);
  desk.take(deposit(1, 4000000, 1), 1);  // more than the UAV can have deposited in a tick
  EXPECT_EQ(desk.ack(1), 3U);
  desk.take(deposit(1, 4, 1), 1);
  EXPECT_EQ(desk.ack(1), 4U);
}

}  // namespace
}  // namespace pheromesh::core
