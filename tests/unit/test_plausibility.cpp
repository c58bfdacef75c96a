// What a receiver refuses although the sample is well formed (issue 16):
// hand-worked cases for each check of plausibility.hpp, the place agent's and
// the recorder's use of them, guards that the attacks do have an effect
// without the checks, and honest simulated runs of every scenario that refuse
// nothing (so lockstep == simulator stays exact).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "pheromesh/core/place_core.hpp"
#include "pheromesh/core/plausibility.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/run_metrics.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"
#include "pheromesh/core/world.hpp"
#include "unit_support.hpp"

namespace pheromesh::core {
namespace {

constexpr uint32_t kMaxSeq = std::numeric_limits<uint32_t>::max();

using test::expect_reason;

ScenarioConfig small_test() {
  auto s = load_scenario(std::string(PHEROMESH_SOURCE_DIR) + "/scenarios/small-test.textproto");
  if (!s) throw std::runtime_error(s.error().message);
  return s.value();
}

// ------------------------------------------------------------------ checks

TEST(Plausibility, UavIdsOutsideTheSwarmAreRefused) {
  EXPECT_FALSE(check_uav_id(0, 4));
  EXPECT_FALSE(check_uav_id(3, 4));
  expect_reason(check_uav_id(4, 4), "not one of the swarm's 4");
  expect_reason(check_uav_id(900000, 4), "uav 900000");
  expect_reason(check_uav_id(0, 0), "uav 0");
}

TEST(Plausibility, ASequenceNumberIsAcceptedOnlyAsFarAheadAsTheUavCanHaveDeposited) {
  // No deposit yet, at tick 0: 256 * (0 + 64) = 16384 are reachable.
  EXPECT_FALSE(check_seq_reachable(1, std::nullopt, 0));
  EXPECT_FALSE(check_seq_reachable(16384, std::nullopt, 0));
  expect_reason(check_seq_reachable(16385, std::nullopt, 0), "further ahead");
  // The issue's attack: 2^32 - 1 under a real UAV's id.
  expect_reason(check_seq_reachable(kMaxSeq, std::nullopt, 100), "4294967295");
  expect_reason(check_seq_reachable(kMaxSeq, 40, 1000), "in 1000 ticks");
  // Last 100, 10 ticks ago: 256 * (10 + 64) = 18944 further.
  EXPECT_FALSE(check_seq_reachable(100 + 18944, 100, 10));
  expect_reason(check_seq_reachable(100 + 18945, 100, 10), "further ahead of 100");
  // Not above the last: a duplicate, the caller's business.
  EXPECT_FALSE(check_seq_reachable(50, 100, 0));
  // The start of a restarted process's life (launch/launcher.cpp: life << 24).
  EXPECT_FALSE(check_seq_reachable((1U << 24) + 1, 500, 3));
  EXPECT_FALSE(check_seq_reachable((2U << 24) + 1, 500, 3));
  expect_reason(check_seq_reachable((3U << 24) + 1, 500, 3), "further ahead");
  // A new life's seq must still be near its base: 20000 > 256 * (0 + 64).
  expect_reason(check_seq_reachable((1U << 24) + 20000, 500, 0), "further ahead");
}

TEST(Plausibility, TheTickCeilingFollowsTheTimeSinceTheLaunch) {
  // (seconds + 30) * rate + 50.
  EXPECT_EQ(realtime_tick_ceiling(0.0, 25.0), 800U);
  EXPECT_EQ(realtime_tick_ceiling(60.0, 10.0), 950U);
  EXPECT_EQ(realtime_tick_ceiling(-5.0, 10.0), 350U);    // a clock behind the launcher's counts as 0 s
  EXPECT_EQ(realtime_tick_ceiling(1.0, 0.0), kMaxSeq);   // no rate: no ceiling
  EXPECT_EQ(realtime_tick_ceiling(1e12, 1e6), kMaxSeq);  // saturates
  EXPECT_EQ(lockstep_tick_ceiling(7), 8U);
  EXPECT_FALSE(check_tick_reachable(800, 800, "tile"));
  expect_reason(check_tick_reachable(801, 800, "tile"), "tile of tick 801, beyond tick 800");
  expect_reason(check_tick_reachable(kMaxSeq, 8, "state"), "state of tick 4294967295");
}

TEST(Plausibility, OnOneHostTheTickCeilingAllowsTwoSecondsAndFiveTicksNotHalfAMinute) {
  // (seconds + 2) * rate + 5 against (seconds + 30) * rate + 50: 60 s into
  // a 5 Hz run (tick 300 at most), a forged field chunk 150 ticks ahead is
  // beyond the first and within the second.
  EXPECT_EQ(realtime_tick_ceiling(60.0, 5.0, kOneHostSlack), 315U);
  EXPECT_EQ(realtime_tick_ceiling(60.0, 5.0), 500U);
  EXPECT_TRUE(check_tick_reachable(300 + 150, realtime_tick_ceiling(60.0, 5.0, kOneHostSlack), "field chunk"));
  EXPECT_FALSE(check_tick_reachable(300 + 150, realtime_tick_ceiling(60.0, 5.0), "field chunk"));
  EXPECT_EQ(realtime_tick_ceiling(0.0, 25.0, kOneHostSlack), 55U);
}

TEST(Plausibility, ValuesOutsideALayersRangeAreRefused) {
  const ValueRange r{0.0F, 10.0F};
  const std::vector<float> good{0.0F, 5.0F, 10.0F};
  EXPECT_FALSE(check_values_in_range(good, r, "tile"));
  expect_reason(check_values_in_range(std::vector<float>{1.0F, 1e30F}, r, "tile"), "outside [0.000000, 10.000000]");
  expect_reason(check_values_in_range(std::vector<float>{-0.1F}, r, "halo"), "halo value -0.1");
  expect_reason(check_values_in_range(std::vector<float>{std::numeric_limits<float>::quiet_NaN()}, r, "tile"), "nan");
  TileMsg t;
  t.layer = 1;
  t.values = {1e30F};
  const std::vector<ValueRange> ranges{{0.0F, 10.0F}, {0.0F, 100.0F}};
  expect_reason(check_tile_range(t, ranges), "tile value");
  t.values = {99.0F};
  EXPECT_FALSE(check_tile_range(t, ranges));
  t.layer = 2;  // a layer without a range is not judged here (check_tile refuses unknown layers)
  t.values = {1e30F};
  EXPECT_FALSE(check_tile_range(t, ranges));
}

TEST(Plausibility, EveryPolicyGivesEveryLayerARangeThatRefusesTheIssues1e30) {
  for (const auto& entry : std::filesystem::directory_iterator(std::string(PHEROMESH_SOURCE_DIR) + "/scenarios")) {
    auto s = load_scenario(entry.path().string());
    ASSERT_TRUE(s) << entry.path();
    const PolicyTraits t = policy_traits(s.value());
    ASSERT_EQ(t.layer_ranges.size(), t.layers.size()) << entry.path();
    for (const auto& r : t.layer_ranges) {
      EXPECT_LT(r.hi, 1e30F) << entry.path();
      EXPECT_GE(r.lo, 0.0F) << entry.path();
    }
    EXPECT_GT(t.max_step, 0.0) << entry.path();
  }
}

UavStateMsg state_at(uint32_t uav, uint32_t tick, double x, double y) {
  UavStateMsg s;
  s.uav = uav;
  s.tick = tick;
  s.x = x;
  s.y = y;
  return s;
}

TEST(Plausibility, AStateFurtherThanTheUavFliesIsRefused) {
  const Cell start{5, 5};
  // First state: from the start cell in tick + 1 steps, 1.5 cells each, + 1.5.
  EXPECT_FALSE(check_state_motion(state_at(0, 0, 6, 5), nullptr, start, 1.5, false));
  EXPECT_FALSE(check_state_motion(state_at(0, 0, 8, 5), nullptr, start, 1.5, false));  // 3 <= 1.5 + 1.5
  expect_reason(check_state_motion(state_at(0, 0, 8.1, 5), nullptr, start, 1.5, false), "further from its start");
  expect_reason(check_state_motion(state_at(0, 0, 25, 25), nullptr, start, 1.5, false), "1.5");
  // From the last state: 2 ticks, 1.5 * 2 + 1.5 = 4.5 cells.
  const UavStateMsg last = state_at(0, 10, 10, 10);
  EXPECT_FALSE(check_state_motion(state_at(0, 12, 13, 13), &last, start, 1.5, false));                     // 4.24
  expect_reason(check_state_motion(state_at(0, 12, 14, 14), &last, start, 1.5, false), "its last state");  // 5.66
  EXPECT_FALSE(check_state_motion(state_at(0, 10, 10, 10), &last, start, 1.5, false));  // the same state again
  // A tick that went back, near the start: a restarted UAV, only if it may be one.
  const UavStateMsg far = state_at(0, 10, 40, 40);
  expect_reason(check_state_motion(state_at(0, 2, 6, 6), &far, start, 1.5, false), "its last state");
  EXPECT_FALSE(check_state_motion(state_at(0, 2, 6, 6), &far, start, 1.5, true));
  // ... and a restart does not excuse a jump forward in time.
  expect_reason(check_state_motion(state_at(0, 11, 6, 6), &far, start, 1.5, true), "its last state");
}

TEST(Plausibility, ADetectionMustBeOfARealTargetNearTheReportingUav) {
  const std::vector<Cell> targets{{3, 4}, {20, 20}};
  const UavStateMsg seen = state_at(2, 10, 5, 4);
  // Radius 4 + 1.5 * (0 + 1) + 1.5 = 7 cells.
  EXPECT_FALSE(check_detection({2, 10, 0, {3, 4}}, targets, &seen, 4.0, 1.5));
  expect_reason(check_detection({2, 10, 1, {20, 20}}, targets, &seen, 4.0, 1.5), "cells away");
  expect_reason(check_detection({2, 10, 5, {3, 4}}, targets, &seen, 4.0, 1.5), "not one of the 2");
  expect_reason(check_detection({2, 10, -1, {3, 4}}, targets, &seen, 4.0, 1.5), "not one of the 2");
  expect_reason(check_detection({2, 10, 0, {4, 4}}, targets, &seen, 4.0, 1.5), "which is at (3, 4)");
  expect_reason(check_detection({2, 10, 0, {3, 4}}, targets, nullptr, 4.0, 1.5), "never seen flying");
  // The state 6 ticks later: the UAV may have flown 1.5 * 7 further.
  const UavStateMsg later = state_at(2, 16, 12, 12);
  EXPECT_FALSE(check_detection({2, 10, 0, {3, 4}}, targets, &later, 4.0, 1.5));
}

TEST(Plausibility, ADepositBeyondItsUavsReachFromItsLastAcceptedStateIsRefused) {
  const Cell start{1, 1};
  DepositMsg d;
  d.uav = 0;
  d.tick = 10;
  // From the last accepted state of the same tick: reach 4 + one step 1.5 + slack 1.5 = 7.
  const UavStateMsg at = state_at(0, 10, 5, 5);
  d.cell = {12, 5};
  EXPECT_FALSE(check_deposit_reach(d, &at, start, 1.5, 4.0));
  d.cell = {15, 5};  // 10 cells away: the issue's forged deposit
  expect_reason(check_deposit_reach(d, &at, start, 1.5, 4.0), "cells from its last accepted state");
  // Two ticks after the last accepted state: 3 more cells.
  d.tick = 12;
  d.cell = {15, 5};
  EXPECT_FALSE(check_deposit_reach(d, &at, start, 1.5, 4.0));
  // No state accepted yet: from the start cell in tick + 1 ticks.
  d.tick = 0;
  d.cell = {8, 1};  // 7 <= 4 + 1.5 + 1.5
  EXPECT_FALSE(check_deposit_reach(d, nullptr, start, 1.5, 4.0));
  d.cell = {9, 1};
  expect_reason(check_deposit_reach(d, nullptr, start, 1.5, 4.0), "from its start cell");
  // An infinite reach (Duan's mesh-wide marks) judges nothing.
  d.cell = {29, 29};
  EXPECT_FALSE(check_deposit_reach(d, nullptr, start, 1.5, std::numeric_limits<double>::infinity()));
}

TEST(Plausibility, RefusalCountsSaturateAndNameEveryReason) {
  RefusalCounts c;
  c.add(Refusal::ForeignClock);
  c.add(Refusal::ForeignClock, std::numeric_limits<uint32_t>::max());
  EXPECT_EQ(c[Refusal::ForeignClock], std::numeric_limits<uint32_t>::max());
  c.add(Refusal::UnknownUav, 2);
  EXPECT_EQ(c.total(), uint64_t{std::numeric_limits<uint32_t>::max()} + 2);
  std::vector<std::string> names;
  for (std::size_t i = 0; i < kRefusalCount; ++i) names.emplace_back(refusal_name(static_cast<Refusal>(i)));
  EXPECT_EQ(names,
            (std::vector<std::string>{"unknown_uav", "seq_far_ahead", "tick_far_ahead", "value_out_of_range",
                                      "foreign_clock", "implausible_detection", "implausible_state", "foreign_writer",
                                      "implausible_deposit", "unknown_place", "stale_detection", "foreign_report",
                                      "unannounced_deposit", "refused_state_deposit"}));
}

// --------------------------------------------------------- the place agent

DepositMsg visit(uint32_t uav, uint32_t seq, uint32_t tick) {
  DepositMsg d;
  d.uav = uav;
  d.seq = seq;
  d.tick = tick;
  d.region = 0;
  d.kind = static_cast<uint8_t>(DepositKind::PathVisit);
  d.cell = {2, 2};
  d.amount = 1.0F;
  return d;
}

TEST(PlacePlausibility, DepositsOfUavIdsOutsideTheSwarmAreRejectedAndCounted) {
  const ScenarioConfig s = small_test();  // 4 UAVs
  PlaceCore p(s, 0);
  std::vector<DepositMsg> in{visit(900000, 1, 0), visit(4, 1, 0), visit(3, 1, 0)};
  std::vector<TargetEventMsg> events;
  std::vector<std::string> why;
  p.begin_tick(in, 0, events, &why);
  EXPECT_EQ(p.ledger().received, 3U);
  EXPECT_EQ(p.ledger().applied, 1U);
  EXPECT_EQ(p.ledger().rejected(), 2U);
  EXPECT_EQ(p.ledger().refused[Refusal::UnknownUav], 2U);
  EXPECT_EQ(p.ledger().rejected_by_reason.at("uav id outside the swarm"), 2U);
  ASSERT_EQ(why.size(), 2U);
  EXPECT_NE(why[0].find("uav 4 seq 1"), std::string::npos) << why[0];
}

TEST(PlacePlausibility, AForgedDepositTenCellsFromItsUavIsRejectedRefusedAndDoesNotLatchItsSeq) {
  const ScenarioConfig s = small_test();
  PlaceCore p(s, 0);
  const UavStateMsg at = state_at(0, 0, 2, 2);
  const PlaceCore::DepositReach reach = [&](const DepositMsg& d) {
    return check_deposit_reach(d, &at, {1, 1}, 1.5, s.aco.sensor_radius);
  };
  DepositMsg forged = visit(0, 1, 0);
  forged.cell = {12, 2};  // 10 cells from (2, 2)
  std::vector<DepositMsg> in{forged};
  std::vector<TargetEventMsg> events;
  p.begin_tick(in, 0, events, nullptr, &reach);
  EXPECT_EQ(p.ledger().received, 1U);
  EXPECT_EQ(p.ledger().applied, 0U);
  EXPECT_EQ(p.ledger().rejected(), 1U);
  EXPECT_EQ(p.ledger().refused[Refusal::ImplausibleDeposit], 1U);
  EXPECT_EQ(p.value(static_cast<int>(0), {12, 2}), 0.0F);
  // The real UAV's deposit with the same seq at its own cell still lands.
  std::vector<DepositMsg> real{visit(0, 1, 1)};
  p.begin_tick(real, 1, events, nullptr, &reach);
  EXPECT_EQ(p.ledger().applied, 1U);
  // Guard: without the judge the forged one is applied.
  PlaceCore open(s, 0);
  std::vector<DepositMsg> again{forged};
  open.begin_tick(again, 0, events);
  EXPECT_EQ(open.ledger().applied, 1U);
}

TEST(PlacePlausibility, ASequenceNumberFarAheadDoesNotLockTheUavOut) {
  const ScenarioConfig s = small_test();
  PlaceCore p(s, 0);
  std::vector<TargetEventMsg> events;
  std::vector<DepositMsg> t0{visit(1, 1, 0), visit(1, kMaxSeq, 0)};  // the forged one under uav 1's id
  p.begin_tick(t0, 0, events);
  std::vector<DepositMsg> t1{visit(1, 2, 1), visit(1, 3, 1)};
  p.begin_tick(t1, 1, events);
  EXPECT_EQ(p.ledger().applied, 3U);  // the UAV keeps delivering
  EXPECT_EQ(p.ledger().rejected(), 1U);
  EXPECT_EQ(p.ledger().refused[Refusal::SeqFarAhead], 1U);
  // A replay is still a duplicate, not a refusal.
  std::vector<DepositMsg> again{visit(1, 3, 2)};
  p.begin_tick(again, 2, events);
  EXPECT_EQ(p.ledger().rejected_by_reason.at("duplicate or out-of-order sequence number"), 1U);
  EXPECT_EQ(p.ledger().refused.total(), 1U);
}

TEST(PlacePlausibility, ADepositRefusedOutrightIsOneTheTickTurnsAwayForWhatItSaysWhoeverSentIt) {
  // What a place agent leaves to its core whoever forwarded it
  // (core::PlaceIntake::judge_forwarded): malformed, a UAV outside the
  // swarm, a sequence number it cannot have reached (issue 43).
  const ScenarioConfig s = small_test();
  PlaceCore p(s, 0);
  EXPECT_FALSE(p.refuses_outright(visit(1, 1, 0), 0));
  EXPECT_TRUE(p.refuses_outright(visit(900000, 1, 0), 0));
  EXPECT_TRUE(p.refuses_outright(visit(1, kMaxSeq, 0), 0));
  DepositMsg malformed = visit(1, 1, 0);
  malformed.kind = 200;
  EXPECT_TRUE(p.refuses_outright(malformed, 0));
  EXPECT_FALSE(p.refuses(malformed, 0)) << "refuses() judges the name and the sequence only";
}

TEST(PlacePlausibility, GuardASequenceNumberTheLedgerLatchesLocksTheUavOut) {
  // What the seq check prevents: a forged seq that is accepted (here one
  // within reach) becomes the UAV's last, and its real deposits below it are
  // rejected as duplicates. Far ahead, the same attack is refused (above).
  const ScenarioConfig s = small_test();
  PlaceCore p(s, 0);
  std::vector<TargetEventMsg> events;
  std::vector<DepositMsg> t0{visit(1, 1, 0), visit(1, 10000, 0)};
  p.begin_tick(t0, 0, events);
  std::vector<DepositMsg> t1{visit(1, 2, 1), visit(1, 3, 1)};
  p.begin_tick(t1, 1, events);
  EXPECT_EQ(p.ledger().applied, 2U);
  EXPECT_EQ(p.ledger().rejected_by_reason.at("duplicate or out-of-order sequence number"), 2U);
}

TEST(PlacePlausibility, HaloRingsOutsideTheLayersRangeAreRefused) {
  const ScenarioConfig s = small_test();
  PlaceCore p(s, 0);
  const MapGeometry geo = s.geometry();
  const RegionId n = p.neighbours().front();
  const std::size_t ring = ring_size(geo.region_rect(n));
  HaloMsg good{n, 0, std::vector<float>(ring, 0.5F), std::vector<float>(ring, 0.5F)};
  EXPECT_TRUE(p.accept_halo(good));
  HaloMsg forged = good;
  forged.target[3] = 1e30F;
  EXPECT_FALSE(p.accept_halo(forged));
  EXPECT_EQ(p.ledger().refused[Refusal::ValueOutOfRange], 1U);
  EXPECT_EQ(p.ledger().rejected(), 0U);  // not a deposit: the deposit accounting is untouched
}

// ------------------------------------------------------------- the recorder

struct PlausibilityRig {
  ScenarioConfig scenario = small_test();
  MapGeometry geo = scenario.geometry();  // the world keeps a pointer to it
  World world{geo, scenario.obstacles, scenario.targets};
  RunRecorder rec{scenario, world};
};

TEST(RecorderPlausibility, ForgedStatesMoveNeitherCoverageNorTheUavs) {
  PlausibilityRig r;
  const Cell start = start_cell(r.scenario, 0);
  ASSERT_TRUE(r.rec.on_uav_state(state_at(0, 0, start.x, start.y)));
  const double before = r.rec.coverage().coverage();
  ASSERT_GT(before, 0.0);
  EXPECT_FALSE(r.rec.on_uav_state(state_at(900000, 1, 20, 20)));  // not a UAV of the swarm
  EXPECT_FALSE(r.rec.on_uav_state(state_at(0, 1, 25, 25)));       // a jump across the map
  r.rec.set_tick_ceiling(50);
  EXPECT_FALSE(r.rec.on_uav_state(state_at(0, 4000000, 25, 25)));  // a tick the run cannot have reached
  EXPECT_EQ(r.rec.coverage().coverage(), before);
  EXPECT_EQ(r.rec.uavs().at(0).last.tick, 0U);
  EXPECT_EQ(r.rec.uavs().count(900000), 0U);
  EXPECT_EQ(r.rec.max_tick(), 0U);
  EXPECT_EQ(r.rec.refused()[Refusal::UnknownUav], 1U);
  EXPECT_EQ(r.rec.refused()[Refusal::ImplausibleState], 1U);
  EXPECT_EQ(r.rec.refused()[Refusal::TickFarAhead], 1U);
  EXPECT_EQ(r.rec.samples_rejected(), 0U);  // well formed: refused, not malformed
  // The real UAV flying on is still followed.
  EXPECT_TRUE(r.rec.on_uav_state(state_at(0, 1, start.x + 1, start.y + 1)));
}

TEST(RecorderPlausibility, GuardAnUncheckedStateWouldMoveCoverage) {
  // The same far cell from a UAV allowed to be there (its first state at a
  // late tick) does raise coverage: the refusal above is what kept it flat.
  PlausibilityRig r;
  const double before = r.rec.coverage().coverage();
  ASSERT_TRUE(r.rec.on_uav_state(state_at(1, 100, 25, 25)));
  EXPECT_GT(r.rec.coverage().coverage(), before);
}

TEST(RecorderPlausibility, ForgedDetectionsDoNotCountAsTargetsFound) {
  PlausibilityRig r;
  const Cell start = start_cell(r.scenario, 2);
  ASSERT_TRUE(r.rec.on_uav_state(state_at(2, 5, start.x, start.y)));
  const Cell far = r.scenario.targets[2];                 // (25, 26): far from the start area
  EXPECT_FALSE(r.rec.on_detection({900000, 5, 2, far}));  // a UAV that does not exist
  EXPECT_TRUE(r.rec.on_detection({2, 5, 2, far}));        // judged now: the state of its tick is here
  r.rec.judge_pending_detections();
  EXPECT_EQ(r.rec.acquisitions().found(), 0U);
  EXPECT_TRUE(r.rec.take_first_acquisitions().empty());
  EXPECT_EQ(r.rec.refused()[Refusal::UnknownUav], 1U);
  EXPECT_EQ(r.rec.refused()[Refusal::ImplausibleDetection], 1U);
}

TEST(RecorderPlausibility, ADetectionWaitsForTheStateOfItsTickAndThenCounts) {
  // Guard and honest case: the UAV flies next to the target; its detection
  // arrives before its state of that tick (two topics) and still counts.
  PlausibilityRig r;
  const Cell t = r.scenario.targets[0];  // (22, 8)
  ASSERT_TRUE(r.rec.on_uav_state(state_at(3, 40, t.x - 1, t.y)));
  ASSERT_TRUE(r.rec.on_detection({3, 41, 0, t}));
  EXPECT_EQ(r.rec.acquisitions().found(), 0U);  // waiting
  ASSERT_TRUE(r.rec.on_uav_state(state_at(3, 41, t.x - 2, t.y)));
  EXPECT_EQ(r.rec.acquisitions().found(), 1U);
  const auto firsts = r.rec.take_first_acquisitions();
  ASSERT_EQ(firsts.size(), 1U);
  EXPECT_EQ(firsts[0].tick, 41U);
  EXPECT_EQ(r.rec.refused().total(), 0U);
}

TEST(RecorderPlausibility, ADetectionOfATickLongPastIsJudgedByTheStateOfThatTickNotTheLatest) {
  // Issue 28: judged against the UAV's latest state, a detection 20 ticks
  // old had the reach of 20 ticks of flight, and a forged one of a target
  // the UAV never came near was accepted.
  PlausibilityRig r;
  const Cell t = r.scenario.targets[0];  // (22, 8)
  // Far from the target at tick 40, then flying towards it.
  for (uint32_t k = 40; k <= 60; ++k) {
    ASSERT_TRUE(r.rec.on_uav_state(state_at(3, k, t.x - 20 + (k - 40), t.y)));
  }
  ASSERT_TRUE(r.rec.on_detection({3, 41, 0, t}));  // 19 cells away at tick 41
  EXPECT_EQ(r.rec.acquisitions().found(), 0U);
  EXPECT_EQ(r.rec.refused()[Refusal::ImplausibleDetection], 1U);
  // At its tick 60 it is next to it: that detection counts.
  ASSERT_TRUE(r.rec.on_detection({3, 60, 0, t}));
  EXPECT_EQ(r.rec.acquisitions().found(), 1U);
  EXPECT_EQ(r.rec.refused()[Refusal::ImplausibleState], 0U) << "the flight itself was plausible";
}

// --------------------------------------------- honest runs refuse nothing

TEST(HonestRuns, SimulatedRunsOfEveryScenarioRefuseNothing) {
  // The checks must never refuse an honest swarm: a refused deposit or state
  // would break lockstep == simulator and the deposit accounting. The
  // simulator runs the same PlaceCore and RunRecorder the processes run.
  for (const auto& entry : std::filesystem::directory_iterator(std::string(PHEROMESH_SOURCE_DIR) + "/scenarios")) {
    auto loaded = load_scenario(entry.path().string());
    ASSERT_TRUE(loaded) << entry.path();
    ScenarioConfig s = loaded.value();
    s.ticks = std::min<uint32_t>(s.ticks, 300);
    Simulator sim(s);
    sim.run();
    const RunRecorder& rec = sim.recorder();
    EXPECT_EQ(rec.refused().total(), 0U) << entry.path();
    for (const auto& [region, h] : rec.health()) {
      for (std::size_t i = 0; i < kRefusalCount; ++i) {
        EXPECT_EQ(h.refused[i], 0U) << entry.path() << " region " << region << " "
                                    << refusal_name(static_cast<Refusal>(i));
      }
      EXPECT_EQ(h.deposits_rejected, 0U) << entry.path() << " region " << region;
    }
    // Every final field value lies in its layer's range.
    const PolicyTraits t = policy_traits(s);
    for (int l = 0; l < sim.layer_count(); ++l) {
      for (int32_t y = 0; y < s.height; ++y) {
        for (int32_t x = 0; x < s.width; ++x) {
          const float v = sim.field_value(l, {x, y});
          ASSERT_TRUE(v >= t.layer_ranges[l].lo && v <= t.layer_ranges[l].hi)
              << entry.path() << " layer " << t.layers[l] << " at (" << x << ", " << y << "): " << v;
        }
      }
    }
  }
}

}  // namespace
}  // namespace pheromesh::core
