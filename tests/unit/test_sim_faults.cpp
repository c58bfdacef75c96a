// Faults in the simulator (faults.hpp, "Meaning at tick k"; simulator.hpp):
// killed UAVs, frozen regions, lost deposits, blind home UAVs, standby.
// Every expected number is worked out by hand in the comments, on maps small
// enough that the UAVs' random walks cannot change it.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "pheromesh/core/faults.hpp"
#include "pheromesh/core/layers.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"
#include "pheromesh/shao/policy.hpp"

using namespace pheromesh::core;

namespace {

// An obstacle-free Shao search map of 4-cell tiles cut into regions_x x 1
// regions; the UAVs start in `start`.
ScenarioConfig tiny(int32_t width, int32_t height, int32_t regions_x, uint32_t uavs, Rect start, uint32_t ticks) {
  ScenarioConfig s;
  s.name = "tiny";
  s.width = width;
  s.height = height;
  s.tile_size = 4;
  s.regions_x = regions_x;
  s.regions_y = 1;
  s.uavs = uavs;
  s.start_area = start;
  s.ticks = ticks;
  s.seed = 7;
  return s;
}

// The same map flown by a policy that reads its neighbours (Shao search
// reads none, so its views carry none: PolicyTraits::reads_neighbours):
// Shao 2020 navigation, holding the start positions for the whole run.
ScenarioConfig reading_neighbours(ScenarioConfig s) {
  ShaoNavigationConfig nav;
  nav.region_centre = {s.width / 2, s.height / 2};
  nav.hold_ticks = s.ticks + 1;
  s.set_policy_config(nav);
  return s;
}

FaultSchedule schedule(const std::string& text) {
  auto s = parse_fault_schedule(text);
  EXPECT_TRUE(s.ok()) << s.error().message;
  return s.ok() ? s.value() : FaultSchedule{};
}

void set_faults(Simulator& sim, const std::string& text, bool standby = false) {
  auto notes = sim.set_faults(schedule(text), standby);
  ASSERT_TRUE(notes.ok()) << notes.error().message;
}

struct Ledger {
  uint64_t applied = 0, rejected = 0;
};
Ledger ledger(const Simulator& sim) {
  Ledger l;
  for (const auto& [r, h] : sim.recorder().health()) {
    l.applied += h.deposits_applied;
    l.rejected += h.deposits_rejected;
  }
  return l;
}

uint64_t region_applied(const Simulator& sim, RegionId r) { return sim.recorder().health().at(r).deposits_applied; }

// Every value of every layer over `rect`.
std::vector<float> values(const Simulator& sim, const Rect& rect) {
  std::vector<float> v;
  for (int l = 0; l < sim.layer_count(); ++l) {
    for (int32_t y = rect.y0; y < rect.y0 + rect.h; ++y) {
      for (int32_t x = rect.x0; x < rect.x0 + rect.w; ++x) v.push_back(sim.field_value(l, {x, y}));
    }
  }
  return v;
}

// 96 x 8 cells, regions 0 (x 0..47) and 1 (x 48..95), path radius D0 = 1;
// three UAVs start on the top row at x = 0, 32, 64 (start_cell spreads them
// over the 96 cells of the start row: k = id * 96 / 3). In ticks 0..6 a UAV
// moves at most 6 cells, so each one stays more than D0 away from the border
// and sends exactly one deposit per tick (a path visit) to the region it is
// in: UAV 0 (home 0) to region 0, UAV 1 (home 1) to region 0, UAV 2
// (home 0) to region 1.
ScenarioConfig three_uavs_two_regions() {
  ScenarioConfig s = tiny(96, 8, 2, 3, {0, 0, 96, 1}, 6);
  s.layers.d0 = 1.0;
  return s;
}

}  // namespace

TEST(SimFaults, AKilledUavMakesNoDepositFromItsKillTickOn) {
  // Ticks 0..6 are 7 steps: 7 deposits per UAV; UAV 1 killed at tick 4 acts
  // in ticks 0..3 only: 4 deposits. Sent 7 + 4 + 7 = 18, all applied.
  Simulator sim(three_uavs_two_regions());
  set_faults(sim, "kill uav:1 @4t");
  sim.run();
  const auto& uavs = sim.recorder().uavs();
  EXPECT_EQ(uavs.at(0).last.deposits_sent, 7U);
  EXPECT_EQ(uavs.at(1).last.deposits_sent, 4U);
  EXPECT_EQ(uavs.at(2).last.deposits_sent, 7U);
  EXPECT_EQ(sim.recorder().deposits_sent(), 18U);
  EXPECT_EQ(ledger(sim).applied, 18U);
  EXPECT_EQ(region_applied(sim, 0), 11U);  // UAVs 0 and 1
  EXPECT_EQ(region_applied(sim, 1), 7U);   // UAV 2
  EXPECT_EQ(sim.recorder().deposits_lost(), 0U);
  // Its last state is that of tick 3; it never finished, it died.
  EXPECT_EQ(uavs.at(1).last.tick, 3U);
  EXPECT_FALSE(uavs.at(1).alive);
  EXPECT_FALSE(uavs.at(1).finished);
  EXPECT_EQ(sim.uav_steps(), 7U + 4U + 7U);
  EXPECT_EQ(sim.recorder().uavs_killed(), 1U);
  EXPECT_EQ(sim.uav_kill_tick(1), 4U);
}

TEST(SimFaults, AUavKilledBeforeTickZeroIsAsIfItNeverFlew) {
  // Obstacle-free: UAV 0's start cell and random stream do not depend on the
  // swarm size, so a swarm of two whose UAV 1 dies at tick 0 flies exactly
  // the one-UAV swarm (same field, same coverage).
  ScenarioConfig two = tiny(24, 24, 2, 2, {0, 0, 4, 4}, 60);
  ScenarioConfig one = two;
  one.uavs = 1;
  Simulator a(two), b(one);
  set_faults(a, "kill uav:1 @0t");
  a.run();
  b.run();
  EXPECT_EQ(values(a, {0, 0, 24, 24}), values(b, {0, 0, 24, 24}));
  EXPECT_EQ(a.recorder().coverage().covered_cells(), b.recorder().coverage().covered_cells());
  EXPECT_EQ(a.recorder().deposits_sent(), b.recorder().deposits_sent());
  // Guard: with UAV 1 alive the field is not that of one UAV.
  Simulator c(two);
  c.run();
  EXPECT_NE(values(c, {0, 0, 24, 24}), values(b, {0, 0, 24, 24}));
}

TEST(SimFaults, AKilledUavCoversNothingFromItsKillTickOn) {
  // 16 x 4 cells, sensor radius 1 (a plus of 5 cells), the fixed-route
  // lawnmower (deterministic, no interaction). Strips: rows 0-1 (lane y = 1)
  // and rows 2-3 (lane y = 3). UAV 0 starts at (0,0), UAV 1 at (0,1) (the
  // start area's 4 cells, k = id * 4 / 2).
  //   UAV 0: (0,0) (0,1) (1,1) ... (15,1): covers rows 0..2, 48 cells.
  //   UAV 1: (0,1) (0,2) (0,3) (1,3) (2,3) (3,3) ... (15,3).
  // Killed at tick 5, UAV 1 was at (0,1) (0,2) (0,3) (1,3) (2,3): of row 3
  // it covered x = 0..3. Coverage 48 + 4 = 52 of 64 cells.
  ScenarioConfig s = tiny(16, 4, 1, 2, {0, 0, 2, 2}, 20);
  s.aco.sensor_radius = 1;
  ShaoSearchConfig lawnmower;
  lawnmower.route = ShaoRoute::LawnmowerTransit;
  s.set_policy_config(lawnmower);
  Simulator killed(s);
  set_faults(killed, "kill uav:1 @5t");
  killed.run();
  EXPECT_EQ(killed.recorder().coverage().reachable_cells(), 64);
  EXPECT_EQ(killed.recorder().coverage().covered_cells(), 52);
  // Guard: alive, it covers the whole map.
  Simulator alive(s);
  alive.run();
  EXPECT_EQ(alive.recorder().coverage().covered_cells(), 64);
}

TEST(SimFaults, AFrozenRegionKeepsItsValuesWhileALiveRegionEvaporates) {
  // 16 x 8 cells, regions 0 (x 0..7) and 1 (x 8..15); obstacle cells (6,4)
  // in region 0 and (9,4) in region 1. One UAV starts at (7,0), home 0; with
  // sensor radius 5 it sees both obstacles at tick 0 and marks them (kε = 1,
  // applied in the place phase of tick 0). Obstacle pheromone without
  // diffusion (Gε = 0), Eε = 1/2, dε = 1: Shao 2020 eq. (3) gives
  // ε(t+1) = (1/2)(ε(t) + 1), so after tick t ε = 1 - 2^-(t+1), exact in float.
  // Region 1 killed at tick 3 ran ticks 0..2: 1 - 1/8 = 0.875, for good.
  // Region 0 runs ticks 0..10: 1 - 1/2048.
  ScenarioConfig s = tiny(16, 8, 2, 1, {7, 0, 1, 1}, 10);
  s.obstacles = {{6, 4, 1, 1}, {9, 4, 1, 1}};
  s.aco.sensor_radius = 5;
  s.layers.e_eps = 0.5;
  s.layers.g_eps = 0.0;
  s.layers.d_eps = 1.0;
  const int obstacle = static_cast<int>(Layer::Obstacle);
  const Rect region1{8, 0, 8, 8};
  Simulator sim(s);
  set_faults(sim, "kill place:1 @3t");
  std::vector<float> after_tick_2;
  float live_after_tick_2 = 0;
  sim.run([&](uint32_t t) {
    if (t != 2) return;
    after_tick_2 = values(sim, region1);
    live_after_tick_2 = sim.field_value(obstacle, {6, 4});
  });
  EXPECT_EQ(sim.field_value(obstacle, {9, 4}), 0.875F);
  EXPECT_EQ(values(sim, region1), after_tick_2);  // every layer, every cell
  EXPECT_EQ(live_after_tick_2, 0.875F);
  EXPECT_EQ(sim.field_value(obstacle, {6, 4}), 1.0F - 1.0F / 2048.0F);
  EXPECT_EQ(sim.recorder().places_killed(), 1U);
  EXPECT_EQ(sim.recorder().regions_frozen(), 1U);
  EXPECT_EQ(sim.region_kill_tick(1), 3U);
  // Guard: alive, region 1 goes on like region 0.
  Simulator alive(s);
  alive.run();
  EXPECT_EQ(alive.field_value(obstacle, {9, 4}), 1.0F - 1.0F / 2048.0F);
}

TEST(SimFaults, DepositsIntoADeadRegionAreLostAndThoseOfItsHomeUavsGoThroughTheirBackup) {
  // Region 1 killed at tick 4 (ticks 0..6, one deposit per UAV and tick):
  //   UAV 0 (home 0, in region 0): 7 applied by region 0;
  //   UAV 1 (home 1, backup 0, in region 0): ticks 0..3 forwarded by region 1
  //     and applied by region 0 (4), ticks 4..6 through its backup, region 0
  //     itself, applied by region 0 (3);
  //   UAV 2 (home 0, in region 1): ticks 0..3 applied by region 1 (4), ticks
  //     4..6 lost: their region is dead (3).
  // Sent 21 = applied 18 + rejected 0 + lost 3. Before the backup gateway
  // UAV 1's last 3 were lost with its home too (applied 15, lost 6).
  Simulator sim(three_uavs_two_regions());
  set_faults(sim, "kill place:1 @4t");
  sim.run();
  EXPECT_EQ(sim.recorder().deposits_sent(), 21U);
  EXPECT_EQ(region_applied(sim, 0), 14U);
  EXPECT_EQ(region_applied(sim, 1), 4U);  // its ledger as it died
  EXPECT_FALSE(sim.recorder().health().at(1).finished);
  EXPECT_TRUE(sim.recorder().health().at(0).finished);
  EXPECT_EQ(ledger(sim).applied, 18U);
  EXPECT_EQ(ledger(sim).rejected, 0U);
  EXPECT_EQ(sim.recorder().deposits_lost(), 3U);
  EXPECT_EQ(sim.recorder().deposits_sent(),
            ledger(sim).applied + ledger(sim).rejected + sim.recorder().deposits_lost());
  // The UAVs themselves fly on: every one took 7 steps.
  EXPECT_EQ(sim.uav_steps(), 21U);
}

TEST(SimFaults, ADeadRegionGoesDarkAndItsHomeUavsTalkToTheirBackupGateway) {
  // 8 x 8 cells of 4 tiles, regions 0 (x 0..3) and 1 (x 4..7); two UAVs at
  // (0,0) (home 0, backup 1) and (1,0) (home 1, backup 0). Every UAV's
  // neighbourhood (5 cells around it) covers all 4 tiles: a view has 4 tiles
  // x 4 layers = 16 tile samples and the other UAV. Region 1 killed at tick
  // 3: its last views are those of tick 2, read at tick 3. From tick 3 UAV 1
  // talks to region 0, its backup, which publishes its states and composes
  // its views of tick 3 on. Region 1 is dark from its views of tick 3 on:
  // both UAVs read 16 tile samples at ticks 1..3 and only region 0's 2 tiles
  // x 4 layers = 8 at ticks 4..10, keep seeing each other, and hold nothing
  // of region 1 in their caches.
  ScenarioConfig s = reading_neighbours(tiny(8, 8, 2, 2, {0, 0, 2, 1}, 10));
  Simulator sim(s);
  set_faults(sim, "kill place:1 @3t");
  std::vector<std::size_t> seen0, seen1;  // neighbours seen at ticks 0..10
  sim.run([&](uint32_t) {
    seen0.push_back(sim.uav(0).last_view_neighbours());
    seen1.push_back(sim.uav(1).last_view_neighbours());
  });
  const std::vector<std::size_t> every_tick{0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
  EXPECT_EQ(seen0, every_tick);
  EXPECT_EQ(seen1, every_tick);
  const auto& uavs = sim.recorder().uavs();
  for (uint32_t u : {0U, 1U}) {
    EXPECT_EQ(uavs.at(u).last.tile_samples_received, 16U * 3U + 8U * 7U) << "uav " << u;  // ticks 1..3, 4..10
    for (const Cell c : {Cell{4, 0}, Cell{7, 7}}) EXPECT_FALSE(sim.uav(u).tiles().value(0, c)) << u << ": " << c.x;
    EXPECT_TRUE(sim.uav(u).tiles().value(0, {3, 3})) << "uav " << u;
  }
  EXPECT_EQ(uavs.at(1).last.tick, 10U);
  EXPECT_EQ(sim.uav_steps(), 22U);
  // Guard: without the kill every view has all 16 tile samples.
  Simulator alive(s);
  alive.run();
  EXPECT_EQ(alive.recorder().uavs().at(1).last.tile_samples_received, 160U);
}

TEST(SimFaults, AUavWhoseHomeAndBackupAreBothDeadFliesBlindAndVanishesFromTheOthers) {
  // Three regions of 4 x 4 cells side by side (one tile each); UAV 0 starts
  // at (3,1) in region 0 (home 0), UAV 1 at (4,1) in region 1 (home 1, backup
  // 2). Regions 1 and 2 killed at tick 3: UAV 1 has no live gateway. From
  // tick 4 it reads no view (its tile samples stop growing), its states are
  // published by nobody (UAV 0 sees no neighbour) and every deposit it makes
  // from tick 3 on is lost.
  const ScenarioConfig s = tiny(12, 4, 3, 2, {3, 1, 2, 1}, 10);
  Simulator sim(s);
  set_faults(sim, "kill place:1 @3t; kill place:2 @3t");
  std::vector<uint64_t> samples1;
  sim.run([&](uint32_t) { samples1.push_back(sim.recorder().uavs().at(1).last.tile_samples_received); });
  ASSERT_EQ(samples1.size(), 11U);
  EXPECT_GT(samples1[3], 0U);
  for (uint32_t k = 4; k <= 10; ++k) EXPECT_EQ(samples1[k], samples1[3]) << "tick " << k;
  EXPECT_GT(sim.recorder().deposits_lost(), 0U);
  // Flown by a policy that reads its neighbours, UAV 0 sees UAV 1 (views of
  // ticks 0..2, read at 1..3) and then no more.
  Simulator nav(reading_neighbours(s));
  set_faults(nav, "kill place:1 @3t; kill place:2 @3t");
  std::vector<std::size_t> seen0;
  nav.run([&](uint32_t) { seen0.push_back(nav.uav(0).last_view_neighbours()); });
  EXPECT_EQ(seen0, (std::vector<std::size_t>{0, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0}));
}

TEST(SimFaults, AStandbyMakesAPlaceKillChangeNothing) {
  auto loaded = load_scenario(std::string(PHEROMESH_SOURCE_DIR) + "/scenarios/small-test.textproto");
  ASSERT_TRUE(loaded.ok());
  ScenarioConfig s = loaded.value();
  s.ticks = 120;
  const Rect map{0, 0, s.width, s.height};
  Simulator plain(s);
  plain.run();
  Simulator standby(s);
  set_faults(standby, "kill place:1 @20t; kill place:3 @40t", true);
  standby.run();
  EXPECT_EQ(values(standby, map), values(plain, map));
  EXPECT_EQ(standby.recorder().coverage().covered_cells(), plain.recorder().coverage().covered_cells());
  EXPECT_EQ(standby.recorder().acquisitions().acquisition_ticks(), plain.recorder().acquisitions().acquisition_ticks());
  EXPECT_EQ(standby.recorder().deposits_sent(), ledger(standby).applied);
  EXPECT_EQ(standby.recorder().deposits_lost(), 0U);
  EXPECT_EQ(standby.recorder().places_killed(), 2U);   // two processes died...
  EXPECT_EQ(standby.recorder().regions_frozen(), 0U);  // ...and no region with them
  // A `standby place:R` event before R's kill does the same.
  Simulator event(s);
  set_faults(event, "standby place:1 @10t; kill place:1 @20t");
  event.run();
  EXPECT_EQ(values(event, map), values(plain, map));
  // Guard: without a standby the same kills change the field and lose deposits.
  Simulator frozen(s);
  set_faults(frozen, "kill place:1 @20t; kill place:3 @40t");
  frozen.run();
  EXPECT_NE(values(frozen, map), values(plain, map));
  EXPECT_GT(frozen.recorder().deposits_lost(), 0U);
  EXPECT_EQ(frozen.recorder().regions_frozen(), 2U);
  EXPECT_EQ(frozen.recorder().deposits_sent(),
            ledger(frozen).applied + ledger(frozen).rejected + frozen.recorder().deposits_lost());
  // A standby started after the kill is too late.
  Simulator late(s);
  set_faults(late, "kill place:1 @20t; standby place:1 @30t");
  late.run();
  EXPECT_EQ(late.recorder().regions_frozen(), 1U);
}

TEST(SimFaults, EventsThatChangeNoNumbersAreNotedAndWhatCannotBeModelledIsRefused) {
  ScenarioConfig s = tiny(16, 8, 2, 2, {0, 0, 2, 1}, 10);
  {
    Simulator sim(s);
    auto notes =
        sim.set_faults(schedule("stop uav:0 @2t for 1s; loss 20% @3t for 2s; partition place:1 @4t for 1s"), false);
    ASSERT_TRUE(notes.ok()) << notes.error().message;
    ASSERT_EQ(notes.value().size(), 3U);
    EXPECT_NE(notes.value()[0].find("does not change simulated numbers"), std::string::npos) << notes.value()[0];
    sim.run();
    Simulator plain(s);
    plain.run();
    EXPECT_EQ(values(sim, {0, 0, 16, 8}), values(plain, {0, 0, 16, 8}));
  }
  auto refused = [&](const std::string& text, const std::string& why) {
    Simulator sim(s);
    auto r = sim.set_faults(schedule(text), false);
    ASSERT_FALSE(r.ok()) << text;
    EXPECT_NE(r.error().message.find(why), std::string::npos) << r.error().message;
  };
  refused("kill uav:1 @5s", "times faults in ticks");
  refused("restart uav:1 @5t for 1s", "cannot restart");
  refused("kill ground @5t", "no ground station");
  refused("kill uav:2 @5t", "does not exist");
  refused("kill place:2 @5t", "does not exist");
}
