// The lockstep conductor's protocol without DDS (core/conductor.hpp): what each
// clock announces, when a phase is complete, a missing UAV, a late PhaseDone,
// a dead place agent. Time is driven by hand.
#include <gtest/gtest.h>

#include "pheromesh/core/conductor.hpp"

namespace pheromesh::core {
namespace {

using namespace std::chrono_literals;
using C = LockstepConductor;

C::Options two_uavs_two_regions() {
  C::Options o;
  o.uavs = 2;
  o.regions = 2;
  o.phase_timeout = 60s;
  o.departed_grace = 5s;
  return o;
}

PhaseDoneMsg uav_done(uint32_t uav, uint32_t tick, uint32_t broadcasts = 0, std::vector<RegionCount> deposits = {}) {
  return {process_key(kRoleUav, uav), tick, static_cast<uint8_t>(ClockPhase::Uav), broadcasts, std::move(deposits)};
}
PhaseDoneMsg place_done(RegionId r, uint32_t tick) {
  return {process_key(kRolePlace, r), tick, static_cast<uint8_t>(ClockPhase::Place), 0, {}};
}

TEST(Conductor, AUavPhaseCompletesWithEveryReportStateAndBroadcastAndAnnouncesWhatItProduced) {
  C c(two_uavs_two_regions());
  const auto t0 = C::Clock::time_point{} + 100s;
  const ClockMsg first = c.begin_phase(0, ClockPhase::Uav, t0);
  EXPECT_EQ(first.tick, 0U);
  EXPECT_EQ(first.phase, static_cast<uint8_t>(ClockPhase::Uav));
  EXPECT_TRUE(first.occupancy.empty()) << "tick 0 has no tick before it";
  EXPECT_EQ(c.status(t0).waiting, 2U);
  // UAV 0 reports 2 deposits for region 1 and a broadcast; UAV 1 one deposit for region 0.
  c.on_phase_done(uav_done(0, 0, 1, {{1, 2}}));
  c.on_phase_done(uav_done(1, 0, 0, {{0, 1}}));
  auto s = c.status(t0);
  EXPECT_FALSE(s.complete);
  EXPECT_EQ(s.waiting, 3U) << "both states and the reported broadcast are still missing";
  c.on_uav_state(0, 0, {0, 0});
  c.on_uav_state(1, 0, {0, 0});
  EXPECT_EQ(c.status(t0).waiting, 1U) << "the broadcast";
  c.on_broadcast(0, 0);
  EXPECT_TRUE(c.status(t0).complete);
  // The place phase announces the reported deposits per region.
  const ClockMsg place = c.begin_phase(0, ClockPhase::Place, t0);
  ASSERT_EQ(place.deposits.size(), 2U);
  EXPECT_EQ(place.deposits[0].region, 0U);
  EXPECT_EQ(place.deposits[0].count, 1U);
  EXPECT_EQ(place.deposits[1].region, 1U);
  EXPECT_EQ(place.deposits[1].count, 2U);
  c.on_phase_done(place_done(0, 0));
  c.on_phase_done(place_done(1, 0));
  EXPECT_TRUE(c.status(t0).complete);
  // The UAV phase of tick 1 announces tick 0: two UAVs over tile (0,0), one broadcast.
  const ClockMsg next = c.begin_phase(1, ClockPhase::Uav, t0);
  ASSERT_EQ(next.occupancy.size(), 1U);
  EXPECT_EQ(next.occupancy[0].tile.tx, 0);
  EXPECT_EQ(next.occupancy[0].count, 2U);
  EXPECT_EQ(next.broadcasts, 1U);
  EXPECT_FALSE(c.status(t0).complete) << "the reports of tick 0 do not count for tick 1";
}

TEST(Conductor, ALatePhaseDoneIsWaitedForAndAnOldOneDoesNotCount) {
  C c(two_uavs_two_regions());
  const auto t0 = C::Clock::time_point{} + 100s;
  c.begin_phase(3, ClockPhase::Place, t0);
  c.on_phase_done(place_done(0, 3));
  c.on_phase_done(place_done(1, 2));  // region 1's report of the tick before
  auto s = c.status(t0 + 59s);
  EXPECT_FALSE(s.complete);
  EXPECT_FALSE(s.timed_out);
  EXPECT_EQ(s.waiting, 1U);
  c.on_phase_done(place_done(1, 3));  // late, within the timeout
  EXPECT_TRUE(c.status(t0 + 59s).complete);
  // A UAV phase report does not complete a place phase of the same tick.
  c.begin_phase(4, ClockPhase::Place, t0);
  c.on_phase_done(place_done(0, 4));
  c.on_phase_done({process_key(kRolePlace, 1), 4, static_cast<uint8_t>(ClockPhase::Uav), 0, {}});
  EXPECT_EQ(c.status(t0).waiting, 1U);
}

TEST(Conductor, ADepartedUavIsWaitedForDuringTheGraceThenNot) {
  C c(two_uavs_two_regions());
  const auto t0 = C::Clock::time_point{} + 100s;
  c.begin_phase(5, ClockPhase::Uav, t0);
  c.on_phase_done(uav_done(0, 5));
  c.on_uav_state(0, 5, {1, 1});
  EXPECT_TRUE(c.on_uav_departed(1, t0));
  EXPECT_FALSE(c.on_uav_departed(1, t0 + 1s)) << "reported once";
  EXPECT_TRUE(c.departed(1));
  EXPECT_EQ(c.status(t0 + 5s).waiting, 1U) << "within the grace a stalled UAV is still awaited";
  EXPECT_FALSE(c.gone_for_good(1, t0 + 5s));
  EXPECT_TRUE(c.gone_for_good(1, t0 + 5s + 1ms));
  EXPECT_TRUE(c.status(t0 + 6s).complete) << "after it, the phase goes on without it";
  // It comes back: waited for again, and its state says so.
  EXPECT_TRUE(c.on_uav_state(1, 5, {1, 1}));
  EXPECT_FALSE(c.departed(1));
  c.begin_phase(6, ClockPhase::Uav, t0 + 6s);
  c.on_phase_done(uav_done(0, 6));
  c.on_uav_state(0, 6, {1, 1});
  EXPECT_EQ(c.status(t0 + 7s).waiting, 1U);
}

TEST(Conductor, ADeadPlaceAgentRunsThePhaseIntoItsTimeout) {
  C::Options o = two_uavs_two_regions();
  o.phase_timeout = 10s;
  C c(o);
  const auto t0 = C::Clock::time_point{} + 100s;
  c.begin_phase(2, ClockPhase::Place, t0);
  c.on_phase_done(place_done(0, 2));
  auto s = c.status(t0 + 10s);
  EXPECT_FALSE(s.timed_out) << "not before the timeout";
  s = c.status(t0 + 10s + 1ms);
  EXPECT_TRUE(s.timed_out);
  EXPECT_FALSE(s.complete);
  EXPECT_EQ(s.waiting, 1U);
  EXPECT_EQ(C::stop(7).phase, static_cast<uint8_t>(ClockPhase::Stop));
  EXPECT_EQ(C::stop(7).tick, 7U);
}

}  // namespace
}  // namespace pheromesh::core

namespace pheromesh::core {
namespace {

TEST(LockstepConductorStandby, EveryLiveReplicaIsWaitedForAndALostOneIsNot) {
  using namespace std::chrono_literals;
  LockstepConductor::Options o;
  o.uavs = 0;
  o.regions = 2;
  o.standbys = 1;
  LockstepConductor c(o);
  const auto t0 = LockstepConductor::Clock::time_point{} + 10s;
  c.begin_phase(0, ClockPhase::Place, t0);
  const auto done = [&](RegionId r, uint16_t replica) {
    PhaseDoneMsg m;
    m.process = process_key(kRolePlace, place_id(r, replica));
    m.tick = 0;
    m.phase = static_cast<uint8_t>(ClockPhase::Place);
    c.on_phase_done(m);
  };
  EXPECT_EQ(c.status(t0).waiting, 4U) << "two regions, two replicas each";
  done(0, 0);
  done(1, 0);
  done(1, 1);
  EXPECT_EQ(c.status(t0).waiting, 1U) << "the standby of region 0 keeps the swarm waiting: it must not fall behind";
  c.on_place_departed(place_id(0, 1));
  EXPECT_TRUE(c.status(t0).complete) << "a lost standby is not waited for";
  // Tick 1: region 0's primary is lost too; without a live replica the
  // region's primary is waited for (the tick cannot be exact without it).
  c.begin_phase(1, ClockPhase::Place, t0);
  c.on_place_departed(place_id(0, 0));
  EXPECT_EQ(c.status(t0).waiting, 3U);
}

}  // namespace
}  // namespace pheromesh::core
