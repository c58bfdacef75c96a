// Run metrics: coverage of reachable cells and first target acquisitions.
#include <gtest/gtest.h>

#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/metrics.hpp"
#include "pheromesh/core/world.hpp"

namespace pheromesh::core {
namespace {

TEST(Coverage, CountsOnlyReachableCellsWithinTheSensorRadius) {
  // 6 x 5 map, wall at x = 3: 15 reachable cells left of the wall from (0,0).
  const MapGeometry geo(6, 5, 5, 1, 1);
  const World w(geo, {Rect{3, 0, 1, 5}}, {});
  CoverageTracker t(w, {Cell{0, 0}}, 1.5);
  EXPECT_EQ(t.reachable_cells(), 15);
  EXPECT_EQ(t.covered_cells(), 0);
  EXPECT_DOUBLE_EQ(t.coverage(), 0.0);

  // At (2,2) the 3 x 3 block covers x = 1..3, y = 1..3; x = 3 is the wall.
  t.observe(Cell{2, 2});
  EXPECT_EQ(t.covered_cells(), 6);
  EXPECT_DOUBLE_EQ(t.coverage(), 6.0 / 15.0);

  // Cells are counted once.
  t.observe(Cell{2, 2});
  EXPECT_EQ(t.covered_cells(), 6);

  // Standing on the wall covers the right side, which is not reachable.
  t.observe(Cell{4, 2});
  EXPECT_EQ(t.covered_cells(), 6);
}

TEST(Coverage, ObservationsAtTheMapBorderAreClipped) {
  const MapGeometry geo(4, 4, 4, 1, 1);
  const World w(geo, {}, {});
  CoverageTracker t(w, {Cell{0, 0}}, 1.0);
  t.observe(Cell{0, 0});  // (0,0), (1,0), (0,1)
  EXPECT_EQ(t.covered_cells(), 3);
  t.observe(Cell{-5, -5});  // nothing in the map
  EXPECT_EQ(t.covered_cells(), 3);
  for (int32_t y = 0; y < 4; ++y) {
    for (int32_t x = 0; x < 4; ++x) {
      t.observe(Cell{x, y});
    }
  }
  EXPECT_DOUBLE_EQ(t.coverage(), 1.0);
}

TEST(Coverage, IsZeroWhenNothingIsReachable) {
  const MapGeometry geo(4, 4, 4, 1, 1);
  const World w(geo, {Rect{0, 0, 4, 4}}, {});
  CoverageTracker t(w, {Cell{1, 1}}, 2.0);
  t.observe(Cell{1, 1});
  EXPECT_EQ(t.reachable_cells(), 0);
  EXPECT_DOUBLE_EQ(t.coverage(), 0.0);
}

TEST(Acquisition, ATargetIsFoundOnceAtTheEarliestTickAnyDetectionNamesWhateverTheOrderTheyArrive) {
  AcquisitionTracker a(3);
  EXPECT_TRUE(a.acquire(1, 40));
  EXPECT_FALSE(a.acquire(1, 50)) << "found already";
  EXPECT_EQ(a.first(1), 40U);
  // A detection of tick 10 that arrives late (another writer's, or history
  // delivered after newer samples): still the same target, found at 10.
  EXPECT_FALSE(a.acquire(1, 10));
  EXPECT_EQ(a.first(1), 10U);
  EXPECT_TRUE(a.acquire(0, 25));
  EXPECT_EQ(a.found(), 2U);
  EXPECT_EQ(a.acquisition_ticks(), (std::vector<uint32_t>{10, 25}));
}

TEST(Acquisition, OutOfRangeTargetIndicesAreIgnored) {
  AcquisitionTracker a(2);
  EXPECT_FALSE(a.acquire(-1, 1));
  EXPECT_FALSE(a.acquire(2, 1));
  EXPECT_FALSE(a.acquire(1000000, 1));
  EXPECT_EQ(a.found(), 0U);
  EXPECT_TRUE(a.acquisition_ticks().empty());
}

}  // namespace
}  // namespace pheromesh::core
