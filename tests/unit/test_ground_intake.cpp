// The ground station's intake of received samples (console/ground_intake.hpp):
// each kind checked, refused or dropped with a count, and handed to the
// recorder, the conductor, the run book and the frame builder; the notes the
// ground station logs. No DDS: samples are built by hand, time is driven by
// hand. The scenario is small-test (30x30 cells, tiles of 6, 2x2 regions,
// 4 UAVs starting in (1,1)-(4,4), 3 targets, the first at (22,8)).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "pheromesh/console/ground_intake.hpp"
#include "pheromesh/core/scenario.hpp"

namespace pheromesh::console {
namespace {

using namespace std::chrono_literals;
using Clock = GroundIntake::Clock;
using Kind = IntakeNote::Kind;
using Notes = GroundIntake::Notes;

const Clock::time_point t0 = Clock::time_point{} + 1000s;
constexpr uint32_t kUnlimited = std::numeric_limits<uint32_t>::max();

struct Rig {
  core::ScenarioConfig scenario;
  core::MapGeometry geo{1, 1, 1, 1, 1};
  std::unique_ptr<core::World> world;
  std::unique_ptr<core::RunRecorder> rec;
  std::unique_ptr<core::LockstepConductor> conductor;
  std::unique_ptr<core::RunBook> book;
  std::unique_ptr<FrameBuilder> frames;
  std::unique_ptr<GroundIntake> intake;

  explicit Rig(GroundIntake::Standby standby = GroundIntake::Standby::None,
               GroundIntake::Pace pace = GroundIntake::Pace::Realtime) {
    auto s = core::load_scenario(std::string(PHEROMESH_SOURCE_DIR) + "/scenarios/small-test.textproto");
    EXPECT_TRUE(s.ok());
    scenario = s.value();
    geo = scenario.geometry();
    world = std::make_unique<core::World>(geo, scenario.obstacles, scenario.targets);
    rec = std::make_unique<core::RunRecorder>(scenario, *world);
    core::LockstepConductor::Options c;
    c.uavs = scenario.uavs;
    c.regions = geo.region_count();
    c.departed_grace = 5s;
    c.standbys = standby == GroundIntake::Standby::Hot ? 1 : 0;
    conductor = std::make_unique<core::LockstepConductor>(c);
    core::RunBook::Options b;
    b.role = core::RunBook::Role::Conductor;
    b.uavs = scenario.uavs;
    b.regions = geo.region_count();
    book = std::make_unique<core::RunBook>(b);
    frames = std::make_unique<FrameBuilder>(geo);
    intake = std::make_unique<GroundIntake>(scenario, GroundIntake::Parts{*rec, *conductor, *book, *frames, *world},
                                            standby, 1000ms, pace);
  }
  Notes take(GroundSamples s, uint32_t ceiling = kUnlimited, Clock::time_point now = t0) {
    return intake->take(s, ceiling, now);
  }
};

GroundSamples states(std::vector<core::UavStateMsg> v) {
  GroundSamples s;
  s.states = std::move(v);
  return s;
}

core::UavStateMsg state(uint32_t uav, uint32_t tick, double x = 2, double y = 2) {
  core::UavStateMsg s;
  s.uav = uav;
  s.tick = tick;
  s.x = x;
  s.y = y;
  return s;
}

core::UavStateMsg finished(uint32_t uav, uint32_t tick) {
  auto s = state(uav, tick);
  s.finished = true;
  return s;
}

// A tile of layer 0 with every value `v`.
core::TileMsg tile(int32_t tx, int32_t ty, uint32_t tick, float v) {
  core::TileMsg t;
  t.tile = {tx, ty};
  t.tick = tick;
  t.width = 6;
  t.height = 6;
  t.values.assign(36, v);
  return t;
}

core::FieldMsg chunk(core::RegionId r, uint32_t tick, uint16_t chunk, uint16_t chunks) {
  core::FieldMsg f;
  f.region = r;
  f.tick = tick;
  f.chunk = chunk;
  f.chunks = chunks;
  return f;
}

core::HealthMsg health(core::RegionId r, uint16_t replica, uint32_t tick = 10) {
  core::HealthMsg h;
  h.region = r;
  h.replica = replica;
  h.tick = tick;
  return h;
}

std::vector<std::string> texts(const Notes& notes, Kind kind) {
  std::vector<std::string> out;
  for (const auto& n : notes) {
    if (n.kind == kind) out.push_back(n.text);
  }
  return out;
}

using Texts = std::vector<std::string>;

TEST(GroundIntake, AStateOfAUavOutsideTheSwarmIsRefusedAsUnknownAndNobodyHearsOfIt) {
  Rig rig;
  const Notes notes = rig.take(states({state(4, 1, 2.5, 2)}));
  EXPECT_EQ(rig.rec->refused()[core::Refusal::UnknownUav], 1U);
  EXPECT_EQ(texts(notes, Kind::StateRefused), Texts{"refused state of uav 4 at tick 1 (2.5, 2): implausible"});
  EXPECT_EQ(rig.frames->uavs_heard(), 0U);
  EXPECT_TRUE(rig.rec->uavs().empty());
}

TEST(GroundIntake, MalformedStatesAreReportedAsDroppedThreeTimesAndNeverAsImplausible) {
  Rig rig;
  std::vector<core::UavStateMsg> outside;
  for (uint32_t u = 0; u < 4; ++u) outside.push_back(state(u, 1, -5, 2));  // west of the map
  outside.push_back(state(0, 1, 2, 31));                                   // south of it
  const Notes notes = rig.take(states(outside));
  EXPECT_EQ(rig.rec->samples_rejected(), 5U);
  EXPECT_EQ(rig.rec->refused().total(), 0U);
  EXPECT_EQ(texts(notes, Kind::StateDropped),
            (Texts{"dropped state of uav 0", "dropped state of uav 1", "dropped state of uav 2"}));
  EXPECT_TRUE(texts(notes, Kind::StateRefused).empty()) << "a malformed state is not an implausible one";
}

TEST(GroundIntake, ATileTwoTicksAheadOfTheLockstepClockIsRefusedAsTickFarAhead) {
  Rig rig;
  GroundSamples s;
  s.tiles = {tile(0, 0, 6, 1.0F), tile(1, 0, 5, 2.0F)};
  const Notes notes = rig.take(std::move(s), core::lockstep_tick_ceiling(4));
  EXPECT_EQ(rig.rec->refused()[core::Refusal::TickFarAhead], 1U);
  ASSERT_EQ(texts(notes, Kind::SampleRefused).size(), 1U);
  EXPECT_NE(texts(notes, Kind::SampleRefused)[0].find("(tick_far_ahead)"), std::string::npos) << notes[0].text;
  EXPECT_EQ(rig.intake->tiles().size(), 1U) << "tick 5, one ahead of clock 4, is reachable";
  EXPECT_TRUE(std::isnan(rig.intake->field_value(0, {0, 0})));
  EXPECT_EQ(rig.intake->field_value(0, {6, 0}), 2.0F);
}

TEST(GroundIntake, ANewerTileReplacesTheFieldValueAndAnOlderOneDoesNot) {
  Rig rig;
  GroundSamples s;
  auto newer = tile(1, 0, 3, 1.0F);
  newer.values[13] = 4.5F;  // cell (7,2): row 2, column 1 of the tile at (6,0)
  s.tiles = {newer, tile(1, 0, 2, 7.0F)};
  rig.take(std::move(s));
  EXPECT_EQ(rig.intake->field_value(0, {7, 2}), 4.5F);
  EXPECT_EQ(rig.intake->field_value(0, {6, 0}), 1.0F);
  EXPECT_TRUE(std::isnan(rig.intake->field_value(1, {7, 2}))) << "no tile of layer 1 arrived";
}

TEST(GroundIntake, ATileOutOfItsLayersRangeIsRefusedAndAMalformedOneDropped) {
  Rig rig;
  GroundSamples s;
  auto narrow = tile(0, 0, 1, 0.0F);
  narrow.width = 5;
  s.tiles = {tile(0, 1, 1, -1.0F), narrow};
  const Notes notes = rig.take(std::move(s));
  EXPECT_EQ(rig.rec->refused()[core::Refusal::ValueOutOfRange], 1U);
  EXPECT_EQ(rig.rec->samples_rejected(), 1U);
  EXPECT_EQ(texts(notes, Kind::TileDropped), Texts{"dropped tile (0,0): tile size 5x6 does not match 6x6"});
  EXPECT_TRUE(rig.intake->tiles().empty());
}

TEST(GroundIntake, AFieldChunkCountsTowardsTheLastFieldOnlyWhenEveryChunkOfItsTickArrivedAndIsPlausible) {
  Rig rig;
  GroundSamples first;
  for (core::RegionId r = 0; r < 4; ++r) first.fields.push_back(chunk(r, 3, 0, 2));
  first.fields[0].tiles = {tile(0, 0, 3, 1.5F)};
  rig.take(std::move(first), core::lockstep_tick_ceiling(3));
  EXPECT_FALSE(rig.book->holds_last_fields(3, *rig.conductor)) << "chunk 1 of 2 missing everywhere";
  EXPECT_EQ(rig.intake->field_value(0, {0, 0}), 1.5F) << "a field's tiles reach the final field";

  GroundSamples forged;
  for (core::RegionId r = 0; r < 4; ++r) forged.fields.push_back(chunk(r, 3, 1, 2));
  forged.fields[0].tick = 9;                        // far ahead of clock 3
  forged.fields[1].tiles = {tile(4, 0, 3, -2.0F)};  // out of range
  rig.take(std::move(forged), core::lockstep_tick_ceiling(3));
  EXPECT_EQ(rig.rec->refused()[core::Refusal::TickFarAhead], 1U);
  EXPECT_EQ(rig.rec->refused()[core::Refusal::ValueOutOfRange], 1U);
  EXPECT_FALSE(rig.book->holds_last_fields(3, *rig.conductor)) << "regions 0 and 1 sent refused chunks only";

  GroundSamples rest;
  rest.fields = {chunk(0, 3, 1, 2), chunk(1, 3, 1, 2)};
  rig.take(std::move(rest), core::lockstep_tick_ceiling(3));
  EXPECT_TRUE(rig.book->holds_last_fields(3, *rig.conductor));
}

TEST(GroundIntake, AFinishedUavsLastStateDoesNotCountAsBackButAFlyingOnesDoes) {
  Rig rig;
  rig.take(states({state(0, 10), state(1, 10)}));
  GroundSamples gone;
  gone.departed_uavs = {0, 1, 9};  // 9: a forger's writer, no UAV
  EXPECT_TRUE(texts(rig.take(std::move(gone), kUnlimited, t0 + 2s), Kind::UavLost).empty())
      << "judged half a lease after the departure";
  const Notes lost = rig.take({}, kUnlimited, t0 + 2600ms);
  EXPECT_EQ(texts(lost, Kind::UavLost),
            (Texts{"uav 0 lost (liveliness) at tick 10", "uav 1 lost (liveliness) at tick 10"}));
  const Notes back = rig.take(states({finished(0, 11), state(1, 11)}), kUnlimited, t0 + 3s);
  EXPECT_EQ(texts(back, Kind::UavBack), Texts{"uav 1 is back at tick 11"});
  EXPECT_FALSE(rig.conductor->departed(0)) << "the conductor takes the finished UAV's state as its end, not a loss";
  GroundSamples again;
  again.departed_uavs = {0};
  rig.take(std::move(again), kUnlimited, t0 + 5s);
  EXPECT_TRUE(texts(rig.take({}, kUnlimited, t0 + 6s), Kind::UavLost).empty())
      << "a finished UAV that leaves is not lost";
}

TEST(GroundIntake, ADepartedPlaceReplicaIsReportedWithTheReplicaThatServesItsRegionNow) {
  Rig rig(GroundIntake::Standby::Hot);  // standbys: only such a run has replica 1
  GroundSamples heard;
  heard.healths = {health(0, 0), health(0, 1), health(1, 0), health(1, 1), health(2, 0), health(3, 0)};
  heard.healths.back().finished = true;
  rig.take(std::move(heard));
  EXPECT_EQ(rig.frames->regions_heard(), 4U);
  GroundSamples gone;
  gone.departed_places = {core::place_id(0, 1), core::place_id(1, 0), core::place_id(2, 0), core::place_id(3, 0)};
  rig.take(std::move(gone), kUnlimited, t0 + 2s);
  const Notes notes = rig.take({}, kUnlimited, t0 + 3s);
  EXPECT_EQ(texts(notes, Kind::PlaceLost),
            (Texts{"standby 1 of region 0 lost (liveliness); region 0 is served by its primary",
                   "place agent 1 lost (liveliness); region 1 is served by standby 1",
                   "place agent 2 lost (liveliness); region 2 has no live place agent: deposits into it are lost"}))
      << "region 3's place agent finished before it left";
  EXPECT_TRUE(rig.rec->place_departed(core::place_id(3, 0)));
}

TEST(GroundIntake, WithHotStandbysALostReplicaIsNoLongerWaitedForInAPlacePhase) {
  Rig rig(GroundIntake::Standby::Hot);
  rig.conductor->begin_phase(0, core::ClockPhase::Place, t0);
  EXPECT_EQ(rig.conductor->status(t0).waiting, 8U) << "4 regions, a primary and a standby each";
  GroundSamples gone;
  gone.departed_places = {core::place_id(2, 1)};
  rig.take(std::move(gone));
  EXPECT_EQ(rig.conductor->status(t0).waiting, 7U);
  // Heard again in the place phase of tick 0 (in step): waited for again.
  GroundSamples heard;
  heard.healths = {health(2, 1, 0)};
  // Heard at once, its lapse is not reported as a loss, so there is no
  // "is back" either (the loss is only reported half a lease later).
  const Notes back = rig.take(std::move(heard));
  EXPECT_TRUE(texts(back, Kind::PlaceBack).empty());
  EXPECT_EQ(rig.conductor->status(t0).waiting, 8U);
}

TEST(GroundIntake, APlaceReplicaHeardAgainIsBackAndTheLowerReplicaOwnsItsRegionAgain) {
  Rig rig(GroundIntake::Standby::Hot);  // standbys: only such a run has replica 1
  GroundSamples heard;
  heard.healths = {health(0, 0), health(0, 1)};
  rig.take(std::move(heard));
  GroundSamples gone;
  gone.departed_places = {core::place_id(0, 0)};
  rig.take(std::move(gone), kUnlimited, t0 + 2s);
  EXPECT_EQ(rig.rec->region_owner(0), std::optional<uint16_t>(1));
  EXPECT_EQ(texts(rig.take({}, kUnlimited, t0 + 3s), Kind::PlaceLost),
            Texts{"place agent 0 lost (liveliness); region 0 is served by standby 1"});
  GroundSamples primary;
  primary.healths = {health(0, 0, 12)};
  const Notes notes = rig.take(std::move(primary), kUnlimited, t0 + 4s);
  EXPECT_EQ(texts(notes, Kind::PlaceBack), Texts{"place agent 0 is back at tick 12 (in step: waited for again)"});
  EXPECT_EQ(texts(notes, Kind::OwnerRegained), Texts{"region 0: replica 0 owns it again"});
  GroundSamples standby_gone;
  standby_gone.departed_places = {core::place_id(0, 1)};
  rig.take(std::move(standby_gone), kUnlimited, t0 + 6s);
  rig.take({}, kUnlimited, t0 + 7s);
  GroundSamples standby;
  standby.healths = {health(0, 1, 13)};
  const Notes again = rig.take(std::move(standby), kUnlimited, t0 + 8s);
  EXPECT_EQ(texts(again, Kind::PlaceBack),
            Texts{"place agent 0 (standby 1) is back at tick 13 (in step: waited for again)"});
  EXPECT_TRUE(texts(again, Kind::OwnerRegained).empty()) << "the primary owned region 0 throughout";
}

TEST(GroundIntake, ABroadcastOfAUavOutsideTheSwarmIsRefusedAndOneOfAnUnknownKindRejected) {
  Rig rig;
  GroundSamples s;
  s.broadcasts = {{7, 1, 0, {}}, {0, 1, 99, {}}, {1, 1, 0, {1.0, 2.0}}};
  const Notes notes = rig.take(std::move(s));
  EXPECT_EQ(texts(notes, Kind::SampleRefused), Texts{"refused a broadcast of uav 7 (unknown_uav)"});
  EXPECT_EQ(rig.rec->refused()[core::Refusal::UnknownUav], 1U);
  EXPECT_EQ(rig.rec->samples_rejected(), 1U);
}

TEST(GroundIntake, OnlyTheFirstFiveRefusalsAreNotedAndEveryOneIsCounted) {
  Rig rig;
  GroundSamples s;
  for (uint32_t k = 0; k < 7; ++k) s.broadcasts.push_back({10 + k, 1, 0, {}});
  const Notes notes = rig.take(std::move(s));
  EXPECT_EQ(texts(notes, Kind::SampleRefused).size(), 5U);
  EXPECT_EQ(rig.rec->refused()[core::Refusal::UnknownUav], 7U);
}

// Under packet loss a live process's liveliness lapses while its samples
// still arrive (docs/dds.md, "Lockstep under packet loss"): such a lapse is
// noted once per process and counted, and never reported as a loss.
TEST(GroundIntake, ALapseOfAProcessHeardAroundItIsNotedOnceAndNeverReportedLost) {
  Rig rig;
  GroundSamples heard;
  heard.healths = {health(2, 0)};
  rig.take(std::move(heard), kUnlimited, t0);
  rig.take(states({state(1, 10)}), kUnlimited, t0 + 200ms);
  GroundSamples gone;
  gone.departed_places = {core::place_id(2, 0)};
  gone.departed_uavs = {1};
  EXPECT_TRUE(texts(rig.take(std::move(gone), kUnlimited, t0 + 300ms), Kind::LivenessLapsed).empty())
      << "judged by what comes after the departure, not before";
  // Heard 0.3 s after their departures (half a lease: 0.5 s).
  GroundSamples after;
  after.healths = {health(2, 0, 10)};
  after.states = {state(1, 11)};
  const Notes lapsed = rig.take(std::move(after), kUnlimited, t0 + 600ms);
  EXPECT_EQ(
      texts(lapsed, Kind::LivenessLapsed),
      (Texts{"uav 1: liveliness lapsed (packet loss?), still heard; not taken for lost (further lapses are counted "
             "at the end of the run)",
             "place agent 2: liveliness lapsed (packet loss?), still heard; not taken for lost (further lapses "
             "are counted at the end of the run)"}));
  EXPECT_FALSE(rig.conductor->departed(1)) << "its state after the departure brought it back in the conductor";
  EXPECT_TRUE(texts(rig.take({}, kUnlimited, t0 + 3s), Kind::PlaceLost).empty());
  // Back: no note, as nobody was told it was lost.
  GroundSamples again;
  again.healths = {health(2, 0, 11)};
  again.states = {state(1, 12)};
  const Notes back = rig.take(std::move(again), kUnlimited, t0 + 3100ms);
  EXPECT_TRUE(texts(back, Kind::PlaceBack).empty());
  EXPECT_TRUE(texts(back, Kind::UavBack).empty());
  // Silent for 2 s, then departed, then a PhaseDone 0.4 s later: a lapse
  // again, counted but not noted a second time.
  GroundSamples gone2;
  gone2.departed_places = {core::place_id(2, 0)};
  rig.take(std::move(gone2), kUnlimited, t0 + 5100ms);
  GroundSamples done;
  done.phase_dones = {
      {core::process_key(core::kRolePlace, 2), 11, static_cast<uint8_t>(core::ClockPhase::Place), 0, {}}};
  const Notes late = rig.take(std::move(done), kUnlimited, t0 + 5500ms);
  EXPECT_TRUE(texts(late, Kind::LivenessLapsed).empty());
  EXPECT_TRUE(texts(late, Kind::PlaceLost).empty());
  EXPECT_TRUE(texts(rig.take({}, kUnlimited, t0 + 9s), Kind::PlaceLost).empty());
  EXPECT_EQ(rig.intake->liveliness_lapses(), 3U);
  EXPECT_EQ(texts(rig.intake->judge_pending(), Kind::LivenessLapsed),
            Texts{"liveliness lapsed 3 times while the process was still heard (packet loss?; UAVs 1, place agents 1); "
                  "none was taken for lost"});
}

// A process killed and started again (pheromesh run --faults "restart ...")
// is heard from its next life soon after its departure: that departure was a
// death, reported as lost, and the new life is back - not a lapse.
TEST(GroundIntake, AProcessHeardFromItsNextLifeAfterItsDepartureWasLostAndIsBack) {
  Rig rig;
  GroundSamples heard;
  heard.healths = {health(2, 0)};
  auto first = state(1, 10);
  first.deposits_sent = 40;
  heard.states = {first};
  rig.take(std::move(heard), kUnlimited, t0);
  GroundSamples gone;
  gone.departed_places = {core::place_id(2, 0)};
  gone.departed_uavs = {1};
  rig.take(std::move(gone), kUnlimited, t0 + 2s);
  GroundSamples next;
  auto place = health(2, 0, 12);
  place.life = 2;
  auto uav = state(1, 12);
  uav.deposits_sent = 3;  // a new life counts from 0
  next.healths = {place};
  next.states = {uav};
  const Notes notes = rig.take(std::move(next), kUnlimited, t0 + 2100ms);
  EXPECT_TRUE(texts(notes, Kind::LivenessLapsed).empty());
  EXPECT_EQ(texts(notes, Kind::UavLost).size(), 1U);
  EXPECT_EQ(texts(notes, Kind::PlaceLost).size(), 1U);
  EXPECT_EQ(texts(notes, Kind::UavBack), Texts{"uav 1 is back at tick 12"});
  EXPECT_EQ(texts(notes, Kind::PlaceBack), Texts{"place agent 2 is back at tick 12"});
  EXPECT_EQ(rig.intake->liveliness_lapses(), 0U);
}

// A process that died or hangs was last heard when it last asserted, a lease
// before its departure: lost, half a lease after the departure; one that
// departs at the very end of the run is lost too.
TEST(GroundIntake, AProcessSilentAroundItsLapseIsReportedLostHalfALeaseAfterIt) {
  Rig rig;
  GroundSamples heard;
  heard.healths = {health(3, 0)};
  heard.states = {state(0, 10), state(2, 10)};
  rig.take(std::move(heard), kUnlimited, t0);
  GroundSamples gone;
  gone.departed_places = {core::place_id(3, 0)};
  gone.departed_uavs = {0};
  EXPECT_TRUE(rig.take(std::move(gone), kUnlimited, t0 + 1s).empty()) << "not judged yet";
  EXPECT_TRUE(rig.take({}, kUnlimited, t0 + 1500ms).empty()) << "half a lease after it: not yet";
  const Notes lost = rig.take({}, kUnlimited, t0 + 1501ms);
  EXPECT_EQ(texts(lost, Kind::UavLost), Texts{"uav 0 lost (liveliness) at tick 10"});
  EXPECT_EQ(texts(lost, Kind::PlaceLost),
            Texts{"place agent 3 lost (liveliness); region 3 has no live place agent: deposits into it are lost"});
  EXPECT_EQ(texts(rig.take(states({state(0, 12)}), kUnlimited, t0 + 3s), Kind::UavBack),
            Texts{"uav 0 is back at tick 12"});
  GroundSamples last;
  last.departed_uavs = {2};
  rig.take(std::move(last), kUnlimited, t0 + 4s);
  EXPECT_EQ(texts(rig.intake->judge_pending(), Kind::UavLost), Texts{"uav 2 lost (liveliness) at tick 10"});
  EXPECT_EQ(rig.intake->liveliness_lapses(), 0U);
}

// Faults.AStoppedPlaceAgentIsShownAliveAgainWhenItResumes, as it failed in
// CI: UAV 1's home place agent was stopped, the UAV went on through its
// backup (states up to tick 136, 251 deposits), and its home, resumed, told
// of the UAV's departure with the last state it held (tick 28) and relayed
// that state once more. Taken for a death, the copy "started a new life" and
// the UAV's 251 deposits were counted twice.
TEST(GroundIntake, ADepartureFromARelayThatLostTheUavBeforeItsNewestStateIsNoDeath) {
  Rig rig;
  auto early = state(1, 16);
  early.deposits_sent = 40;
  auto newest = state(1, 136);
  newest.deposits_sent = 251;
  rig.take(states({early, newest}), kUnlimited, t0);
  GroundSamples gone;
  gone.departed_uavs = {core::UavDeparture{1, 28}};
  auto copy = state(1, 28);
  copy.deposits_sent = 100;
  gone.states = {copy};
  rig.take(std::move(gone), kUnlimited, t0 + 100ms);
  const Notes later = rig.take({}, kUnlimited, t0 + 3s);
  EXPECT_TRUE(texts(later, Kind::UavLost).empty());
  EXPECT_TRUE(rig.rec->uavs().at(1).alive);
  EXPECT_EQ(rig.rec->uavs().at(1).last.tick, 136U);
  EXPECT_EQ(rig.rec->deposits_sent(), 251U) << "counted once";
  EXPECT_EQ(rig.rec->departures_stale(), 1U);
  EXPECT_EQ(rig.rec->states_stale(), 1U);
  EXPECT_FALSE(rig.conductor->departed(1));
  // The relay that held its newest state telling of its departure is a death.
  GroundSamples dead;
  dead.departed_uavs = {core::UavDeparture{1, 136}};
  rig.take(std::move(dead), kUnlimited, t0 + 4s);
  EXPECT_EQ(texts(rig.take({}, kUnlimited, t0 + 5s), Kind::UavLost), Texts{"uav 1 lost (liveliness) at tick 136"});
  EXPECT_FALSE(rig.rec->uavs().at(1).alive);
  EXPECT_EQ(rig.rec->departures_stale(), 1U);
}

// Lockstep under packet loss: a live process is heard once a tick, and a
// tick takes seconds. Its departure waits twice its longest silence so far
// (at least the lockstep takeover time, 10 s here, at most three times
// that) before it is taken for lost.
TEST(GroundIntake, InLockstepADepartureWaitsTwiceTheLongestSilenceOfItsProcess) {
  Rig rig(GroundIntake::Standby::None, GroundIntake::Pace::Lockstep);
  GroundSamples first;
  first.healths = {health(2, 0)};
  first.states = {state(1, 10), state(0, 10)};
  rig.take(std::move(first), kUnlimited, t0);
  // Place agent 2 and uav 1 next heard 3 s later (a slow tick); uav 0 after 0.1 s.
  rig.take(states({state(0, 10)}), kUnlimited, t0 + 100ms);
  GroundSamples slow;
  slow.healths = {health(2, 0, 11)};
  slow.states = {state(1, 11)};
  rig.take(std::move(slow), kUnlimited, t0 + 3s);
  GroundSamples gone;
  gone.departed_places = {core::place_id(2, 0)};
  gone.departed_uavs = {1, 0};
  rig.take(std::move(gone), kUnlimited, t0 + 4s);
  // Heard 7 s after the departure (seen under 30 % loss): a lapse, though
  // twice their longest silence (6 s) is shorter: the wait is 10 s at least.
  EXPECT_TRUE(rig.take({}, kUnlimited, t0 + 11s).empty());
  GroundSamples late;
  late.healths = {health(2, 0, 12)};
  late.states = {state(1, 12)};
  const Notes lapsed = rig.take(std::move(late), kUnlimited, t0 + 11s);
  EXPECT_EQ(texts(lapsed, Kind::LivenessLapsed).size(), 2U);
  EXPECT_TRUE(texts(lapsed, Kind::UavLost).empty());
  EXPECT_TRUE(texts(lapsed, Kind::PlaceLost).empty());
  // uav 0, never heard again: lost 10 s after its departure, not sooner.
  EXPECT_TRUE(texts(rig.take({}, kUnlimited, t0 + 14s), Kind::UavLost).empty());
  EXPECT_EQ(texts(rig.take({}, kUnlimited, t0 + 14001ms), Kind::UavLost), Texts{"uav 0 lost (liveliness) at tick 10"});
  // At most 30 s: after a 60 s silence (a paused run), lost 30 s after.
  GroundSamples paused;
  paused.healths = {health(2, 0, 13)};
  rig.take(std::move(paused), kUnlimited, t0 + 71s);
  GroundSamples gone2;
  gone2.departed_places = {core::place_id(2, 0)};
  rig.take(std::move(gone2), kUnlimited, t0 + 72s);
  EXPECT_TRUE(rig.take({}, kUnlimited, t0 + 102s).empty());
  EXPECT_EQ(texts(rig.take({}, kUnlimited, t0 + 102001ms), Kind::PlaceLost).size(), 1U);
}

// Realtime: half a lease, however long a process was silent before.
TEST(GroundIntake, InRealtimeADepartureWaitsHalfALease) {
  Rig rig;
  rig.take(states({state(1, 10)}), kUnlimited, t0);
  rig.take(states({state(1, 11)}), kUnlimited, t0 + 3s);
  GroundSamples gone;
  gone.departed_uavs = {1};
  rig.take(std::move(gone), kUnlimited, t0 + 4s);
  EXPECT_TRUE(rig.take({}, kUnlimited, t0 + 4500ms).empty());
  EXPECT_EQ(texts(rig.take({}, kUnlimited, t0 + 4501ms), Kind::UavLost), Texts{"uav 1 lost (liveliness) at tick 11"});
}

TEST(GroundIntake, APhaseDoneOfADepartedUavIsASignOfLifeThatHoldsOffItsDrop) {
  Rig rig;
  rig.take(states({state(0, 10), state(1, 10)}), kUnlimited, t0);
  GroundSamples gone;
  gone.departed_uavs = {0, 1};
  rig.take(std::move(gone), kUnlimited, t0);
  GroundSamples done;
  done.phase_dones = {{core::process_key(core::kRoleUav, 0), 10, static_cast<uint8_t>(core::ClockPhase::Uav), 0, {}}};
  rig.take(std::move(done), kUnlimited, t0 + 4s);
  EXPECT_FALSE(rig.conductor->gone_for_good(0, t0 + 6s)) << "heard 2 s ago, grace 5 s";
  EXPECT_TRUE(rig.conductor->gone_for_good(1, t0 + 6s)) << "silent for 6 s since it left";
}

TEST(GroundIntake, TheFirstDetectionOfATargetIsNotedWithHowManyOfTheTargetsAreFound) {
  Rig rig;
  rig.take(states({state(0, 100, 22, 8), state(1, 100, 22, 9)}));
  GroundSamples s;
  s.detections = {{0, 100, 0, {22, 8}}, {1, 100, 0, {22, 8}}};
  const Notes notes = rig.take(std::move(s));
  EXPECT_EQ(texts(notes, Kind::TargetAcquired), Texts{"target 0 at (22,8) first acquired by uav 0 at tick 100 (1/3)"});
  EXPECT_TRUE(rig.intake->judge_pending().empty()) << "nothing was waiting";
}

TEST(GroundIntake, ADetectionAheadOfItsUavsStateIsJudgedAtTheEndOfTheRun) {
  Rig rig;
  rig.take(states({state(0, 100, 22, 8)}));
  GroundSamples s;
  s.detections = {{0, 101, 0, {22, 8}}};
  EXPECT_TRUE(texts(rig.take(std::move(s)), Kind::TargetAcquired).empty()) << "waits for the state of tick 101";
  EXPECT_EQ(texts(rig.intake->judge_pending(), Kind::TargetAcquired),
            Texts{"target 0 at (22,8) first acquired by uav 0 at tick 101 (1/3)"});
}

// Issue 28: what place agents write or relay, taken only from a process
// heard as one (core/place_vouch.hpp). Processes: 0xA region 0's place
// agent, 0xB region 1's, 0xF a forger's.
core::UavStateMsg from(core::UavStateMsg m, uint64_t participant) {
  m.participant = participant;
  return m;
}

core::HealthMsg health_from(core::RegionId r, uint64_t participant, uint32_t tick = 10) {
  core::HealthMsg h = health(r, 0, tick);
  h.participant = participant;
  return h;
}

// Regions 0 and 1 heard from their processes 0xA and 0xB at t0.
void hear_regions_0_and_1(Rig& rig) {
  GroundSamples h;
  h.healths = {health_from(0, 0xA), health_from(1, 0xB)};
  rig.take(std::move(h), kUnlimited, t0);
}

TEST(GroundIntake, ARelayFromAProcessHeardAsNoPlaceAgentWaitsAndIsTakenOnceItsHealthArrives) {
  Rig rig;
  GroundSamples early;
  early.states = {from(state(0, 5), 0xA)};
  early.target_events = {{0, 5, 0, {2, 2}, 0}};
  early.target_events[0].participant = 0xA;
  rig.take(std::move(early), kUnlimited, t0);
  EXPECT_TRUE(rig.rec->uavs().empty()) << "parked: region 0's health not heard yet";
  EXPECT_EQ(rig.intake->parked(), 2U);
  GroundSamples h;
  h.healths = {health_from(0, 0xA)};
  rig.take(std::move(h), kUnlimited, t0 + 400ms);
  EXPECT_EQ(rig.intake->parked(), 0U);
  ASSERT_EQ(rig.rec->uavs().count(0), 1U) << "taken once its process holds a place id";
  EXPECT_EQ(rig.rec->refused().total(), 0U);
}

TEST(GroundIntake, AForgersRelaysAreRefusedAfterTheyWaitedAndItsHealthForAHeldRegionAtOnce) {
  Rig rig;  // lease 1 s: takeover 2 s, a sample waits 4 s
  hear_regions_0_and_1(rig);
  // The forger: a health of region 0, a plausible state of uav 0, a
  // departure of uav 1, a field chunk of region 3 (held by nobody yet) with
  // a tile.
  GroundSamples one;
  one.states = {from(state(1, 5), 0xB)};
  rig.take(std::move(one), kUnlimited, t0 + 50ms);
  GroundSamples forged;
  forged.healths = {health_from(0, 0xF)};
  forged.states = {from(state(0, 5), 0xF)};
  forged.fields = {chunk(3, 5, 0, 1)};
  forged.fields[0].tiles = {tile(4, 4, 5, 0.5F)};
  forged.fields[0].participant = 0xF;
  forged.departed_uavs = {core::UavDeparture{1, 5}};  // a relayed departure of uav 1
  forged.departed_uavs[0].participant = 0xF;
  rig.take(std::move(forged), kUnlimited, t0 + 100ms);
  EXPECT_EQ(rig.rec->refused()[core::Refusal::ForeignWriter], 1U) << "the health, at once";
  EXPECT_EQ(rig.intake->parked(), 3U);
  // Region 0's own states go on meanwhile.
  GroundSamples own;
  own.states = {from(state(0, 5), 0xA)};
  own.healths = {health_from(0, 0xA)};
  rig.take(std::move(own), kUnlimited, t0 + 3s);
  ASSERT_EQ(rig.rec->uavs().count(0), 1U);
  rig.take({}, kUnlimited, t0 + 4200ms);
  EXPECT_EQ(rig.intake->parked(), 0U);
  EXPECT_EQ(rig.rec->refused()[core::Refusal::ForeignWriter], 4U)
      << "the state, the departure and the chunk, after 4 s";
  EXPECT_FALSE(rig.conductor->gone_for_good(1, t0 + 10s)) << "nobody was told uav 1 left";
  EXPECT_TRUE(std::isnan(rig.intake->field_value(0, {24, 24}))) << "the forged tile never reached the field";
}

TEST(GroundIntake, AFieldChunkOrTileOfARegionFromAnotherPlaceAgentsProcessIsRefused) {
  Rig rig;
  hear_regions_0_and_1(rig);
  GroundSamples s;
  s.fields = {chunk(1, 5, 0, 1)};
  s.fields[0].participant = 0xA;    // region 0's process, as region 1
  s.tiles = {tile(3, 0, 5, 0.5F)};  // tile (3,0) is region 1's
  s.tiles[0].participant = 0xA;
  rig.take(std::move(s), kUnlimited, t0 + 10ms);
  EXPECT_EQ(rig.rec->refused()[core::Refusal::ForeignWriter], 2U);
  EXPECT_TRUE(std::isnan(rig.intake->field_value(0, {18, 0})));
  GroundSamples ok;
  ok.tiles = {tile(3, 0, 5, 0.5F)};
  ok.tiles[0].participant = 0xB;
  rig.take(std::move(ok), kUnlimited, t0 + 20ms);
  EXPECT_EQ(rig.intake->field_value(0, {18, 0}), 0.5F);
}

TEST(GroundIntake, APlaceAgentStartedAgainTakesItsRegionByItsLaterLifeAndItsRelaysWaitUntilThen) {
  Rig rig;
  GroundSamples h;
  h.healths = {health_from(0, 0xA)};
  rig.take(std::move(h), kUnlimited, t0);
  // Killed at t0; started again 1.5 s later as a new process, life 2.
  GroundSamples next;
  next.states = {from(state(0, 8), 0xC)};
  next.healths = {health_from(0, 0xC, 20)};
  next.healths[0].life = 2;
  rig.take(std::move(next), kUnlimited, t0 + 1500ms);
  EXPECT_EQ(rig.rec->refused().total(), 0U);
  EXPECT_EQ(rig.intake->parked(), 0U);
  EXPECT_EQ(rig.rec->uavs().count(0), 1U);
}

}  // namespace
}  // namespace pheromesh::console

// Issue 42 D5: only names the run has, only from their holder
// (core/sender_judge.hpp); detections judged against the position of their
// own tick.
namespace pheromesh::console {
namespace {

TEST(GroundIntake, AHealthOfAStandbyTheRunDoesNotHaveOrOfARegionBeyondTheMapIsRefusedAndMakesNoPlaceAgent) {
  Rig rig;  // small-test: 4 regions, no standbys
  GroundSamples forged;
  forged.healths = {health(0, 1), health(7, 0)};
  forged.healths[0].participant = 0xF;
  forged.healths[0].deposits_applied = 1;  // counters that would replace region 0's in metrics.json
  forged.healths[1].participant = 0xF;
  forged.states = {from(state(0, 5), 0xF)};
  rig.take(std::move(forged), kUnlimited, t0);
  EXPECT_EQ(rig.rec->refused()[core::Refusal::UnknownPlace], 2U);
  EXPECT_TRUE(rig.rec->replica_health().empty()) << "no counters of an id the run does not have";
  EXPECT_EQ(rig.intake->parked(), 1U) << "its relay waits: its process holds no place id";
  rig.take({}, kUnlimited, t0 + 4200ms);
  EXPECT_EQ(rig.rec->refused()[core::Refusal::ForeignWriter], 1U) << "and is refused once it waited";
  EXPECT_TRUE(rig.rec->uavs().empty());
}

TEST(GroundIntake, WhatADepartedPlaceAgentRelaysIsTakenUntilAnotherProcessHoldsItsId) {
  // Lockstep under loss: place agent 0's liveliness lapsed, and its next
  // health comes only with the next tick, which waits for the UAV states it
  // relays. They are taken, not parked.
  Rig rig(GroundIntake::Standby::None, GroundIntake::Pace::Lockstep);
  GroundSamples h;
  h.healths = {health_from(0, 0xA)};
  rig.take(std::move(h), kUnlimited, t0);
  GroundSamples gone;
  gone.departed_places = {core::place_id(0, 0)};
  rig.take(std::move(gone), kUnlimited, t0 + 1s);
  rig.take(states({from(state(0, 11), 0xA)}), kUnlimited, t0 + 2s);
  EXPECT_EQ(rig.intake->parked(), 0U);
  ASSERT_TRUE(rig.rec->uavs().contains(0));
  EXPECT_EQ(rig.rec->uavs().at(0).last.tick, 11U);
  // Killed and started again: the new process takes the id at once, and
  // the old one's relays wait (and are refused once they waited).
  GroundSamples next;
  next.healths = {health_from(0, 0xB, 12)};
  next.states = {from(state(0, 12), 0xA)};
  rig.take(std::move(next), kUnlimited, t0 + 3s);
  EXPECT_EQ(rig.rec->replica_health().at(core::place_id(0, 0)).participant, 0xBU);
  EXPECT_EQ(rig.intake->parked(), 1U);
  rig.take({}, kUnlimited, t0 + 16s);
  EXPECT_EQ(rig.rec->refused()[core::Refusal::ForeignWriter], 1U);
  EXPECT_EQ(rig.rec->uavs().at(0).last.tick, 11U);
}

TEST(GroundIntake, APhaseDoneFromAProcessThatIsNotTheUavsGatewayIsRefusedAndTheConductorNeverCountsIt) {
  Rig rig(GroundIntake::Standby::None, GroundIntake::Pace::Lockstep);
  GroundSamples h;
  h.healths = {health_from(0, 0xA), health_from(1, 0xB), health_from(2, 0xC), health_from(3, 0xD)};
  rig.take(std::move(h), kUnlimited, t0);
  (void)rig.conductor->begin_phase(10, core::ClockPhase::Uav, t0);
  const auto done = [](uint32_t uav, uint64_t participant) {
    core::PhaseDoneMsg m{
        core::process_key(core::kRoleUav, uav), 10, static_cast<uint8_t>(core::ClockPhase::Uav), 0, {}};
    m.participant = participant;
    return m;
  };
  GroundSamples forged;
  forged.phase_dones = {done(0, 0xF), done(1, 0xF), done(2, 0xA), done(3, 0xB)};
  core::PhaseDoneMsg place{core::process_key(core::kRolePlace, core::place_id(0, 0)),
                           10,
                           static_cast<uint8_t>(core::ClockPhase::Uav),
                           0,
                           {}};
  place.participant = 0xF;
  forged.phase_dones.push_back(place);
  rig.take(std::move(forged), kUnlimited, t0 + 10ms);
  EXPECT_EQ(rig.rec->refused()[core::Refusal::ForeignReport], 5U)
      << "a forger's, and uav 2's and 3's from place agents that are neither their home nor their backup";
  EXPECT_EQ(rig.conductor->status(t0 + 20ms).waiting, 4U) << "no UAV's report was taken";
  GroundSamples real;
  real.phase_dones = {done(0, 0xA), done(1, 0xC)};  // uav 0 through its home, uav 1 through its backup
  rig.take(std::move(real), kUnlimited, t0 + 30ms);
  EXPECT_EQ(rig.conductor->status(t0 + 40ms).waiting, 2U);
  EXPECT_EQ(rig.rec->refused()[core::Refusal::ForeignReport], 5U);
}

TEST(GroundIntake, ADetectionOlderThanThePositionsKeptOfItsUavIsRefusedAsStale) {
  Rig rig;
  std::vector<core::UavStateMsg> flown;
  // Uav 0 stays on target 0 (22,8) from tick 20 (reachable from its start)
  // to 219: the ground keeps 128 of its positions, from tick 92.
  for (uint32_t k = 20; k < 220; ++k) flown.push_back(state(0, k, 22, 8));
  rig.take(states(flown));
  GroundSamples old;
  old.detections = {{0, 10, 0, {22, 8}}};
  EXPECT_TRUE(texts(rig.take(std::move(old)), Kind::TargetAcquired).empty());
  EXPECT_EQ(rig.rec->refused()[core::Refusal::StaleDetection], 1U) << "tick 10 is before the oldest kept (92)";
  GroundSamples kept;
  kept.detections = {{0, 150, 0, {22, 8}}};
  EXPECT_EQ(texts(rig.take(std::move(kept)), Kind::TargetAcquired),
            Texts{"target 0 at (22,8) first acquired by uav 0 at tick 150 (1/3)"});
  for (std::size_t i = 0; i < core::kRefusalCount; ++i) {
    if (static_cast<core::Refusal>(i) != core::Refusal::StaleDetection) {
      EXPECT_EQ(rig.rec->refused()[static_cast<core::Refusal>(i)], 0U)
          << core::refusal_name(static_cast<core::Refusal>(i));
    }
  }
}

TEST(GroundIntake, ADetectionOfAUavsFirstTicksIsJudgedWhileEveryPositionSinceItsFirstIsKept) {
  Rig rig;
  std::vector<core::UavStateMsg> flown;
  for (uint32_t k = 20; k < 100; ++k) flown.push_back(state(0, k, 22, 8));
  rig.take(states(flown));
  GroundSamples s;
  s.detections = {{0, 20, 0, {22, 8}}};
  EXPECT_EQ(texts(rig.take(std::move(s)), Kind::TargetAcquired).size(), 1U);
  EXPECT_EQ(rig.rec->refused()[core::Refusal::StaleDetection], 0U);
}

TEST(GroundIntake, BeforeAKillItWaitsForTheHealthOfEveryLiveReplicaOfTheTickAndNotForADroppedRegionOrAGoneStandby) {
  Rig rig(GroundIntake::Standby::Hot);
  GroundSamples heard;
  heard.healths = {health(0, 0, 5), health(0, 1, 4), health(1, 0, 5), health(3, 0, 6), health(3, 1, 5)};
  rig.take(std::move(heard));
  EXPECT_EQ(
      rig.intake->places_without_health_of(5),
      (std::vector<uint32_t>{core::place_id(0, 1), core::place_id(1, 1), core::place_id(2, 0), core::place_id(2, 1)}))
      << "an older health is no health of the tick; region 3's of tick 6 is";
  EXPECT_TRUE(rig.intake->places_without_health_of(4).size() == 3U) << "region 0's standby has tick 4's";
  ASSERT_TRUE(rig.conductor->drop_region(2));
  rig.conductor->on_place_killed(core::place_id(1, 1));
  EXPECT_EQ(rig.intake->places_without_health_of(5), std::vector<uint32_t>{core::place_id(0, 1)});
  Rig single;  // no standbys: replica 1 is never waited for
  EXPECT_EQ(
      single.intake->places_without_health_of(0),
      (std::vector<uint32_t>{core::place_id(0, 0), core::place_id(1, 0), core::place_id(2, 0), core::place_id(3, 0)}));
}

TEST(GroundIntake, AMonitorsRunIsOverFiveSecondsAfterEveryPlaceAgentItHeardFinishedAndNamesTheRegionsNeverHeard) {
  Rig rig;
  EXPECT_FALSE(rig.intake->heard_places_over(t0 + 60s)) << "none heard: not over";
  GroundSamples heard;
  heard.healths = {health(0, 0), health(1, 0)};
  heard.healths[0].finished = true;
  rig.take(std::move(heard));
  EXPECT_FALSE(rig.intake->heard_places_over(t0)) << "region 1's place agent has not finished";
  GroundSamples last;
  last.healths = {health(1, 0, 11)};
  last.healths[0].finished = true;
  rig.take(std::move(last), kUnlimited, t0 + 1s);
  EXPECT_FALSE(rig.intake->heard_places_over(t0 + 1s));
  EXPECT_FALSE(rig.intake->heard_places_over(t0 + 6s)) << "5 s, not more";
  EXPECT_EQ(rig.intake->heard_places_over(t0 + 6s + 1ms), (std::vector<core::RegionId>{2, 3}));
  // One more place agent heard, not finished: the wait starts again once it is.
  GroundSamples late;
  late.healths = {health(2, 0, 11)};
  rig.take(std::move(late), kUnlimited, t0 + 7s);
  EXPECT_FALSE(rig.intake->heard_places_over(t0 + 7s));
  GroundSamples gone;
  gone.departed_places = {core::place_id(2, 0)};
  rig.take(std::move(gone), kUnlimited, t0 + 8s);
  EXPECT_FALSE(rig.intake->heard_places_over(t0 + 8s)) << "a departure counts as finished; the 5 s start now";
  EXPECT_FALSE(rig.intake->heard_places_over(t0 + 13s));
  EXPECT_EQ(rig.intake->heard_places_over(t0 + 14s), (std::vector<core::RegionId>{3}));
}

}  // namespace
}  // namespace pheromesh::console
