// MapGeometry: tiles, regions and neighbour counts, with hand-worked numbers.
#include <gtest/gtest.h>

#include <vector>

#include "pheromesh/core/grid.hpp"

namespace pheromesh::core {
namespace {

// 50 x 50 cells, tile 10 -> 5 x 5 tiles. 2 x 2 regions: region column rx
// starts at tile rx*5/2, i.e. tiles 0, 2, 5 -> columns [0,2) and [2,5), so the
// split is 2 + 3 tiles = cells [0,20) and [20,50). Same for rows.
MapGeometry fifty() { return {50, 50, 10, 2, 2}; }

TEST(Grid, TileCountsRoundUp) {
  const MapGeometry g = fifty();
  EXPECT_EQ(g.tiles_x(), 5);
  EXPECT_EQ(g.tiles_y(), 5);
  EXPECT_EQ(g.region_count(), 4U);
  // 23 x 17, tile 5: ceil(23/5) = 5, ceil(17/5) = 4.
  const MapGeometry odd(23, 17, 5, 2, 2);
  EXPECT_EQ(odd.tiles_x(), 5);
  EXPECT_EQ(odd.tiles_y(), 4);
}

TEST(Grid, TileOfCellDividesByTileSize) {
  const MapGeometry g = fifty();
  EXPECT_EQ(g.tile_of({0, 0}), (TileCoord{0, 0}));
  EXPECT_EQ(g.tile_of({19, 19}), (TileCoord{1, 1}));  // 19/10 = 1
  EXPECT_EQ(g.tile_of({20, 0}), (TileCoord{2, 0}));
  EXPECT_EQ(g.tile_of({49, 35}), (TileCoord{4, 3}));
}

TEST(Grid, TileRectIsTileSizedOnMultipleMap) {
  const MapGeometry g = fifty();
  EXPECT_EQ(g.tile_rect({0, 0}), (Rect{0, 0, 10, 10}));
  EXPECT_EQ(g.tile_rect({4, 4}), (Rect{40, 40, 10, 10}));
  EXPECT_EQ(g.tile_rect({5, 0}), Rect{});  // not a tile
}

TEST(Grid, RegionsSplitTilesTwoPlusThree) {
  const MapGeometry g = fifty();
  EXPECT_EQ(g.region_rect(0), (Rect{0, 0, 20, 20}));
  EXPECT_EQ(g.region_rect(1), (Rect{20, 0, 30, 20}));
  EXPECT_EQ(g.region_rect(2), (Rect{0, 20, 20, 30}));
  EXPECT_EQ(g.region_rect(3), (Rect{20, 20, 30, 30}));
  EXPECT_EQ(g.region_of({19, 19}), 0U);
  EXPECT_EQ(g.region_of({20, 19}), 1U);
  EXPECT_EQ(g.region_of({19, 25}), 2U);  // tile (1,2): rx 0, ry 1 -> 1*2 + 0
  EXPECT_EQ(g.region_of({49, 49}), 3U);
  const std::vector<TileCoord> tiles3 = g.region_tiles(3);
  ASSERT_EQ(tiles3.size(), 9U);  // tiles 2..4 x 2..4
  EXPECT_EQ(tiles3.front(), (TileCoord{2, 2}));
  EXPECT_EQ(tiles3[1], (TileCoord{3, 2}));  // row-major
  EXPECT_EQ(tiles3.back(), (TileCoord{4, 4}));
}

TEST(Grid, NonMultipleMapClipsLastTilesAndRegions) {
  // 23 x 17, tile 5: tiles 5 x 4; last tile column is 23-20 = 3 wide, last
  // tile row 17-15 = 2 high. Regions 2 x 2: tile columns [0,2) [2,5) -> cells
  // [0,10) [10,23); tile rows [0,2) [2,4) -> cells [0,10) [10,17).
  const MapGeometry g(23, 17, 5, 2, 2);
  EXPECT_EQ(g.tile_rect({4, 3}), (Rect{20, 15, 3, 2}));
  EXPECT_EQ(g.tile_rect({4, 0}), (Rect{20, 0, 3, 5}));
  EXPECT_EQ(g.tile_rect({0, 3}), (Rect{0, 15, 5, 2}));
  EXPECT_EQ(g.region_rect(0), (Rect{0, 0, 10, 10}));
  EXPECT_EQ(g.region_rect(3), (Rect{10, 10, 13, 7}));
  EXPECT_EQ(g.region_of({22, 16}), 3U);
}

TEST(Grid, EveryCellLiesInExactlyTheRectOfItsRegion) {
  // 37 x 29, tile 5 -> 8 x 6 tiles; 3 x 2 regions split tiles 2+3+3 and 3+3.
  for (const MapGeometry& g : {MapGeometry(37, 29, 5, 3, 2), MapGeometry(23, 17, 5, 2, 2), MapGeometry(50, 50, 10, 2, 2),
                               MapGeometry(31, 7, 3, 4, 1), MapGeometry(10, 10, 10, 1, 1)}) {
    int64_t covered = 0;
    for (RegionId r = 0; r < g.region_count(); ++r) covered += g.region_rect(r).area();
    EXPECT_EQ(covered, g.map_rect().area());
    for (int32_t y = 0; y < g.height(); ++y) {
      for (int32_t x = 0; x < g.width(); ++x) {
        const RegionId r = g.region_of({x, y});
        ASSERT_LT(r, g.region_count());
        ASSERT_TRUE(g.region_rect(r).contains({x, y})) << x << "," << y;
      }
    }
  }
  const MapGeometry g(37, 29, 5, 3, 2);
  EXPECT_EQ(g.region_rect(0), (Rect{0, 0, 10, 15}));    // tiles x [0,8/3=2), y [0,3)
  EXPECT_EQ(g.region_rect(1), (Rect{10, 0, 15, 15}));   // tiles x [2,16/3=5)
  EXPECT_EQ(g.region_rect(5), (Rect{25, 15, 12, 14}));  // tiles x [5,8) -> [25,37), y [3,6) -> [15,29)
}

TEST(Grid, NeighbourCountIsThreeAtCornersFiveOnBordersEightInside) {
  const MapGeometry g = fifty();
  EXPECT_EQ(g.neighbour_count({0, 0}), 3);
  EXPECT_EQ(g.neighbour_count({49, 0}), 3);
  EXPECT_EQ(g.neighbour_count({49, 49}), 3);
  EXPECT_EQ(g.neighbour_count({0, 10}), 5);
  EXPECT_EQ(g.neighbour_count({25, 49}), 5);
  EXPECT_EQ(g.neighbour_count({25, 25}), 8);
  EXPECT_EQ(g.neighbour_count({19, 20}), 8);  // a region border is not a map border
}

TEST(Grid, RegionsWithinRadiusNearRegionCorner) {
  // c = (18,18) in region 0. Nearest cells of region 1: (20,18), distance 2;
  // of region 2: (18,20), distance 2; of region 3: (20,20), distance
  // sqrt(2^2 + 2^2) = 2.828...
  const MapGeometry g = fifty();
  EXPECT_EQ(g.regions_within({18, 18}, 1.0), (std::vector<RegionId>{0}));
  EXPECT_EQ(g.regions_within({18, 18}, 2.0), (std::vector<RegionId>{0, 1, 2}));
  EXPECT_EQ(g.regions_within({18, 18}, 2.8), (std::vector<RegionId>{0, 1, 2}));
  EXPECT_EQ(g.regions_within({18, 18}, 2.83), (std::vector<RegionId>{0, 1, 2, 3}));
  EXPECT_EQ(g.regions_within({21, 21}, 0.0), (std::vector<RegionId>{3}));
  EXPECT_EQ(g.regions_within({49, 0}, 4.0), (std::vector<RegionId>{1}));
}

TEST(Grid, TilesWithinAreClippedToTheMapInRowMajorOrder) {
  const MapGeometry g = fifty();
  // c = (3,45), r = 8: x in [-5,11] -> [0,11] -> tiles 0..1;
  // y in [37,53] -> [37,49] -> tiles 3..4.
  EXPECT_EQ(g.tiles_within({3, 45}, 8),
            (std::vector<TileCoord>{{0, 3}, {1, 3}, {0, 4}, {1, 4}}));
  EXPECT_EQ(g.tiles_within({15, 15}, 0), (std::vector<TileCoord>{{1, 1}}));
  // r = 4 around (10,10): [6,14] -> tiles 0..1 in both axes.
  EXPECT_EQ(g.tiles_within({10, 10}, 4), (std::vector<TileCoord>{{0, 0}, {1, 0}, {0, 1}, {1, 1}}));
  EXPECT_EQ(g.tiles_within({10, 10}, 1000).size(), 25U);
  EXPECT_TRUE(g.tiles_within({10, 10}, -1).empty());
}

TEST(Grid, NeighbourRegionsAreTheSortedEightNeighbourhood) {
  const MapGeometry g(37, 29, 5, 3, 2);  // region ids: row 0 = 0 1 2, row 1 = 3 4 5
  EXPECT_EQ(g.neighbour_regions(0), (std::vector<RegionId>{1, 3, 4}));
  EXPECT_EQ(g.neighbour_regions(4), (std::vector<RegionId>{0, 1, 2, 3, 5}));
  EXPECT_EQ(g.neighbour_regions(2), (std::vector<RegionId>{1, 4, 5}));
  const MapGeometry single(10, 10, 5, 1, 1);
  EXPECT_TRUE(single.neighbour_regions(0).empty());
}

}  // namespace
}  // namespace pheromesh::core
