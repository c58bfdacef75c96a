// Ground-truth world: obstacles, targets, the sensor disk and reachability.
#include <gtest/gtest.h>

#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/world.hpp"

namespace pheromesh::core {
namespace {

TEST(World, CellsInsideObstacleRectsAreObstaclesAndRectsAreClippedToTheMap) {
  const MapGeometry geo(10, 8, 4, 1, 1);
  // The second rect sticks out of the top-right corner of the map.
  const World w(geo, {Rect{1, 1, 2, 3}, Rect{8, 6, 5, 5}}, {});
  EXPECT_TRUE(w.is_obstacle(Cell{1, 1}));
  EXPECT_TRUE(w.is_obstacle(Cell{2, 3}));
  EXPECT_FALSE(w.is_obstacle(Cell{3, 1}));  // half-open: x0 + w excluded
  EXPECT_FALSE(w.is_obstacle(Cell{1, 4}));
  EXPECT_TRUE(w.is_obstacle(Cell{9, 7}));
  EXPECT_TRUE(w.is_obstacle(Cell{8, 6}));
  EXPECT_FALSE(w.is_obstacle(Cell{10, 7}));  // outside the map
  EXPECT_FALSE(w.is_obstacle(Cell{-1, 0}));
}

TEST(World, TargetAtGivesTheIndexInScenarioOrderOrMinusOne) {
  const MapGeometry geo(10, 8, 4, 1, 1);
  const World w(geo, {}, {Cell{3, 4}, Cell{0, 0}, Cell{20, 20}});
  EXPECT_EQ(w.target_at(Cell{3, 4}), 0);
  EXPECT_EQ(w.target_at(Cell{0, 0}), 1);
  EXPECT_EQ(w.target_at(Cell{1, 0}), -1);
  EXPECT_EQ(w.target_at(Cell{20, 20}), -1);  // off-map target is never found
  EXPECT_EQ(w.targets().size(), 3U);
}

TEST(World, DiskHoldsCellsWithinTheRadiusInRowMajorOrder) {
  const MapGeometry geo(10, 10, 5, 1, 1);
  const World w(geo, {}, {});
  const std::vector<Cell> expected{{4, 3}, {3, 4}, {4, 4}, {5, 4}, {4, 5}};
  EXPECT_EQ(w.disk(Cell{4, 4}, 1.0), expected);
  EXPECT_EQ(w.disk(Cell{4, 4}, 1.5).size(), 9U);   // the 3 x 3 block
  EXPECT_EQ(w.disk(Cell{4, 4}, 2.0).size(), 13U);  // plus (±2, 0), (0, ±2)
  EXPECT_EQ(w.disk(Cell{4, 4}, 0.0), (std::vector<Cell>{Cell{4, 4}}));
}

TEST(World, DiskIsClippedAtTheMapCorner) {
  const MapGeometry geo(10, 10, 5, 1, 1);
  const World w(geo, {}, {});
  const std::vector<Cell> expected{{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  EXPECT_EQ(w.disk(Cell{0, 0}, 1.5), expected);
  EXPECT_TRUE(w.disk(Cell{4, 4}, -1.0).empty());
}

TEST(World, SenseReportsObstacleCellsAndTargetIndicesWithinTheRadius) {
  const MapGeometry geo(10, 10, 5, 1, 1);
  const World w(geo, {Rect{5, 4, 1, 2}}, {Cell{9, 9}, Cell{3, 4}, Cell{4, 6}});
  const World::Reading r = w.sense(Cell{4, 4}, 2.0);
  EXPECT_EQ(r.obstacles, (std::vector<Cell>{{5, 4}, {5, 5}}));
  EXPECT_EQ(r.targets, (std::vector<int32_t>{1, 2}));  // in disk (row-major) order
}

TEST(World, ReachabilityFloodsThroughDiagonalGapsButNotThroughWalls) {
  // 6 x 5 map. A full wall at x = 3 seals the right side. On the left, the
  // staircase (0,3), (1,2), (2,1) separates the upper cells from (0,0) for
  // 4-connectivity; 8-connectivity passes its diagonal gaps.
  //   y=4  . . . # . .
  //   y=3  # . . # . .
  //   y=2  . # . # . .
  //   y=1  . . # # . .
  //   y=0  . . . # . .
  const MapGeometry geo(6, 5, 5, 1, 1);
  const World w(geo, {Rect{3, 0, 1, 5}, Rect{0, 3, 1, 1}, Rect{1, 2, 1, 1}, Rect{2, 1, 1, 1}}, {});
  const auto reach = w.reachable_from({Cell{0, 0}});
  ASSERT_EQ(reach.size(), 30U);
  auto at = [&](int32_t x, int32_t y) { return reach[geo.index(Cell{x, y})]; };
  EXPECT_EQ(at(0, 0), 1);
  EXPECT_EQ(at(2, 2), 1);  // through the diagonal gap between (1,2) and (2,1)
  EXPECT_EQ(at(0, 4), 1);
  EXPECT_EQ(at(0, 2), 1);
  EXPECT_EQ(at(1, 2), 0);  // obstacle
  EXPECT_EQ(at(4, 0), 0);  // behind the wall
  EXPECT_EQ(at(5, 4), 0);
  int count = 0;
  for (const auto v : reach) {
    count += v;
  }
  EXPECT_EQ(count, 15 - 3);  // x < 3 minus the three obstacle cells
}

TEST(World, StartsOnObstaclesOrOffTheMapAreIgnoredByReachability) {
  const MapGeometry geo(6, 5, 5, 1, 1);
  const World w(geo, {Rect{3, 0, 1, 5}}, {});
  const auto none = w.reachable_from({Cell{3, 2}, Cell{-1, 0}, Cell{6, 0}});
  for (const auto v : none) {
    EXPECT_EQ(v, 0);
  }
  const auto both = w.reachable_from({Cell{0, 0}, Cell{5, 4}, Cell{3, 3}});
  int count = 0;
  for (const auto v : both) {
    count += v;
  }
  EXPECT_EQ(count, 30 - 5);
}

TEST(World, KeepsItsOwnGeometryWhenBuiltFromATemporary) {
  // As `World(scenario.geometry(), ...)` does: the geometry is a temporary.
  const World w(MapGeometry(12, 9, 3, 1, 1), {{2, 2, 1, 1}}, {});
  const auto churn = [] { return MapGeometry(1, 1, 1, 1, 1); };  // reuses the stack where the temporary was
  EXPECT_EQ(churn().width(), 1);
  EXPECT_EQ(w.geometry().width(), 12);
  EXPECT_EQ(w.geometry().height(), 9);
  EXPECT_TRUE(w.is_obstacle({2, 2}));
  EXPECT_FALSE(w.is_obstacle({11, 8}));
  EXPECT_FALSE(w.is_obstacle({12, 8})) << "outside the map";
}

}  // namespace
}  // namespace pheromesh::core
