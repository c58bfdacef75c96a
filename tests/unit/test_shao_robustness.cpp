// The pieces of `pheromesh experiment shao2020-robustness` (Shao 2020 Sec. 4.3.3):
// the fixed-route lawnmower with transit, and the reproducible kill draws.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>
#include <string>
#include <vector>

#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/world.hpp"
#include "pheromesh/shao/lawnmower.hpp"
#include "pheromesh/shao/robustness.hpp"

using namespace pheromesh::core;

namespace {

ScenarioConfig shao_50x50() {
  auto s = load_scenario(std::string(PHEROMESH_SOURCE_DIR) + "/scenarios/shao2020-50x50.textproto");
  EXPECT_TRUE(s.ok());
  return s.value();
}

ScenarioConfig strip_map(std::vector<Rect> obstacles) {
  ScenarioConfig s;
  s.name = "strips";
  s.width = 16;
  s.height = 4;
  s.tile_size = 4;
  s.uavs = 2;
  s.start_area = {0, 0, 2, 2};
  s.aco.sensor_radius = 1;
  s.obstacles = std::move(obstacles);
  return s;
}

bool is_step(Cell a, Cell b) { return std::max(std::abs(a.x - b.x), std::abs(a.y - b.y)) == 1; }

}  // namespace

TEST(ShaoLawnmower, RoutesAreWorkedOutByHandOnAStripMap) {
  // 16 x 4, sensor radius 1: lanes 3 rows apart; strip 0 = rows 0-1 (lane
  // y = 1), strip 1 = rows 2-3 (lane y = 3). UAV 0 starts at (0,0), UAV 1
  // at (0,1). Both start on the west side: first sweep eastwards.
  const ScenarioConfig s = strip_map({});
  const MapGeometry geo = s.geometry();  // the world keeps a pointer to it
  const World world(geo, s.obstacles, s.targets);
  EXPECT_EQ(lawnmower_strip(s, 0).lanes, std::vector<int32_t>{1});
  EXPECT_EQ(lawnmower_strip(s, 1).lanes, std::vector<int32_t>{3});
  std::vector<Cell> r0{{0, 0}};
  for (int32_t x = 0; x < 16; ++x) r0.push_back({x, 1});
  EXPECT_EQ(lawnmower_transit_route(s, world, 0), r0);
  // Transit (0,1) -> (0,3): of the two shortest first steps, (0,2) and (1,2),
  // the one nearer the goal.
  std::vector<Cell> r1{{0, 1}, {0, 2}};
  for (int32_t x = 0; x < 16; ++x) r1.push_back({x, 3});
  EXPECT_EQ(lawnmower_transit_route(s, world, 1), r1);
}

TEST(ShaoLawnmower, ARouteGoesAroundAnObstacleOnItsLaneAndComesBackForWhatItMissed) {
  // An obstacle at (5,1) on UAV 0's lane: from (4,1) to (6,1) the two
  // shortest ways are over (5,0) and (5,2), equally near the goal; the tie
  // goes to the first in heading order E, NE (= +x, +y): (5,2). With sensor
  // radius 1, (5,0) of its strip was then never in range (from (4,1), (6,1)
  // it is sqrt(2) away): at the lane's end (15,1) the UAV flies back to it,
  // 10 steps along row 0 (of the shortest first steps (14,0), (14,1),
  // (14,2), the one nearest (5,0)).
  const ScenarioConfig s = strip_map({{5, 1, 1, 1}});
  const MapGeometry geo = s.geometry();  // the world keeps a pointer to it
  const World world(geo, s.obstacles, s.targets);
  const auto r = lawnmower_transit_route(s, world, 0);
  std::vector<Cell> expected{{0, 0}};
  for (int32_t x = 0; x < 5; ++x) expected.push_back({x, 1});
  expected.push_back({5, 2});
  for (int32_t x = 6; x < 16; ++x) expected.push_back({x, 1});
  for (int32_t x = 14; x >= 5; --x) expected.push_back({x, 0});
  EXPECT_EQ(r, expected);
  EXPECT_EQ(free_path(world, {4, 1}, {6, 1}), (std::vector<Cell>{{5, 2}, {6, 1}}));
  EXPECT_TRUE(free_path(world, {4, 1}, {5, 1}).empty());  // into an obstacle: no path
}

TEST(ShaoLawnmower, EveryRouteStartsInTheStartAreaFliesOneStepPerTickAndAvoidsObstacles) {
  const ScenarioConfig s = shao_50x50();
  const MapGeometry geo = s.geometry();  // the world keeps a pointer to it
  const World world(geo, s.obstacles, s.targets);
  for (uint32_t id = 0; id < s.uavs; ++id) {
    const auto r = lawnmower_transit_route(s, world, id);
    ASSERT_GT(r.size(), 1U);
    EXPECT_EQ(r.front(), start_cell(s, id));
    EXPECT_TRUE(s.start_area.contains(r.front())) << "uav " << id;
    for (std::size_t t = 1; t < r.size(); ++t) {
      EXPECT_TRUE(is_step(r[t - 1], r[t])) << "uav " << id << " tick " << t;
      EXPECT_FALSE(world.is_obstacle(r[t])) << "uav " << id << " tick " << t;
    }
  }
}

TEST(ShaoLawnmower, EveryRouteCoversItsStripAndTheRoutesTogetherTheMap) {
  // Every reachable cell of a UAV's strip is within the sensor radius of
  // some cell of its route (a cell the UAV is over for one tick).
  const ScenarioConfig s = shao_50x50();
  const MapGeometry geo = s.geometry();
  const World world(geo, s.obstacles, s.targets);
  std::vector<Cell> starts;
  for (uint32_t id = 0; id < s.uavs; ++id) starts.push_back(start_cell(s, id));
  const auto reachable = world.reachable_from(starts);
  const double r2 = s.aco.sensor_radius * s.aco.sensor_radius;
  for (uint32_t id = 0; id < s.uavs; ++id) {
    const auto route = lawnmower_transit_route(s, world, id);
    const LawnmowerStrip strip = lawnmower_strip(s, id);
    int missed = 0;
    for (int32_t y = strip.row_begin; y < strip.row_end; ++y) {
      for (int32_t x = 0; x < geo.width(); ++x) {
        if (reachable[geo.index({x, y})] == 0) continue;
        const bool seen = std::any_of(route.begin(), route.end(), [&](Cell c) {
          return static_cast<double>((c.x - x) * (c.x - x) + (c.y - y) * (c.y - y)) <= r2;
        });
        missed += seen ? 0 : 1;
      }
    }
    EXPECT_EQ(missed, 0) << "uav " << id << " rows " << strip.row_begin << ".." << strip.row_end - 1;
  }
}

TEST(ShaoRobustness, TheKilledUavsAreDrawnReproduciblyPerSeed) {
  EXPECT_EQ(kill_count(0.0, 10), 0U);
  EXPECT_EQ(kill_count(0.1, 10), 1U);
  EXPECT_EQ(kill_count(0.3, 10), 3U);
  EXPECT_EQ(kill_count(2.0, 10), 10U);
  std::set<std::vector<uint32_t>> distinct;
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    const auto three = draw_killed_uavs(seed, 10, 3);
    EXPECT_EQ(three, draw_killed_uavs(seed, 10, 3)) << "seed " << seed;
    ASSERT_EQ(three.size(), 3U);
    EXPECT_TRUE(std::is_sorted(three.begin(), three.end()));
    EXPECT_EQ(std::set<uint32_t>(three.begin(), three.end()).size(), 3U);
    EXPECT_LT(three.back(), 10U);
    // The UAV killed at 10 % is one of those killed at 30 %.
    const auto one = draw_killed_uavs(seed, 10, 1);
    ASSERT_EQ(one.size(), 1U);
    EXPECT_TRUE(std::binary_search(three.begin(), three.end(), one.front())) << "seed " << seed;
    distinct.insert(three);
  }
  EXPECT_GT(distinct.size(), 10U);  // the seed matters
  EXPECT_EQ(draw_killed_uavs(3, 10, 10), (std::vector<uint32_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
  const FaultSchedule f = uav_kill_schedule({2, 7}, 25);
  EXPECT_EQ(f.uav_kills(), (std::vector<std::pair<uint32_t, uint32_t>>{{2, 25}, {7, 25}}));
}

TEST(ShaoRobustness, AFixedRouteLeavesADeadUavsStripUnsearched) {
  // The strip map of the hand-worked routes, 20 ticks. At tick t (2 <= t
  // <= 15) UAV 0 is at (t-1, 1) and UAV 1 at (t-2, 3); the radius-1 plus
  // covers row 0 to x = t-1, row 1 to x = t, row 2 to x = t-1 and row 3 to
  // x = t-1: 4t + 1 cells. 95 % of 64 is 60.8: 61 cells at tick 15.
  ScenarioConfig s = strip_map({});
  s.ticks = 20;
  const auto all = run_robustness(s, ShaoRoute::LawnmowerTransit, 0.0, 1, 5, 0.95);
  EXPECT_TRUE(all.killed.empty());
  ASSERT_EQ(all.coverage.size(), 21U);
  EXPECT_EQ(all.coverage[14], 57.0 / 64.0);
  EXPECT_EQ(all.coverage.back(), 1.0);
  ASSERT_TRUE(all.reached.has_value());
  EXPECT_EQ(*all.reached, 15U);
  // Half the swarm (one UAV, whichever the seed draws) dies at tick 5, before
  // sweeping 11 of its lane's 16 cells: nobody else ever flies them.
  const auto half = run_robustness(s, ShaoRoute::LawnmowerTransit, 0.5, 1, 5, 0.95);
  ASSERT_EQ(half.killed.size(), 1U);
  EXPECT_FALSE(half.reached.has_value());
  EXPECT_LT(half.coverage.back(), 0.95);
}
