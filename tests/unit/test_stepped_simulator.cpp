// The simulator's lifecycle (simulator.hpp): advance() a tick at a time,
// faults added between ticks, finish() - what pheromesh.Simulation drives
// (docs/python.md). A stepped run must be the run `pheromesh sim` makes.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "pheromesh/core/faults.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"

using namespace pheromesh::core;

namespace {

ScenarioConfig small_test_of(uint32_t ticks) {
  auto s = load_scenario(std::string(PHEROMESH_SOURCE_DIR) + "/scenarios/small-test.textproto");
  EXPECT_TRUE(s.ok());
  ScenarioConfig c = s.value();
  c.regions_x = 2;
  c.regions_y = 2;
  c.seed = 4;
  c.ticks = ticks;
  return c;
}

FaultSchedule tick_schedule(const std::string& text) {
  auto s = parse_fault_schedule(text);
  EXPECT_TRUE(s.ok()) << s.error().message;
  return s.ok() ? s.value() : FaultSchedule{};
}

// Every layer's bytes, row-major.
std::vector<float> every_layer(const Simulator& sim) {
  const auto geo = sim.scenario().geometry();
  std::vector<float> v;
  for (int l = 0; l < sim.layer_count(); ++l) {
    for (int32_t y = 0; y < geo.height(); ++y) {
      for (int32_t x = 0; x < geo.width(); ++x) v.push_back(sim.field_value(l, {x, y}));
    }
  }
  return v;
}

bool same_float_bytes(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// Everything series.csv, metrics.json and the final field hold.
void expect_same_stepped_run(const Simulator& a, const Simulator& b) {
  EXPECT_TRUE(same_float_bytes(every_layer(a), every_layer(b)));
  const auto sa = a.recorder().tick_series();
  const auto sb = b.recorder().tick_series();
  ASSERT_EQ(sa.size(), sb.size());
  for (std::size_t i = 0; i < sa.size(); ++i) {
    EXPECT_EQ(sa[i].covered_cells, sb[i].covered_cells) << "tick " << i;
    EXPECT_EQ(sa[i].targets_found, sb[i].targets_found) << "tick " << i;
    EXPECT_EQ(sa[i].uavs_reporting, sb[i].uavs_reporting) << "tick " << i;
    EXPECT_EQ(sa[i].deposits_sent, sb[i].deposits_sent) << "tick " << i;
    EXPECT_EQ(sa[i].deposits_applied, sb[i].deposits_applied) << "tick " << i;
    EXPECT_EQ(sa[i].deposits_rejected, sb[i].deposits_rejected) << "tick " << i;
  }
  EXPECT_EQ(a.recorder().acquisitions().acquisition_ticks(), b.recorder().acquisitions().acquisition_ticks());
  EXPECT_EQ(a.recorder().deposits_sent(), b.recorder().deposits_sent());
  EXPECT_EQ(a.recorder().deposits_lost(), b.recorder().deposits_lost());
  EXPECT_EQ(a.recorder().uavs_killed(), b.recorder().uavs_killed());
  EXPECT_EQ(a.recorder().places_killed(), b.recorder().places_killed());
  EXPECT_EQ(a.recorder().field_summary(), b.recorder().field_summary());
}

// Steps `sim` until tick `until` has run.
void advance_through_tick(Simulator& sim, uint32_t until) {
  while (sim.next_tick() <= until) ASSERT_TRUE(sim.advance());
}

}  // namespace

TEST(SteppedSimulator, AdvancingTickByTickAndFinishingEqualsRunningToTheEnd) {
  Simulator ran(small_test_of(120));
  ran.run();
  Simulator stepped(small_test_of(120));
  EXPECT_EQ(stepped.next_tick(), 0U);
  uint32_t ticks = 0;
  while (stepped.advance()) ++ticks;
  EXPECT_EQ(ticks, 121U);  // ticks 0..120
  EXPECT_TRUE(stepped.done());
  EXPECT_TRUE(stepped.finish());
  expect_same_stepped_run(ran, stepped);
  // The guard: a shorter run differs, so the comparison can fail.
  Simulator shorter(small_test_of(119));
  shorter.run();
  EXPECT_FALSE(same_float_bytes(every_layer(ran), every_layer(shorter)));
}

TEST(SteppedSimulator, FinishRefusesARunWithTicksLeftAndRunsOnlyOnce) {
  Simulator sim(small_test_of(5));
  advance_through_tick(sim, 3);
  EXPECT_FALSE(sim.finish());
  EXPECT_FALSE(sim.finished());
  advance_through_tick(sim, 5);
  EXPECT_FALSE(sim.advance());  // every tick has run
  EXPECT_TRUE(sim.finish());
  EXPECT_FALSE(sim.finish());
  EXPECT_EQ(sim.next_tick(), 6U);
}

TEST(SteppedSimulator, AUavKillAddedBetweenTicksEqualsTheSameKillScheduledBeforeTheRun) {
  Simulator scheduled(small_test_of(100));
  ASSERT_TRUE(scheduled.set_faults(tick_schedule("kill uav:1 @40t"), false).ok());
  scheduled.run();
  Simulator stepped(small_test_of(100));
  advance_through_tick(stepped, 39);
  EXPECT_TRUE(stepped.uav_alive(1));
  auto notes = stepped.add_faults(tick_schedule("kill uav:1 @40t"));
  ASSERT_TRUE(notes.ok()) << notes.error().message;
  EXPECT_FALSE(stepped.uav_alive(1));
  advance_through_tick(stepped, 100);
  ASSERT_TRUE(stepped.finish());
  expect_same_stepped_run(scheduled, stepped);
  EXPECT_EQ(stepped.recorder().uavs_killed(), 1U);
  // The guard: the kill changes the run.
  Simulator unharmed(small_test_of(100));
  unharmed.run();
  EXPECT_NE(unharmed.recorder().deposits_sent(), stepped.recorder().deposits_sent());
}

TEST(SteppedSimulator, APlaceKillAddedBetweenTicksFreezesTheRegionAsTheScheduledKillDoes) {
  // The dead region's neighbours diffuse against its ring of tick 29: the
  // stepped run must still hold it though no kill was known at tick 29.
  Simulator scheduled(small_test_of(80));
  ASSERT_TRUE(scheduled.set_faults(tick_schedule("kill place:1 @30t; kill uav:3 @50t"), false).ok());
  scheduled.run();
  Simulator stepped(small_test_of(80));
  advance_through_tick(stepped, 29);
  ASSERT_TRUE(stepped.add_faults(tick_schedule("kill place:1 @30t")).ok());
  advance_through_tick(stepped, 45);
  ASSERT_TRUE(stepped.add_faults(tick_schedule("kill uav:3 @50t")).ok());  // a kill some ticks ahead
  advance_through_tick(stepped, 80);
  ASSERT_TRUE(stepped.finish());
  expect_same_stepped_run(scheduled, stepped);
  EXPECT_EQ(stepped.region_kill_tick(1), std::optional<uint32_t>(30));
  EXPECT_GT(stepped.recorder().deposits_lost(), 0U);
  EXPECT_EQ(stepped.faults().events.size(), 2U);
}

TEST(SteppedSimulator, AStopBetweenTicksIsNotedAsChangingNoNumber) {
  Simulator sim(small_test_of(20));
  advance_through_tick(sim, 4);
  auto notes = sim.add_faults(tick_schedule("stop place:1 @5t for 2s"));
  ASSERT_TRUE(notes.ok()) << notes.error().message;
  ASSERT_EQ(notes.value().size(), 1U);
  EXPECT_NE(notes.value()[0].find("does not change simulated numbers"), std::string::npos) << notes.value()[0];
  // Only the new event's note: the earlier ones were given before.
  auto more = sim.add_faults(tick_schedule("kill uav:0 @6t"));
  ASSERT_TRUE(more.ok());
  EXPECT_TRUE(more.value().empty());
}

TEST(SteppedSimulator, AFaultThatCannotBeAddedIsRefusedNamingWhyAndChangesNothing) {
  Simulator sim(small_test_of(60));
  advance_through_tick(sim, 20);
  const auto refused = [&](const std::string& text, const std::string& why) {
    auto r = sim.add_faults(tick_schedule(text));
    ASSERT_FALSE(r.ok()) << text;
    EXPECT_NE(r.error().message.find(why), std::string::npos) << r.error().message;
  };
  refused("kill uav:2 @20t", "tick 20 has already run (the next tick is 21)");
  refused("kill uav:99 @30t", "uav-99 does not exist (this swarm has 4 UAVs: uav:0-3)");
  refused("kill place:7 @30t", "place-7 does not exist (this map has 4 regions: place:0-3)");
  refused("restart uav:1 @30t for 1s", "cannot restart");
  EXPECT_TRUE(sim.faults().empty());
  EXPECT_TRUE(sim.uav_alive(2));
  ASSERT_TRUE(sim.add_faults(tick_schedule("kill uav:2 @21t")).ok());
  advance_through_tick(sim, 25);
  refused("kill uav:2 @30t", "uav:2 is already dead (killed at tick 21)");
  advance_through_tick(sim, 60);
  ASSERT_TRUE(sim.finish());
  refused("kill uav:1 @61t", "the run has ended");
}

TEST(SteppedSimulator, GatheringALayerGivesEveryCellsValueRowByRow) {
  Simulator sim(small_test_of(30));
  advance_through_tick(sim, 30);
  const auto geo = sim.scenario().geometry();
  std::vector<float> layer(static_cast<std::size_t>(geo.width() * geo.height()));
  int nonzero = 0;
  for (int l = 0; l < sim.layer_count(); ++l) {
    ASSERT_TRUE(sim.gather_layer(l, layer));
    for (int32_t y = 0; y < geo.height(); ++y) {
      for (int32_t x = 0; x < geo.width(); ++x) {
        const float v = layer[static_cast<std::size_t>(y * geo.width() + x)];
        EXPECT_EQ(v, sim.field_value(l, {x, y}));
        nonzero += v != 0.0F ? 1 : 0;
      }
    }
  }
  EXPECT_GT(nonzero, 0);
  EXPECT_FALSE(sim.gather_layer(sim.layer_count(), layer));
  std::vector<float> wrong(7);
  EXPECT_FALSE(sim.gather_layer(0, wrong));
}
