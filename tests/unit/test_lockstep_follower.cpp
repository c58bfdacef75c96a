// A UAV's and a place agent's side of the lockstep protocol without DDS
// (core/lockstep_follower.hpp): the latched conductor, phases once and in
// order, Stop, the watch on the conductor, absent regions. Time by hand.
#include <gtest/gtest.h>

#include "pheromesh/core/lockstep_follower.hpp"

namespace pheromesh::core {
namespace {

using namespace std::chrono_literals;
using F = LockstepFollower;

ClockMsg clock_of(uint32_t tick, ClockPhase phase, uint64_t writer = 7, std::vector<RegionId> absent = {}) {
  ClockMsg c;
  c.tick = tick;
  c.phase = static_cast<uint8_t>(phase);
  c.writer = writer;
  c.absent = std::move(absent);
  return c;
}

F uav_follower(F::Clock::time_point t0) { return F(ClockPhase::Uav, ConductorWatch(6s, 300s, t0)); }

TEST(LockstepFollower, EachPhaseOfItsKindRunsOnceInTickOrderAndReSentClocksAreNotNewPhases) {
  const auto t0 = F::Clock::time_point{} + 100s;
  F f = uav_follower(t0);
  std::vector<ClockMsg> taken{clock_of(0, ClockPhase::Uav), clock_of(0, ClockPhase::Place),
                              clock_of(1, ClockPhase::Uav)};
  EXPECT_TRUE(f.offer(taken, t0).empty());
  EXPECT_TRUE(taken.empty()) << "the samples are moved out";
  auto p = f.next_phase();
  ASSERT_TRUE(p);
  EXPECT_EQ(p->tick, 0U);
  f.done(0);
  // Tick 0's UAV clock again (re-sent while the UAV ran its phase).
  taken = {clock_of(0, ClockPhase::Uav)};
  f.offer(taken, t0 + 1s);
  p = f.next_phase();
  ASSERT_TRUE(p) << "tick 1 was queued before the re-send";
  EXPECT_EQ(p->tick, 1U);
  f.done(1);
  EXPECT_FALSE(f.next_phase()) << "the place phase is not a UAV's and tick 0 is done";
  EXPECT_EQ(f.last_done(), 1U);
  EXPECT_EQ(f.newest_tick(), 1U);
}

TEST(LockstepFollower, TheFirstWriterIsTheConductorAndAnotherWritersClockIsRefusedEvenAStop) {
  const auto t0 = F::Clock::time_point{} + 100s;
  F f = uav_follower(t0);
  std::vector<ClockMsg> taken{clock_of(0, ClockPhase::Uav, 7), clock_of(5, ClockPhase::Stop, 99),
                              clock_of(50, ClockPhase::Uav, 99)};
  const auto refused = f.offer(taken, t0);
  ASSERT_EQ(refused.size(), 2U);
  EXPECT_EQ(refused[0].phase, static_cast<uint8_t>(ClockPhase::Stop));
  EXPECT_EQ(f.newest_tick(), 0U) << "a forged tick does not raise the ceiling";
  ASSERT_TRUE(f.next_phase());
  f.done(0);
  EXPECT_FALSE(f.next_phase());
  EXPECT_FALSE(f.stopped());
  taken = {clock_of(0, ClockPhase::Stop, 7)};
  f.offer(taken, t0);
  EXPECT_FALSE(f.next_phase());
  EXPECT_TRUE(f.stopped()) << "the conductor's own Stop ends the run";
}

TEST(LockstepFollower, AStopHeardBeforeAnyClockLatchesNobodyAndTheConductorHeardNextIsLatched) {
  const auto t0 = F::Clock::time_point{} + 100s;
  F f = uav_follower(t0);
  std::vector<ClockMsg> taken{clock_of(0, ClockPhase::Stop, 99)};
  EXPECT_EQ(f.offer(taken, t0).size(), 1U);
  EXPECT_FALSE(f.next_phase());
  EXPECT_FALSE(f.stopped()) << "a forged Stop before the conductor's first clock ended the run at tick 0";
  taken = {clock_of(0, ClockPhase::Ready, 7), clock_of(0, ClockPhase::Uav, 7), clock_of(3, ClockPhase::Stop, 99)};
  EXPECT_EQ(f.offer(taken, t0).size(), 1U) << "the forger is still nobody";
  ASSERT_TRUE(f.next_phase());
  f.done(0);
  EXPECT_FALSE(f.stopped());
}

TEST(LockstepFollower, AUavAcceptsTheClockOfAsManyRelaysAsMayServeItAndRefusesAWriterHeardAfterThem) {
  // The lockstep tree: home and backup place agents, each with a standby,
  // relay every clock from before tick 0 - four writers, heard first.
  const auto t0 = F::Clock::time_point{} + 100s;
  F f(ClockPhase::Uav, ConductorWatch(6s, 300s, t0), 4);
  std::vector<ClockMsg> taken{clock_of(0, ClockPhase::Ready, 11), clock_of(0, ClockPhase::Ready, 12),
                              clock_of(0, ClockPhase::Ready, 21), clock_of(0, ClockPhase::Ready, 22),
                              clock_of(0, ClockPhase::Uav, 11), clock_of(0, ClockPhase::Uav, 22)};
  std::vector<ClockMsg> accepted;
  EXPECT_TRUE(f.offer(taken, t0, &accepted).empty());
  EXPECT_EQ(accepted.size(), 6U) << "copies of the accepted samples (a place agent relays them)";
  ASSERT_TRUE(f.next_phase());
  f.done(0);
  EXPECT_FALSE(f.next_phase()) << "tick 0's clock from a second relay is the same phase";
  // A fifth writer, after them: refused, even a Stop.
  taken = {clock_of(0, ClockPhase::Stop, 99)};
  accepted.clear();
  EXPECT_EQ(f.offer(taken, t0, &accepted).size(), 1U);
  EXPECT_TRUE(accepted.empty());
  EXPECT_FALSE(f.next_phase());
  EXPECT_FALSE(f.stopped());
  // The backup's standby alone still keeps the watch and ends the run
  // (its home and the other relays are dead).
  taken = {clock_of(1, ClockPhase::Uav, 22)};
  f.offer(taken, t0 + 5s);
  EXPECT_FALSE(f.conductor_lost(t0 + 10s));
  taken = {clock_of(1, ClockPhase::Stop, 22)};
  f.offer(taken, t0 + 10s);
  ASSERT_TRUE(f.next_phase());
  f.done(1);
  EXPECT_FALSE(f.next_phase());
  EXPECT_TRUE(f.stopped());
}

TEST(LockstepFollower, ASilentConductorIsLostAfterTheWatchsLimitAndAForgedClockDoesNotKeepItAlive) {
  const auto t0 = F::Clock::time_point{} + 100s;
  F f = uav_follower(t0);
  EXPECT_FALSE(f.conductor_lost(t0 + 299s)) << "before the first clock the bound is the discovery one";
  EXPECT_TRUE(f.conductor_lost(t0 + 301s));
  std::vector<ClockMsg> taken{clock_of(3, ClockPhase::Uav, 7)};
  f.offer(taken, t0 + 301s);
  EXPECT_FALSE(f.conductor_lost(t0 + 306s));
  taken = {clock_of(4, ClockPhase::Uav, 8)};
  EXPECT_EQ(f.offer(taken, t0 + 306s).size(), 1U);
  EXPECT_TRUE(f.conductor_lost(t0 + 308s)) << "6 s after the conductor's last clock";
}

TEST(LockstepFollower, AnAbsentRegionIsRememberedFromTheFirstTickThatListedIt) {
  const auto t0 = F::Clock::time_point{} + 100s;
  F f(ClockPhase::Place, ConductorWatch(6s, 300s, t0));
  std::vector<ClockMsg> taken{clock_of(8, ClockPhase::Place), clock_of(9, ClockPhase::Uav, 7, {2}),
                              clock_of(9, ClockPhase::Place, 7, {2}), clock_of(10, ClockPhase::Uav, 7, {1, 2})};
  f.offer(taken, t0);
  EXPECT_FALSE(f.absent_since(0));
  EXPECT_EQ(f.absent_since(2), 9U);
  EXPECT_EQ(f.absent_since(1), 10U);
  auto p = f.next_phase();
  ASSERT_TRUE(p);
  EXPECT_EQ(p->tick, 8U);
  f.done(8);
  p = f.next_phase();
  ASSERT_TRUE(p);
  EXPECT_EQ(p->tick, 9U) << "a place agent runs place phases only";
  EXPECT_FALSE(f.skips(9));
  EXPECT_TRUE(f.skips(11)) << "a clock of tick 11 after tick 8 skipped ticks";
}

// "home": to the UAVs homed on the place agent; "backups": to those it backs up.
std::string to(UavClockRelay::To t) { return std::string(t.home ? "home" : "-") + "/" + (t.backups ? "backups" : "-"); }

TEST(UavClockRelay, EachUavHearsOneClockATickFromItsHomeAndItsBackupOnlyWhatItNeedsWhileItsHomeLives) {
  UavClockRelay relay;
  EXPECT_EQ(to(relay.relays(clock_of(0, ClockPhase::Ready))), "home/backups") << "every UAV latches its relays";
  EXPECT_EQ(to(relay.relays(clock_of(0, ClockPhase::Ready))), "home/backups");
  EXPECT_EQ(to(relay.relays(clock_of(1, ClockPhase::Uav))), "home/-");
  EXPECT_EQ(to(relay.relays(clock_of(1, ClockPhase::Place))), "-/-") << "a UAV runs no place phase";
  EXPECT_EQ(to(relay.relays(clock_of(1, ClockPhase::Place))), "home/backups")
      << "re-sent: the conductor waits, every UAV hears it lives (a backed-up UAV's home may be dead, not yet absent)";
  EXPECT_EQ(to(relay.relays(clock_of(2, ClockPhase::Uav))), "home/-");
  EXPECT_EQ(to(relay.relays(clock_of(2, ClockPhase::Uav))), "home/backups") << "re-sent";
  EXPECT_EQ(to(relay.relays(clock_of(2, ClockPhase::Place))), "-/-");
  // Region 3 listed absent first in a place phase: every UAV hears that
  // tick, and the UAVs it backs up every UAV clock from then on.
  EXPECT_EQ(to(relay.relays(clock_of(3, ClockPhase::Place, 7, {3}))), "home/backups");
  EXPECT_EQ(to(relay.relays(clock_of(4, ClockPhase::Uav, 7, {3}))), "home/backups");
  EXPECT_EQ(to(relay.relays(clock_of(4, ClockPhase::Place, 7, {3}))), "-/-") << "region 3 was relayed absent already";
  EXPECT_EQ(to(relay.relays(clock_of(5, ClockPhase::Uav, 7, {3}))), "home/backups");
  EXPECT_EQ(to(relay.relays(clock_of(5, ClockPhase::Place, 7, {3, 1}))), "home/backups") << "region 1 is newly absent";
  EXPECT_EQ(to(relay.relays(clock_of(5, ClockPhase::Stop))), "home/backups");
}

TEST(UavClockRelay, APlaceClockThatBeginsTheNextUavPhaseGivesTheUavsThatClockFromTheSameWriter) {
  ClockMsg place = clock_of(4, ClockPhase::Place, 9, {2});
  EXPECT_FALSE(uav_clock_begun_by(place)) << "a place clock on its own begins nothing";
  place.next_uav_phase = true;
  place.broadcasts = 3;
  place.occupancy = {{{1, 2}, 5}};
  place.deposits = {{0, 8}};
  place.served = {ServedUav{}};
  const auto uav = uav_clock_begun_by(place);
  ASSERT_TRUE(uav);
  EXPECT_EQ(uav->tick, 5U);
  EXPECT_EQ(uav->phase, static_cast<uint8_t>(ClockPhase::Uav));
  EXPECT_EQ(uav->broadcasts, 3U);
  ASSERT_EQ(uav->occupancy.size(), 1U);
  EXPECT_EQ(uav->occupancy[0].count, 5U);
  EXPECT_EQ(uav->absent, (std::vector<RegionId>{2}));
  EXPECT_EQ(uav->writer, 9U) << "the conductor latched by the follower";
  EXPECT_TRUE(uav->deposits.empty() && uav->served.empty()) << "the place phase's, not a UAV's";
  EXPECT_FALSE(uav->next_uav_phase);
  // A UAV follower runs it as UAV phase 5, and the place clock not at all.
  auto f = uav_follower(F::Clock::time_point{} + 1s);
  std::vector<ClockMsg> taken{clock_of(0, ClockPhase::Ready, 9), place, *uav};
  EXPECT_TRUE(f.offer(taken, F::Clock::time_point{} + 2s).empty());
  f.done(0);
  const auto next = f.next_phase();
  ASSERT_TRUE(next);
  EXPECT_EQ(next->tick, 5U);
  EXPECT_EQ(next->phase, static_cast<uint8_t>(ClockPhase::Uav));
  EXPECT_FALSE(f.next_phase());
  // A UAV clock that carries the flag (no conductor writes one) begins nothing.
  ClockMsg odd = clock_of(4, ClockPhase::Uav);
  odd.next_uav_phase = true;
  EXPECT_FALSE(uav_clock_begun_by(odd));
}

}  // namespace
}  // namespace pheromesh::core
