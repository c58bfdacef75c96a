// The ground station's run bookkeeping (core/run_book.hpp): the realtime
// start gate and discovery time, the fields of the last tick, --until-done,
// the place agents' finish, --attach's full state, the tick ceiling. Time is
// driven by hand; the recorder's scenario is small-test (30x30, 2x2 regions,
// 4 UAVs starting in (1,1)-(4,4), 50 Hz).
#include <gtest/gtest.h>

#include <limits>
#include <memory>
#include <string>

#include "pheromesh/core/run_book.hpp"
#include "pheromesh/core/scenario.hpp"

namespace pheromesh::core {
namespace {

using namespace std::chrono_literals;
using Clock = RunBook::Clock;
using Role = RunBook::Role;
using StartNow = RunBook::StartNow;

const Clock::time_point t0 = Clock::time_point{} + 1000s;

RunBook::Options options(Role role, uint32_t uavs, uint32_t regions) {
  RunBook::Options o;
  o.role = role;
  o.uavs = uavs;
  o.regions = regions;
  o.tick_rate_hz = 50.0;
  o.started = t0;
  return o;
}

LockstepConductor conductor(uint32_t regions) {
  LockstepConductor::Options o;
  o.uavs = 1;
  o.regions = regions;
  return LockstepConductor(o);
}

struct Recorder {
  ScenarioConfig scenario;
  MapGeometry geo{1, 1, 1, 1, 1};  // outlives the world, which keeps a pointer to it
  std::unique_ptr<World> world;
  std::unique_ptr<RunRecorder> rec;
  Recorder() {
    auto s = load_scenario(std::string(PHEROMESH_SOURCE_DIR) + "/scenarios/small-test.textproto");
    EXPECT_TRUE(s.ok());
    scenario = s.value();
    geo = scenario.geometry();
    world = std::make_unique<World>(geo, scenario.obstacles, scenario.targets);
    rec = std::make_unique<RunRecorder>(scenario, *world);
  }
};

UavStateMsg state(uint32_t uav, uint32_t tick, bool finished) {
  UavStateMsg s;
  s.uav = uav;
  s.tick = tick;
  s.x = 2;
  s.y = 2;
  s.finished = finished;
  return s;
}

HealthMsg health(RegionId r, uint16_t replica, bool finished) {
  HealthMsg h;
  h.region = r;
  h.replica = replica;
  h.tick = 10;
  h.finished = finished;
  return h;
}

TEST(RunBook, AStarterSendsTheStartOnceWhenEveryProcessIsHeardAndTimesDiscoveryFromTheLaunch) {
  auto o = options(Role::Starter, 4, 4);
  o.launched = t0 - 2s;  // pheromesh run launched the swarm 2 s before this process started
  RunBook book(o);
  for (RegionId r = 0; r < 4; ++r) book.note_linked(r);
  auto d = book.note_discovery({3, 4}, t0 + 1s);
  EXPECT_EQ(d.start, StartNow::No) << "one UAV not heard, and the bound is far";
  EXPECT_FALSE(d.complete_s);
  d = book.note_discovery({4, 4}, t0 + 3s);
  EXPECT_EQ(d.start, StartNow::EveryoneHeard);
  ASSERT_TRUE(d.complete_s);
  EXPECT_DOUBLE_EQ(*d.complete_s, 5.0) << "3 s after this process started, 5 s after the launch";
  EXPECT_TRUE(book.start_sent());
  d = book.note_discovery({4, 4}, t0 + 4s);
  EXPECT_EQ(d.start, StartNow::No) << "the Start goes out once";
  EXPECT_FALSE(d.complete_s) << "discovery is reported once";
  EXPECT_DOUBLE_EQ(book.discovery_s().value_or(-1), 5.0);
}

TEST(RunBook, AStarterWaitsThirtySecondsAndATenthPerUavThenStartsWithoutThoseNotHeard) {
  RunBook book(options(Role::Starter, 20, 4));
  EXPECT_EQ(book.start_bound(), 32000ms) << "30 s + 20 x 0.1 s";
  auto d = book.note_discovery({18, 3}, t0 + 31999ms);
  EXPECT_EQ(d.start, StartNow::No);
  d = book.note_discovery({18, 3}, t0 + 32s);
  EXPECT_EQ(d.start, StartNow::WithoutSomeAfterBound);
  EXPECT_EQ(d.uavs_missing, 2U);
  EXPECT_EQ(d.regions_missing, 1U);
  EXPECT_EQ(d.regions_unlinked, 3U) << "three place agents heard, none said it matched the others";
  EXPECT_FALSE(d.complete_s);
  for (RegionId r = 0; r < 4; ++r) book.note_linked(r);
  d = book.note_discovery({20, 4}, t0 + 40s);
  EXPECT_EQ(d.start, StartNow::No) << "already started";
  EXPECT_DOUBLE_EQ(d.complete_s.value_or(-1), 40.0) << "no launch known: timed from this process's start";
}

TEST(RunBook, AStarterHoldsTheStartUntilEveryPlaceAgentMatchedEveryOther) {
  // Every process heard, but region 2's place agent has not matched every
  // other region's yet: a deposit a UAV homed on it made elsewhere would be
  // rejected as not forwardable. Under load (mixed vendors, CI) this takes
  // longer than hearing everyone.
  RunBook book(options(Role::Starter, 4, 4));
  book.note_linked(0);
  book.note_linked(1);
  book.note_linked(3);
  book.note_linked(7);  // no such region: ignored
  EXPECT_EQ(book.regions_linked(), 3U);
  auto d = book.note_discovery({4, 4}, t0 + 1s);
  EXPECT_EQ(d.start, StartNow::No);
  EXPECT_FALSE(d.complete_s);
  book.note_linked(2);
  d = book.note_discovery({4, 4}, t0 + 2s);
  EXPECT_EQ(d.start, StartNow::EveryoneHeard);
  EXPECT_DOUBLE_EQ(d.complete_s.value_or(-1), 2.0);
}

TEST(RunBook, AStarterStartsAfterTheBoundWithPlaceAgentsNotLinkedAndSaysHowMany) {
  RunBook book(options(Role::Starter, 2, 4));
  book.note_linked(1);
  const auto d = book.note_discovery({2, 4}, t0 + 31s);
  EXPECT_EQ(d.start, StartNow::WithoutSomeAfterBound);
  EXPECT_EQ(d.uavs_missing, 0U);
  EXPECT_EQ(d.regions_missing, 0U);
  EXPECT_EQ(d.regions_unlinked, 3U);
}

TEST(RunBook, AConductorAndAMonitorTimeDiscoveryButNeverSendTheStart) {
  for (Role role : {Role::Conductor, Role::Monitor}) {
    RunBook book(options(role, 2, 1));
    book.note_linked(0);
    EXPECT_EQ(book.note_discovery({0, 0}, t0 + 1h).start, StartNow::No);
    const auto d = book.note_discovery({2, 1}, t0 + 1h + 500ms);
    EXPECT_EQ(d.start, StartNow::No);
    EXPECT_DOUBLE_EQ(d.complete_s.value_or(-1), 3600.5);
    EXPECT_FALSE(book.start_sent());
  }
}

TEST(RunBook, TheLastFieldIsHeldWhenEveryChunkOfItsTickArrivedFromEveryPresentRegion) {
  RunBook book(options(Role::Conductor, 1, 2));
  auto c = conductor(2);
  book.on_field_chunk(0, 5, 0, 2);
  book.on_field_chunk(0, 5, 1, 2);
  book.on_field_chunk(1, 5, 0, 2);
  EXPECT_FALSE(book.holds_last_fields(5, c)) << "region 1 sent 1 chunk of 2";
  book.on_field_chunk(1, 5, 0, 2);
  EXPECT_FALSE(book.holds_last_fields(5, c)) << "the same chunk twice is one chunk";
  book.on_field_chunk(1, 5, 1, 2);
  EXPECT_TRUE(book.holds_last_fields(5, c));
  EXPECT_FALSE(book.holds_last_fields(4, c)) << "the fields held are of tick 5";
  book.on_field_chunk(1, 4, 0, 2);
  EXPECT_TRUE(book.holds_last_fields(5, c)) << "an older chunk changes nothing";
  book.on_field_chunk(0, 6, 1, 2);
  EXPECT_FALSE(book.holds_last_fields(5, c)) << "region 0 moved on to tick 6";
  EXPECT_FALSE(book.holds_last_fields(6, c)) << "region 0 sent 1 chunk of tick 6, region 1 none";
  ASSERT_TRUE(c.drop_region(1));
  book.on_field_chunk(0, 6, 0, 2);
  EXPECT_TRUE(book.holds_last_fields(6, c)) << "absent region 1 is not waited for";
}

LockstepConductor conductor_with_grace(uint32_t uavs, std::chrono::milliseconds grace) {
  LockstepConductor::Options o;
  o.uavs = uavs;
  o.regions = 4;
  o.departed_grace = grace;
  return LockstepConductor(o);
}

TEST(RunBook, UntilDoneEndsWhenEveryExpectedUavFinishedOrWasLostForGood) {
  Recorder r;
  RunBook book(options(Role::Starter, 4, 4));
  auto c = conductor_with_grace(4, 5s);
  EXPECT_FALSE(book.uavs_done(*r.rec, c, t0)) << "no UAV heard";
  for (uint32_t u = 0; u < 3; ++u) ASSERT_TRUE(r.rec->on_uav_state(state(u, 10, false)));
  ASSERT_TRUE(r.rec->on_uav_state(state(0, 11, true)));
  ASSERT_TRUE(r.rec->on_uav_state(state(1, 11, true)));
  r.rec->on_uav_departed(2);
  c.on_uav_departed(2, t0);
  EXPECT_FALSE(book.uavs_done(*r.rec, c, t0 + 10s)) << "3 of 4 heard, and the swarm was not started without the fourth";
  ASSERT_EQ(book.note_discovery({3, 4}, t0 + 31s).start, StartNow::WithoutSomeAfterBound);
  EXPECT_TRUE(book.uavs_done(*r.rec, c, t0 + 31s)) << "started without uav 3: 0 and 1 finished, 2 lost for good";
  ASSERT_TRUE(r.rec->on_uav_state(state(3, 10, false)));
  EXPECT_FALSE(book.uavs_done(*r.rec, c, t0 + 31s)) << "uav 3 came late and flies";
}

// A SIGSTOPped UAV: its liveliness lapses, but it has not finished. The End
// waits the departed grace; if it resumes within it, it flies on.
TEST(RunBook, UntilDoneWaitsTheDepartedGraceForAUavWhoseLivelinessLapsed) {
  Recorder r;
  RunBook book(options(Role::Starter, 2, 4));
  auto c = conductor_with_grace(2, 5s);
  for (uint32_t u = 0; u < 2; ++u) {
    ASSERT_TRUE(r.rec->on_uav_state(state(u, 10, false)));
    c.heard_from(u, t0);
  }
  ASSERT_TRUE(r.rec->on_uav_state(state(0, 20, true)));
  c.heard_from(1, t0 + 1s);
  r.rec->on_uav_departed(1);  // stopped: its liveliness lapsed at t0 + 3 s
  c.on_uav_departed(1, t0 + 3s);
  EXPECT_FALSE(book.uavs_done(*r.rec, c, t0 + 3s)) << "uav 1 lapsed just now";
  EXPECT_FALSE(book.uavs_done(*r.rec, c, t0 + 8s))
      << "the grace (5 s) runs from the lapse (3 s), not from its last sample";
  // It resumes: its states come back and it finishes later.
  ASSERT_TRUE(r.rec->on_uav_state(state(1, 11, false)));
  c.heard_from(1, t0 + 7s);
  c.on_uav_state(1, 11, {0, 0});
  EXPECT_FALSE(book.uavs_done(*r.rec, c, t0 + 20s)) << "uav 1 is back and flies, however long it takes";
  ASSERT_TRUE(r.rec->on_uav_state(state(1, 20, true)));
  EXPECT_TRUE(book.uavs_done(*r.rec, c, t0 + 20s)) << "both finished";
}

TEST(RunBook, UntilDoneCountsAUavGoneForGoodAfterTheGrace) {
  Recorder r;
  RunBook book(options(Role::Starter, 2, 4));
  auto c = conductor_with_grace(2, 5s);
  ASSERT_TRUE(r.rec->on_uav_state(state(0, 20, true)));
  ASSERT_TRUE(r.rec->on_uav_state(state(1, 10, false)));
  c.heard_from(1, t0);
  r.rec->on_uav_departed(1);
  c.on_uav_departed(1, t0 + 1s);
  EXPECT_FALSE(book.uavs_done(*r.rec, c, t0 + 6s)) << "exactly the grace: not yet past it";
  EXPECT_TRUE(book.uavs_done(*r.rec, c, t0 + 6s + 1ms)) << "silent past the grace: gone for good";
}

TEST(RunBook, UntilDoneCountsAKilledUavAsNotFlyingUntilItIsHeardAgain) {
  Recorder r;
  RunBook book(options(Role::Starter, 2, 4));
  auto c = conductor_with_grace(2, 5s);
  ASSERT_TRUE(r.rec->on_uav_state(state(0, 20, true)));
  ASSERT_TRUE(r.rec->on_uav_state(state(1, 10, false)));
  c.heard_from(1, t0);
  EXPECT_FALSE(book.uavs_done(*r.rec, c, t0 + 1s)) << "uav 1 flies";
  book.note_uav_killed(1, t0 + 1s);
  EXPECT_TRUE(book.uavs_done(*r.rec, c, t0 + 1s)) << "killed: done at once, before its liveliness lapses";
  // Restarted: the new process is heard after the kill.
  r.rec->on_uav_departed(1);
  c.on_uav_departed(1, t0 + 2s);
  ASSERT_TRUE(r.rec->on_uav_state(state(1, 0, false)));
  c.heard_from(1, t0 + 3s);
  EXPECT_FALSE(book.uavs_done(*r.rec, c, t0 + 3s)) << "restarted after the kill: it flies again";
}

TEST(RunBook, UntilDoneCountsAUavTheConductorDroppedAtATickAsDone) {
  Recorder r;
  RunBook book(options(Role::Conductor, 2, 4));
  auto c = conductor_with_grace(2, 5s);
  ASSERT_TRUE(r.rec->on_uav_state(state(0, 20, true)));
  ASSERT_TRUE(r.rec->on_uav_state(state(1, 10, false)));
  EXPECT_FALSE(book.uavs_done(*r.rec, c, t0));
  ASSERT_TRUE(c.drop_uav(1));
  EXPECT_TRUE(book.uavs_done(*r.rec, c, t0)) << "killed by the launcher at a tick";
}

TEST(RunBook, PlacesFinishWhenEveryReplicaHeardFinishedOrLeftAndEveryRegionWasHeardOrLeft) {
  Recorder r;
  RunBook book(options(Role::Monitor, 4, 4));
  for (RegionId g = 0; g < 3; ++g) r.rec->on_health(health(g, 0, true));
  r.rec->on_health(health(0, 1, false));
  EXPECT_FALSE(book.places_finished(*r.rec)) << "region 3 never heard, standby 1 of region 0 still runs";
  r.rec->on_place_departed(place_id(0, 1));
  EXPECT_FALSE(book.places_finished(*r.rec)) << "region 3 never heard";
  r.rec->on_place_departed(place_id(3, 0));
  EXPECT_TRUE(book.places_finished(*r.rec)) << "region 3 left before its first health";
}

TEST(RunBook, AMonitorShowsTheFullStateOnceEveryProcessAndEveryRegionsFieldArrived) {
  auto o = options(Role::Monitor, 4, 2);
  o.launched = t0;
  RunBook book(o);
  book.on_field_chunk(0, 3, 0, 1);
  book.on_field_chunk(7, 3, 0, 1);  // no region of this map
  EXPECT_FALSE(book.note_full_state({4, 2}, t0 + 1s)) << "region 1's field has not arrived";
  book.on_field_chunk(1, 3, 0, 1);
  EXPECT_FALSE(book.note_full_state({3, 2}, t0 + 2s)) << "one UAV not heard";
  EXPECT_DOUBLE_EQ(book.note_full_state({4, 2}, t0 + 2250ms + 999us).value_or(-1), 2.25) << "to the millisecond";
  EXPECT_FALSE(book.note_full_state({4, 2}, t0 + 3s)) << "once";
}

TEST(RunBook, TheTickCeilingIsTheConductorsClockPlusOneOrTheLaunchTimeOrUnlimited) {
  RunBook conducting(options(Role::Conductor, 1, 1));
  EXPECT_EQ(conducting.tick_ceiling(t0), 1U) << "tick 0 announced";
  conducting.note_conducted(7);
  conducting.note_conducted(3);
  EXPECT_EQ(conducting.tick_ceiling(t0), 8U) << "the highest tick announced, 7, plus one";
  auto launched = options(Role::Starter, 1, 1);
  launched.launched = t0 - 10s;
  EXPECT_EQ(RunBook(launched).tick_ceiling(t0), 2050U) << "(10 s + 30 s slack) x 50 Hz + 50 ticks";
  EXPECT_EQ(RunBook(options(Role::Starter, 1, 1)).tick_ceiling(t0), std::numeric_limits<uint32_t>::max())
      << "no launch time known";
  auto monitor = options(Role::Monitor, 1, 1);
  monitor.launched = t0 - 10s;
  EXPECT_EQ(RunBook(monitor).tick_ceiling(t0), std::numeric_limits<uint32_t>::max());
}

}  // namespace
}  // namespace pheromesh::core
