// The home place agent's neighbourhood service (core/view_server.hpp).
#include <gtest/gtest.h>

#include <algorithm>

#include "pheromesh/core/view_server.hpp"

namespace pheromesh::core {
namespace {

// 40 x 40 cells, tiles of 10, 2 x 2 regions.
MapGeometry geo() { return {40, 40, 10, 2, 2}; }

TileMsg tile(int layer, TileCoord t, uint32_t tick, float v) {
  return {static_cast<uint8_t>(layer), t, tick, 0, 10, 10, std::vector<float>(100, v)};
}

UavStateMsg uav(uint32_t id, uint32_t tick, double x, double y) {
  UavStateMsg s;
  s.uav = id;
  s.tick = tick;
  s.x = x;
  s.y = y;
  s.view = {static_cast<int32_t>(x), static_cast<int32_t>(y)};
  return s;
}

TEST(ViewServer, AViewHoldsTheTilesWithinTheRadiusOfTheViewCellAndTheUavsOverThem) {
  const MapGeometry g = geo();
  ViewServer vs(g, 2, 3.0);
  for (int32_t tx = 0; tx < 4; ++tx) {
    for (int32_t ty = 0; ty < 4; ++ty) {
      for (int l = 0; l < 2; ++l) vs.update_tile(tile(l, {tx, ty}, 5, static_cast<float>(tx * 10 + ty)));
    }
  }
  vs.update_state(uav(1, 5, 11, 11));  // view cell (11,11): radius 3 reaches tiles (0..1, 0..1)
  vs.update_state(uav(2, 5, 8, 8));    // over tile (0,0): a neighbour
  vs.update_state(uav(3, 5, 35, 35));  // over tile (3,3): far away
  ViewMsg v;
  ASSERT_TRUE(vs.compose(1, 5, 0, v));
  EXPECT_EQ(v.uav, 1U);
  EXPECT_EQ(v.tick, 5U);
  // 2 x 2 tiles x 2 layers, as UavCore's neighbourhood of (11,11) with radius 3.
  ASSERT_EQ(v.tiles.size(), 8U);
  EXPECT_EQ(vs.neighbourhood({11, 11}), g.tiles_within({11, 11}, 3));
  for (const auto& t : v.tiles) {
    EXPECT_LE(t.tile.tx, 1);
    EXPECT_LE(t.tile.ty, 1);
    EXPECT_EQ(t.values[0], static_cast<float>(t.tile.tx * 10 + t.tile.ty));
  }
  ASSERT_EQ(v.uavs.size(), 1U);  // not itself, not UAV 3
  EXPECT_EQ(v.uavs[0].uav, 2U);
  EXPECT_FALSE(vs.compose(9, 5, 0, v)) << "no state of UAV 9 is known";
}

TEST(ViewServer, NeighboursFollowTheirNewestStateAndOldOrFinishedOnesAreLeftOut) {
  ViewServer vs(geo(), 1, 3.0);
  vs.update_state(uav(1, 10, 5, 5));
  vs.update_state(uav(2, 9, 6, 6));
  ViewMsg v;
  ASSERT_TRUE(vs.compose(1, 10, 0, v));
  EXPECT_TRUE(v.uavs.empty()) << "UAV 2's state is a tick older than UAV 1's and max_age is 0";
  ASSERT_TRUE(vs.compose(1, 10, 1, v));
  EXPECT_EQ(v.uavs.size(), 1U);
  // UAV 2 moves away (its newer state), then an older state arrives late: ignored.
  vs.update_state(uav(2, 10, 35, 35));
  vs.update_state(uav(2, 8, 6, 6));
  ASSERT_TRUE(vs.compose(1, 10, 4, v));
  EXPECT_TRUE(v.uavs.empty());
  EXPECT_EQ(vs.state(2)->tick, 10U);
  // A finished UAV is not a neighbour.
  UavStateMsg done = uav(3, 10, 4, 4);
  done.finished = true;
  vs.update_state(done);
  ASSERT_TRUE(vs.compose(1, 10, 4, v));
  EXPECT_TRUE(v.uavs.empty());
}

TEST(ViewServer, FieldsOfATickAreHeldOnlyWhenEveryChunkOfEveryRegionArrived) {
  ViewServer vs(geo(), 1, 3.0);
  const std::vector<RegionId> regions{1, 2};
  std::vector<TileMsg> many;
  for (int i = 0; i < 300; ++i) many.push_back(tile(0, {0, 0}, 4, 1.0F));  // more than one chunk holds
  const auto chunks = make_field_chunks(1, 4, many, {});
  ASSERT_EQ(chunks.size(), 2U);
  EXPECT_EQ(chunks[0].tiles.size(), kMaxFieldTiles);
  EXPECT_EQ(chunks[1].tiles.size(), 300U - kMaxFieldTiles);
  vs.update_field(chunks[0]);
  for (const auto& f : make_field_chunks(2, 4, {}, {uav(7, 4, 30, 30)})) vs.update_field(f);
  EXPECT_FALSE(vs.holds_fields(4, regions)) << "chunk 1 of region 1 is missing";
  EXPECT_EQ(vs.missing_fields(4, regions), "region 1: tick 4, 1 of 2 chunks");
  vs.update_field(chunks[1]);
  EXPECT_TRUE(vs.holds_fields(4, regions));
  EXPECT_EQ(vs.missing_fields(4, regions), "");
  EXPECT_FALSE(vs.holds_fields(5, regions));
  EXPECT_EQ(vs.missing_fields(5, std::vector<RegionId>{2, 9}), "region 2: tick 4, 1 of 1 chunks; region 9: none");
  ASSERT_NE(vs.state(7), nullptr) << "a field carries its home UAVs' states";
  // An empty region still sends one chunk.
  EXPECT_EQ(make_field_chunks(3, 1, {}, {}).size(), 1U);
}

}  // namespace
}  // namespace pheromesh::core
