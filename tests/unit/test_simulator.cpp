// The in-process simulator: determinism, and the region split invisible in
// its results (the same property the lockstep DDS run is tested against).
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <utility>
#include <vector>

#include "pheromesh/core/layers.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"

using namespace pheromesh::core;

namespace {

ScenarioConfig small(int32_t regions_x, int32_t regions_y, uint64_t seed) {
  auto s = load_scenario(std::string(PHEROMESH_SOURCE_DIR) + "/scenarios/small-test.textproto");
  EXPECT_TRUE(s.ok());
  ScenarioConfig c = s.value();
  c.regions_x = regions_x;
  c.regions_y = regions_y;
  c.seed = seed;
  c.ticks = 80;
  return c;
}

void expect_same_run(const Simulator& a, const Simulator& b) {
  const auto geo = a.scenario().geometry();
  int differing = 0;
  for (int l = 0; l < kLayerCount; ++l) {
    for (int32_t y = 0; y < geo.height(); ++y) {
      for (int32_t x = 0; x < geo.width(); ++x) differing += a.field_value(l, {x, y}) != b.field_value(l, {x, y}) ? 1 : 0;
    }
  }
  EXPECT_EQ(differing, 0);
  EXPECT_EQ(a.recorder().acquisitions().acquisition_ticks(), b.recorder().acquisitions().acquisition_ticks());
  EXPECT_EQ(a.recorder().coverage().covered_cells(), b.recorder().coverage().covered_cells());
  EXPECT_EQ(a.recorder().revisit_response_ticks(), b.recorder().revisit_response_ticks());
}

}  // namespace

TEST(Simulator, SameSeedGivesTheSameRun) {
  Simulator a(small(2, 2, 5));
  Simulator b(small(2, 2, 5));
  a.run();
  b.run();
  expect_same_run(a, b);
  EXPECT_GT(a.recorder().coverage().coverage(), 0.3);
}

TEST(Simulator, DifferentSeedsGiveDifferentTrajectories) {
  Simulator a(small(2, 2, 5));
  Simulator b(small(2, 2, 6));
  a.run();
  b.run();
  int differing = 0;
  for (int32_t y = 0; y < 30; ++y) {
    for (int32_t x = 0; x < 30; ++x) {
      differing += a.field_value(static_cast<int>(Layer::Path), {x, y}) != b.field_value(static_cast<int>(Layer::Path), {x, y});
    }
  }
  EXPECT_GT(differing, 0);
}

TEST(Simulator, SplittingTheMapIntoRegionsDoesNotChangeTheRun) {
  // Obstacle pheromone of small-test diffuses across the x = 12 region border.
  Simulator whole(small(1, 1, 3));
  Simulator split(small(2, 2, 3));
  whole.run();
  split.run();
  expect_same_run(whole, split);
}

TEST(Simulator, EveryDepositIsAppliedOrRejected) {
  Simulator s(small(2, 2, 9));
  s.run();
  uint64_t applied = 0, rejected = 0;
  for (const auto& [r, h] : s.recorder().health()) {
    applied += h.deposits_applied;
    rejected += h.deposits_rejected;
  }
  EXPECT_GT(s.recorder().deposits_sent(), 0U);
  EXPECT_EQ(s.recorder().deposits_sent(), applied + rejected);
  EXPECT_EQ(rejected, 0U);
}

// A tick builds only the tiles its UAVs read (issue 44); asking for every
// tile between ticks (the console recording does) gives each live region's
// tiles of that tick, as the field holds them, and changes nothing in the run.
TEST(Simulator, EveryTileAskedForBetweenTicksIsTheFieldOfThatTickAndChangesNothing) {
  Simulator lazy(small(2, 2, 5));
  Simulator asked(small(2, 2, 5));
  const auto geo = asked.scenario().geometry();
  EXPECT_TRUE(asked.tiles().empty());  // no place agent has ticked yet
  while (!lazy.done()) {
    const uint32_t tick = asked.next_tick();
    ASSERT_TRUE(lazy.advance());
    ASSERT_TRUE(asked.advance());
    const auto& tiles = asked.tiles();
    ASSERT_EQ(tiles.size(), static_cast<std::size_t>(geo.tiles_x() * geo.tiles_y()));
    for (const auto& [key, layers] : tiles) {
      ASSERT_EQ(layers.size(), static_cast<std::size_t>(asked.layer_count()));
      for (const TileMsg& m : layers) {
        ASSERT_EQ(m.tick, tick);
        const Rect r = geo.tile_rect(m.tile);
        ASSERT_EQ(m.values.size(), static_cast<std::size_t>(r.area()));
        for (int32_t y = 0; y < r.h; ++y) {
          for (int32_t x = 0; x < r.w; ++x) {
            ASSERT_EQ(m.values[static_cast<std::size_t>(y * r.w + x)],
                      asked.field_value(m.layer, {r.x0 + x, r.y0 + y}));
          }
        }
      }
    }
  }
  lazy.finish();
  asked.finish();
  expect_same_run(lazy, asked);
  EXPECT_EQ(lazy.recorder().deposits_sent(), asked.recorder().deposits_sent());
}

// Each UAV's start cell, computed once per run for the gateways' judges,
// is start_cell's.
TEST(Simulator, StartCellsOfTheWholeSwarmAreEachUavsStartCell) {
  ScenarioConfig s = small(2, 2, 5);
  s.uavs = 7;
  const std::vector<Cell> all = start_cells(s);
  ASSERT_EQ(all.size(), 7U);
  std::set<std::pair<int32_t, int32_t>> distinct;
  for (uint32_t i = 0; i < 7; ++i) {
    EXPECT_EQ(all[i], start_cell(s, i)) << "uav " << i;
    EXPECT_TRUE(s.start_area.contains(all[i])) << "uav " << i;
    for (const Rect& o : s.obstacles) EXPECT_FALSE(o.contains(all[i])) << "uav " << i;
    distinct.insert({all[i].x, all[i].y});
  }
  EXPECT_EQ(distinct.size(), 7U);
}
