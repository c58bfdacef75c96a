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
  // ... and the states each home place agent must hold: uav 0 is homed on
  // region 0, uav 1 on region 1 (uav mod regions).
  ASSERT_EQ(place.states.size(), 2U);
  EXPECT_EQ(place.states[0].region, 0U);
  EXPECT_EQ(place.states[0].count, 1U);
  EXPECT_EQ(place.states[1].region, 1U);
  EXPECT_EQ(place.states[1].count, 1U);
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

TEST(Conductor, EachPhaseIsTimedFromItsClockToTheStatusThatFoundItComplete) {
  C c(two_uavs_two_regions());
  const auto t0 = C::Clock::time_point{} + 100s;
  c.begin_phase(0, ClockPhase::Ready, t0);
  for (uint32_t u : {0U, 1U})
    c.on_phase_done({process_key(kRoleUav, u), 0, static_cast<uint8_t>(ClockPhase::Ready), 0, {}});
  for (RegionId r : {0U, 1U})
    c.on_phase_done({process_key(kRolePlace, r), 0, static_cast<uint8_t>(ClockPhase::Ready), 0, {}});
  ASSERT_TRUE(c.status(t0 + 7s).complete);
  c.begin_phase(0, ClockPhase::Uav, t0 + 10s);
  EXPECT_FALSE(c.status(t0 + 10s + 1ms).complete);
  for (uint32_t u : {0U, 1U}) {
    c.on_phase_done(uav_done(u, 0));
    c.on_uav_state(u, 0, {0, 0});
  }
  ASSERT_TRUE(c.status(t0 + 10s + 3ms).complete);
  EXPECT_TRUE(c.status(t0 + 10s + 9ms).complete) << "asking again records nothing more";
  c.begin_phase(0, ClockPhase::Place, t0 + 11s);
  c.on_phase_done(place_done(0, 0));
  c.on_phase_done(place_done(1, 0));
  ASSERT_TRUE(c.status(t0 + 11s + 500us).complete);
  ASSERT_EQ(c.phase_times().uav_ms.size(), 1U) << "the Ready phase is not a tick's";
  EXPECT_DOUBLE_EQ(c.phase_times().uav_ms[0], 3.0);
  ASSERT_EQ(c.phase_times().place_ms.size(), 1U);
  EXPECT_DOUBLE_EQ(c.phase_times().place_ms[0], 0.5);
}

TEST(Conductor, APlacePhaseThatBeginsTheNextUavPhaseCompletesWithBothAndTimesEachPart) {
  C c(two_uavs_two_regions());
  const auto t0 = C::Clock::time_point{} + 100s;
  c.begin_phase(0, ClockPhase::Uav, t0);
  c.on_phase_done(uav_done(0, 0, 1, {{1, 2}}));
  c.on_phase_done(uav_done(1, 0));
  c.on_uav_state(0, 0, {0, 0});
  c.on_uav_state(1, 0, {1, 0});
  c.on_broadcast(0, 0);
  ASSERT_TRUE(c.status(t0 + 4ms).complete);
  // The place clock of tick 0 begins UAV phase 1: it announces what the UAV
  // clock of tick 1 would (the one broadcast of tick 0, the UAVs over each
  // tile), as well as the place phase's deposits.
  const auto t1 = t0 + 10ms;
  const ClockMsg fused = c.begin_phase(0, ClockPhase::Place, t1, /*next_uav_phase=*/true);
  EXPECT_TRUE(fused.next_uav_phase);
  EXPECT_EQ(fused.phase, static_cast<uint8_t>(ClockPhase::Place));
  EXPECT_EQ(fused.tick, 0U);
  EXPECT_EQ(fused.broadcasts, 1U);
  ASSERT_EQ(fused.occupancy.size(), 2U);
  ASSERT_EQ(fused.deposits.size(), 1U);
  EXPECT_EQ(fused.deposits[0].count, 2U);
  EXPECT_EQ(c.phase(), ClockPhase::Place);
  // UAV 0 got its view early and reports tick 1 while region 1 still works on tick 0.
  c.on_phase_done(uav_done(0, 1));
  c.on_uav_state(0, 1, {0, 0});
  c.on_phase_done(place_done(0, 0));
  auto s = c.status(t1 + 5ms);
  EXPECT_FALSE(s.complete);
  EXPECT_EQ(s.waiting, 1U) << "region 1's place phase";
  EXPECT_EQ(s.regions_not_ready, std::vector<uint32_t>{1}) << "named in a phase that times out";
  EXPECT_EQ(c.phase(), ClockPhase::Place);
  c.on_phase_done(place_done(1, 0));
  s = c.status(t1 + 6ms);
  EXPECT_FALSE(s.complete) << "the UAV phase of tick 1 is not: uav 1 has not reported it";
  EXPECT_EQ(s.waiting, 1U);
  EXPECT_EQ(s.uavs_not_ready, std::vector<uint32_t>{1});
  EXPECT_EQ(c.phase(), ClockPhase::Uav) << "what is under way now is UAV phase 1";
  EXPECT_EQ(c.tick(), 1U);
  c.on_phase_done(uav_done(1, 1, 0, {{0, 3}}));
  s = c.status(t1 + 8ms);
  EXPECT_FALSE(s.complete) << "and its state";
  EXPECT_EQ(s.uavs_not_ready, std::vector<uint32_t>{1}) << "whose state is missing";
  c.on_uav_state(1, 1, {1, 0});
  ASSERT_TRUE(c.status(t1 + 9ms).complete);
  // Each part timed: the place phase from its clock, the UAV phase from the
  // place phase's end, so that they add up to the tick's time.
  ASSERT_EQ(c.phase_times().place_ms.size(), 1U);
  EXPECT_DOUBLE_EQ(c.phase_times().place_ms[0], 6.0);
  ASSERT_EQ(c.phase_times().uav_ms.size(), 2U);
  EXPECT_DOUBLE_EQ(c.phase_times().uav_ms[1], 3.0);
  // The place phase of tick 1 announces what UAV phase 1 reported.
  const ClockMsg place1 = c.begin_phase(1, ClockPhase::Place, t1 + 10ms);
  EXPECT_FALSE(place1.next_uav_phase);
  ASSERT_EQ(place1.deposits.size(), 1U);
  EXPECT_EQ(place1.deposits[0].region, 0U);
  EXPECT_EQ(place1.deposits[0].count, 3U);
  EXPECT_EQ(place1.served.size(), 2U);
}

TEST(LockstepConductorStandby, APlacePhaseWithStandbysDoesNotBeginTheNextUavPhase) {
  C::Options o = two_uavs_two_regions();
  o.standbys = 1;
  C c(o);
  const auto t0 = C::Clock::time_point{} + 100s;
  const ClockMsg m = c.begin_phase(0, ClockPhase::Place, t0, /*next_uav_phase=*/true);
  EXPECT_FALSE(m.next_uav_phase) << "a standby may still take the inputs of its place phase when the UAVs act";
  for (uint16_t rep : {0, 1}) {
    for (RegionId r : {0U, 1U}) {
      c.on_phase_done({process_key(kRolePlace, place_id(r, rep)), 0, static_cast<uint8_t>(ClockPhase::Place), 0, {}});
    }
  }
  EXPECT_TRUE(c.status(t0).complete);
  EXPECT_EQ(c.phase(), ClockPhase::Place);
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
  // A report of an older tick does not replace a newer one (a lagging
  // replica's copy of a gateway's report comes after the other's next one).
  c.on_phase_done(place_done(1, 2));
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

// A replica whose lease lapsed while it kept up (a loaded host did not run it
// for a while) is waited for again when it is heard; one that missed a place
// phase, or that the launcher killed, is not.
TEST(LockstepConductorStandby, AReplicaBackInStepIsWaitedForAgain) {
  using namespace std::chrono_literals;
  LockstepConductor::Options o;
  o.uavs = 0;
  o.regions = 1;
  o.standbys = 1;
  LockstepConductor c(o);
  const auto t0 = LockstepConductor::Clock::time_point{} + 10s;
  const auto done = [&](uint16_t replica, uint32_t tick) {
    PhaseDoneMsg m;
    m.process = process_key(kRolePlace, place_id(0, replica));
    m.tick = tick;
    m.phase = static_cast<uint8_t>(ClockPhase::Place);
    c.on_phase_done(m);
  };
  c.begin_phase(0, ClockPhase::Place, t0);
  done(0, 0);
  done(1, 0);
  c.begin_phase(1, ClockPhase::Place, t0);
  c.on_place_departed(place_id(0, 1));
  done(0, 1);
  EXPECT_TRUE(c.status(t0).complete) << "the lapsed standby is not waited for";
  EXPECT_TRUE(c.on_place_back(place_id(0, 1))) << "it finished tick 0 and is working on tick 1: in step";
  EXPECT_FALSE(c.status(t0).complete) << "so tick 1 waits for it again";
  done(1, 1);
  EXPECT_TRUE(c.status(t0).complete);
  EXPECT_FALSE(c.on_place_back(place_id(0, 1))) << "not gone: nothing to do";

  // Lapsed at tick 2, heard again at tick 4: it missed tick 3's place phase.
  c.begin_phase(2, ClockPhase::Place, t0);
  c.on_place_departed(place_id(0, 1));
  done(0, 2);
  c.begin_phase(3, ClockPhase::Place, t0);
  done(0, 3);
  c.begin_phase(4, ClockPhase::Uav, t0);
  EXPECT_FALSE(c.on_place_back(place_id(0, 1))) << "its last place phase is tick 1";
  c.begin_phase(4, ClockPhase::Place, t0);
  EXPECT_EQ(c.status(t0).waiting, 1U) << "only the primary";

  // Killed by the launcher: a late health sample does not bring it back.
  done(0, 4);
  c.begin_phase(5, ClockPhase::Uav, t0);
  c.on_place_killed(place_id(0, 0));
  EXPECT_FALSE(c.on_place_back(place_id(0, 0))) << "in step by its reports, but dead";
}

using namespace std::chrono_literals;
using C = LockstepConductor;

C::Options four_uavs_two_regions() {
  C::Options o;
  o.uavs = 4;  // homes: uav % 2 -> uavs 0 and 2 on region 0, 1 and 3 on region 1
  o.regions = 2;
  o.phase_timeout = 60s;
  o.departed_grace = 5s;
  return o;
}

PhaseDoneMsg uav_report(uint32_t uav, uint32_t tick, std::vector<RegionCount> deposits = {}) {
  return {process_key(kRoleUav, uav), tick, static_cast<uint8_t>(ClockPhase::Uav), 0, std::move(deposits)};
}
PhaseDoneMsg place_report(RegionId r, uint32_t tick) {
  return {process_key(kRolePlace, r), tick, static_cast<uint8_t>(ClockPhase::Place), 0, {}};
}

TEST(ConductorFaults, TheLaunchersAnswerNamesTheGoneUavsAndPlaceAgents) {
  auto g = parse_gone("gone uav-3,place-1,uav-0", 4, 2);
  ASSERT_TRUE(g) << g.error().message;
  EXPECT_EQ(g->uavs, (std::vector<uint32_t>{3, 0}));
  EXPECT_EQ(g->regions, (std::vector<RegionId>{1}));
  auto none = parse_gone("gone -", 4, 2);
  ASSERT_TRUE(none);
  EXPECT_TRUE(none->uavs.empty());
  EXPECT_TRUE(none->regions.empty());
  // What is not the protocol, or not this swarm, is an error that quotes it.
  for (const char* bad : {"SIGKILL sent to uav-3", "gone ", "gone uav-4", "gone place-2", "gone uav3", "gone uav-", "gone uav-1x",
                          "gone ground", "gone uav-1,,uav-2", "gone uav--1"}) {
    auto r = parse_gone(bad, 4, 2);
    EXPECT_FALSE(r) << bad;
  }
  EXPECT_NE(parse_gone("gone uav-9", 4, 2).error().message.find("uav-9"), std::string::npos);
}

TEST(ConductorFaults, AUavKilledAtATickIsNotWaitedForAtThatTickAndItsOldStateDoesNotBringItBack) {
  C c(four_uavs_two_regions());
  const auto t0 = C::Clock::time_point{} + 100s;
  c.begin_phase(7, ClockPhase::Uav, t0);
  for (uint32_t u : {0U, 1U, 2U, 3U}) {
    c.on_phase_done(uav_report(u, 7));
    c.on_uav_state(u, 7, {0, 0});
  }
  ASSERT_TRUE(c.status(t0).complete);
  c.begin_phase(7, ClockPhase::Place, t0);
  c.on_phase_done(place_report(0, 7));
  c.on_phase_done(place_report(1, 7));
  ASSERT_TRUE(c.status(t0).complete);
  // The launcher killed uav 2 before tick 8.
  EXPECT_TRUE(c.drop_uav(2));
  EXPECT_FALSE(c.drop_uav(2)) << "reported once";
  EXPECT_TRUE(c.dropped(2));
  c.begin_phase(8, ClockPhase::Uav, t0);
  for (uint32_t u : {0U, 1U, 3U}) {
    c.on_phase_done(uav_report(u, 8));
    c.on_uav_state(u, 8, {0, 0});
  }
  EXPECT_TRUE(c.status(t0).complete) << "no wait, no grace: complete at once";
  EXPECT_FALSE(c.on_uav_state(2, 7, {0, 0})) << "a state it wrote before it died";
  EXPECT_FALSE(c.on_uav_departed(2, t0)) << "its liveliness lapsing is no news";
  EXPECT_TRUE(c.status(t0).complete);
  // The guard: without the drop the same tick waits for it (grace, then timeout).
  C g(four_uavs_two_regions());
  g.begin_phase(8, ClockPhase::Uav, t0);
  for (uint32_t u : {0U, 1U, 3U}) {
    g.on_phase_done(uav_report(u, 8));
    g.on_uav_state(u, 8, {0, 0});
  }
  EXPECT_EQ(g.status(t0 + 30s).waiting, 1U);
}

TEST(ConductorFaults, AnAbsentRegionIsListedNotWaitedForAndItsDepositsAreCountedLost) {
  C c(four_uavs_two_regions());
  const auto t0 = C::Clock::time_point{} + 100s;
  EXPECT_TRUE(c.drop_region(1));
  EXPECT_FALSE(c.drop_region(1));
  EXPECT_TRUE(c.absent(1));
  const ClockMsg uav = c.begin_phase(9, ClockPhase::Uav, t0);
  EXPECT_EQ(uav.absent, (std::vector<RegionId>{1})) << "the UAV phase tells the UAVs homed on it";
  // uav 0 (home 0): 2 deposits for region 0, 3 for region 1 (lost: absent owner).
  // uav 1 (home 1, absent; backup 0): 4 for region 0, through its backup.
  // uav 2 (home 0): 1 for region 0. uav 3 (home 1; backup 0): none.
  c.on_phase_done(uav_report(0, 9, {{0, 2}, {1, 3}}));
  c.on_phase_done(uav_report(1, 9, {{0, 4}}));
  c.on_phase_done(uav_report(2, 9, {{0, 1}}));
  c.on_phase_done(uav_report(3, 9));
  for (uint32_t u : {0U, 1U, 2U, 3U}) c.on_uav_state(u, 9, {0, 0});
  ASSERT_TRUE(c.status(t0).complete);
  EXPECT_TRUE(c.status(t0).complete) << "asking twice counts nothing twice";
  const ClockMsg place = c.begin_phase(9, ClockPhase::Place, t0);
  ASSERT_EQ(place.deposits.size(), 1U);
  EXPECT_EQ(place.deposits[0].region, 0U);
  EXPECT_EQ(place.deposits[0].count, 7U);
  EXPECT_EQ(place.absent, (std::vector<RegionId>{1}));
  // States: region 0 is the gateway of all four now (home of 0 and 2, backup
  // of 1 and 3).
  ASSERT_EQ(place.states.size(), 1U);
  EXPECT_EQ(place.states[0].region, 0U);
  EXPECT_EQ(place.states[0].count, 4U);
  EXPECT_EQ(c.deposits_lost(), 3U);
  c.on_phase_done(place_report(0, 9));
  EXPECT_TRUE(c.status(t0).complete) << "region 1 is not waited for";
  // Nothing lost in a tick without deposits for the absent region.
  c.begin_phase(10, ClockPhase::Uav, t0);
  for (uint32_t u : {0U, 1U, 2U, 3U}) {
    c.on_phase_done(uav_report(u, 10, {{0, 1}}));
    c.on_uav_state(u, 10, {0, 0});
  }
  ASSERT_TRUE(c.status(t0).complete);
  c.begin_phase(10, ClockPhase::Place, t0);
  EXPECT_EQ(c.deposits_lost(), 3U) << "uavs 1 and 3 deposit through their backup";
}

TEST(Conductor, APlacePhaseListsEveryUavWhoseStateArrivedWithItsPoseAndItsGateway) {
  // Four UAVs, two regions; region 1's place agent is absent from tick 4:
  // its home UAVs (1 and 3) are served by their backup, region 0. A UAV
  // whose state was refused, or that was dropped, is served by no one.
  C::Options o = two_uavs_two_regions();
  o.uavs = 5;
  C c(o);
  const auto t0 = C::Clock::time_point{} + 100s;
  c.begin_phase(3, ClockPhase::Uav, t0);
  ServedUav pose{99, 7, 2.5, 3.5, 0.5, -1.0, 3, 1, {4, 6}, 12};  // uav and region are the conductor's to fill
  for (uint32_t u : {0U, 1U, 2U, 3U}) {
    c.on_phase_done(uav_done(u, 3));
    pose.x = 2.5 + u;
    c.on_uav_state(u, 3, {0, 0}, pose);
  }
  c.on_phase_done(uav_done(4, 3));
  c.on_uav_refused(4, 3);
  ASSERT_TRUE(c.status(t0).complete);
  const ClockMsg place = c.begin_phase(3, ClockPhase::Place, t0);
  ASSERT_EQ(place.served.size(), 4U) << "uav 4's state was refused";
  for (uint32_t u = 0; u < 4; ++u) {
    EXPECT_EQ(place.served[u].uav, u);
    EXPECT_EQ(place.served[u].region, u % 2) << "its home";
    EXPECT_DOUBLE_EQ(place.served[u].x, 2.5 + u);
    EXPECT_DOUBLE_EQ(place.served[u].y, 3.5);
    EXPECT_DOUBLE_EQ(place.served[u].vx, 0.5);
    EXPECT_DOUBLE_EQ(place.served[u].vy, -1.0);
    EXPECT_EQ(place.served[u].heading, 3U);
    EXPECT_EQ(place.served[u].role, 1U);
    EXPECT_EQ(place.served[u].view, (Cell{4, 6}));
    EXPECT_EQ(place.served[u].deposits_sent, 12U);
  }
  EXPECT_TRUE(c.begin_phase(3, ClockPhase::Uav, t0).served.empty()) << "only a place phase lists them";

  c.drop_region(1);
  EXPECT_TRUE(c.drop_uav(2));
  c.begin_phase(4, ClockPhase::Uav, t0);
  for (uint32_t u : {0U, 1U, 3U}) {
    c.on_phase_done(uav_done(u, 4));
    c.on_uav_state(u, 4, {0, 0}, pose);
  }
  c.on_uav_state(2, 4, {0, 0}, pose);  // written before it was killed
  c.on_phase_done(uav_done(4, 4));
  c.on_uav_refused(4, 4);
  ASSERT_TRUE(c.status(t0).complete);
  const ClockMsg later = c.begin_phase(4, ClockPhase::Place, t0);
  ASSERT_EQ(later.served.size(), 3U) << "uav 2 was dropped, uav 4's state refused";
  for (const auto& s : later.served) EXPECT_EQ(s.region, 0U) << "uav " << s.uav << ": region 1 is absent";
}

TEST(ConductorFaults, AUavWhoseHomeAndBackupAreBothAbsentHasItsDepositsCountedLost) {
  // Two regions: each is the other's backup. Both absent: every deposit is lost.
  C c(four_uavs_two_regions());
  const auto t0 = C::Clock::time_point{} + 100s;
  c.drop_region(0);
  c.drop_region(1);
  c.begin_phase(9, ClockPhase::Uav, t0);
  for (uint32_t u : {0U, 1U, 2U, 3U}) {
    c.on_phase_done(uav_report(u, 9, {{0, 1}}));
    c.on_uav_state(u, 9, {0, 0});
  }
  ASSERT_TRUE(c.status(t0).complete);
  const ClockMsg place = c.begin_phase(9, ClockPhase::Place, t0);
  EXPECT_TRUE(place.deposits.empty());
  EXPECT_TRUE(place.states.empty());
  EXPECT_EQ(c.deposits_lost(), 4U);
}

TEST(ConductorFaults, AUavWhoseLivelinessLapsesButThatStillTalksIsNotDropped) {
  C c(four_uavs_two_regions());
  const auto t0 = C::Clock::time_point{} + 100s;
  c.begin_phase(4, ClockPhase::Uav, t0);
  for (uint32_t u : {0U, 1U, 2U}) {
    c.on_phase_done(uav_report(u, 4));
    c.on_uav_state(u, 4, {0, 0});
  }
  // Under packet loss uav 3's liveliness lapses, but its re-sent PhaseDone of
  // the tick before keeps arriving while it waits for its view.
  c.on_uav_departed(3, t0);
  for (auto t = t0; t < t0 + 20s; t += 1s) c.heard_from(3, t);
  EXPECT_FALSE(c.gone_for_good(3, t0 + 20s));
  EXPECT_EQ(c.status(t0 + 20s).waiting, 1U);
  // Silent for longer than the grace: gone.
  EXPECT_TRUE(c.gone_for_good(3, t0 + 25s));
  EXPECT_TRUE(c.status(t0 + 25s).complete);
}

TEST(ConductorWatch, ASilentConductorIsLostAfterItsLimitAndEveryClockResetsIt) {
  const auto t0 = ConductorWatch::Clock::time_point{} + 100s;
  ConductorWatch w(6s, 300s, t0);
  EXPECT_FALSE(w.lost(t0 + 200s)) << "before the first clock: discovery";
  EXPECT_TRUE(w.lost(t0 + 301s));
  w.on_clock(t0 + 10s);
  EXPECT_TRUE(w.heard());
  EXPECT_FALSE(w.lost(t0 + 16s));
  EXPECT_TRUE(w.lost(t0 + 16s + 1ms));
  w.on_clock(t0 + 16s);  // a re-sent clock
  EXPECT_FALSE(w.lost(t0 + 21s));
  EXPECT_EQ(w.silence(t0 + 21s), 5s);
  const auto f = ConductorWatch::for_lease(1000ms, t0);
  EXPECT_EQ(f.limit(), ConductorWatch::kFirstClock);
  auto g = ConductorWatch::for_lease(1000ms, t0);
  g.on_clock(t0);
  EXPECT_EQ(g.limit(), 1000ms * ConductorWatch::kLeases);
}

}  // namespace
}  // namespace pheromesh::core

namespace pheromesh::core {
namespace {

using namespace std::chrono_literals;

TEST(ConductorStart, TickZeroWaitsForEveryUavAndPlaceAgentToReportReadyThenForNobodyElse) {
  LockstepConductor::Options o;
  o.uavs = 2;
  o.regions = 2;
  o.start_timeout = 120s;
  LockstepConductor c(o);
  const auto t0 = LockstepConductor::Clock::time_point{} + 100s;
  const ClockMsg ready = c.begin_phase(0, ClockPhase::Ready, t0);
  EXPECT_EQ(ready.phase, static_cast<uint8_t>(ClockPhase::Ready));
  EXPECT_EQ(c.status(t0).waiting, 4U);
  const auto report = [](uint32_t role, uint32_t id) {
    return PhaseDoneMsg{process_key(role, id), 0, static_cast<uint8_t>(ClockPhase::Ready), 0, {}};
  };
  c.on_phase_done(report(kRoleUav, 0));
  c.on_phase_done(report(kRolePlace, 1));
  c.on_phase_done(report(kRolePlace, 1));  // re-sent: counts once
  auto s = c.status(t0 + 60s);
  EXPECT_EQ(s.waiting, 2U);
  EXPECT_FALSE(s.timed_out);
  EXPECT_EQ(s.uavs_not_ready, std::vector<uint32_t>{1});
  EXPECT_EQ(s.regions_not_ready, std::vector<uint32_t>{0});
  EXPECT_TRUE(c.status(t0 + 121s).timed_out) << "the ground station then refuses the run, naming uav 1 and place 0";
  c.on_phase_done(report(kRoleUav, 1));
  c.on_phase_done(report(kRolePlace, 0));
  EXPECT_TRUE(c.status(t0 + 60s).complete);
  // A Ready report is no report of the UAV phase of tick 0.
  c.begin_phase(0, ClockPhase::Uav, t0 + 60s);
  EXPECT_EQ(c.status(t0 + 60s).waiting, 2U);
}

}  // namespace
}  // namespace pheromesh::core
