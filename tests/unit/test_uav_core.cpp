// UavCore's neighbourhood (core/uav_core.hpp): the states of the UAVs near
// it, a few ticks of each, as lockstep's holds_tick reads them.
#include "pheromesh/core/uav_core.hpp"

#include <gtest/gtest.h>

#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/world.hpp"
#include "unit_support.hpp"

namespace pheromesh::core {
namespace {

const auto at = test::state_at;

// UAV 0 of a swarm of three on a 20 x 20 map of 10-cell tiles, all starting
// over tile (0,0).
class UavCore3 : public ::testing::Test {
 protected:
  ScenarioConfig s = parse_scenario(
                         "map { width: 20 height: 20 tile_size: 10 }\n"
                         "swarm { uavs: 3 start_area { x: 0 y: 0 w: 2 h: 2 } }\n",
                         "n")
                         .value();
  MapGeometry geo = s.geometry();
  World world{geo, s.obstacles, s.targets};
  UavCore uav{s, world, 0};
};

TEST_F(UavCore3, ANeighboursLastFourTicksAreKeptAnOlderOneChangesNothingAndATickHeardAgainIsReplaced) {
  // One UAV besides this one over tile (0,0), at each tick asked about.
  const std::vector<TileCount> one{{{0, 0}, 1}};
  for (uint32_t t = 1; t <= 6; ++t) uav.receive_neighbour(at(1, t, 2.0, 2.0));
  EXPECT_FALSE(uav.holds_tick(2, one, 0)) << "ticks 1 and 2 made room for 5 and 6";
  for (uint32_t t = 3; t <= 6; ++t) EXPECT_TRUE(uav.holds_tick(t, one, 0)) << t;
  uav.receive_neighbour(at(1, 1, 2.0, 2.0));  // older than every tick kept
  EXPECT_FALSE(uav.holds_tick(1, one, 0));
  EXPECT_TRUE(uav.holds_tick(3, one, 0)) << "an older state pushes out none";
  uav.receive_neighbour(at(1, 5, 15.0, 15.0));  // tick 5 again, over tile (1,1)
  EXPECT_FALSE(uav.holds_tick(5, one, 0)) << "the state of tick 5 heard last is the one kept";
  uav.receive_neighbour(at(1, 7, 2.0, 2.0));
  EXPECT_FALSE(uav.holds_tick(3, one, 0));
  EXPECT_TRUE(uav.holds_tick(7, one, 0));
  EXPECT_TRUE(uav.holds_tick(4, one, 0));
}

TEST_F(UavCore3, AStepForgetsTheUavsNotHeardForMoreThanFourTicksAndALateStateBringsOneBack) {
  uav.receive_neighbour(at(1, 0, 2.0, 2.0));  // heard last at tick 0
  uav.receive_neighbour(at(2, 1, 3.0, 3.0));  // and at tick 1
  EXPECT_EQ(uav.neighbours_held(), 2U);
  UavCore::Output out;
  uav.step(5, out);  // tick 0 + 4 < 5: UAV 1 can show in no view from tick 5 on
  EXPECT_EQ(uav.neighbours_held(), 1U);
  uav.step(6, out);
  EXPECT_EQ(uav.neighbours_held(), 0U);
  // A late state of UAV 1 of tick 5 is held again, as it would have been.
  uav.receive_neighbour(at(1, 5, 2.0, 2.0));
  EXPECT_EQ(uav.neighbours_held(), 1U);
  EXPECT_TRUE(uav.holds_tick(5, {{{0, 0}, 1}}, 0));
}

TEST_F(UavCore3, ANeighbourIsKnownByItsPoseWhoeverSentIt) {
  // A neighbour's state as a view brings it, counters and all; the step
  // decides on its pose only (the place clock lists other regions' UAVs by
  // pose, and the simulator must show the same).
  UavStateMsg full = at(1, 4, 2.5, 3.5);
  full.vx = 0.5;
  full.heading = 2;
  full.role = 1;
  full.view = {2, 3};
  full.deposits_sent = 9;
  full.samples_received = 40;
  full.ticks_late = 3;
  full.refused[0] = 2;
  uav.receive_neighbour(full);
  UavCore::Output out;
  uav.step(5, out);
  ASSERT_EQ(uav.last_view_states().size(), 1U);
  const UavStateMsg& seen = uav.last_view_states()[0];
  EXPECT_EQ(seen.uav, 1U);
  EXPECT_EQ(seen.tick, 4U);
  EXPECT_DOUBLE_EQ(seen.x, 2.5);
  EXPECT_DOUBLE_EQ(seen.y, 3.5);
  EXPECT_DOUBLE_EQ(seen.vx, 0.5);
  EXPECT_EQ(seen.heading, 2U);
  EXPECT_EQ(seen.role, 1U);
  EXPECT_EQ(seen.view, (Cell{2, 3}));
  EXPECT_EQ(seen.deposits_sent, 0U);
  EXPECT_EQ(seen.samples_received, 0U);
  EXPECT_EQ(seen.ticks_late, 0U);
  EXPECT_EQ(seen.refused[0], 0U);
}

}  // namespace
}  // namespace pheromesh::core
