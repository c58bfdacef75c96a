// The home place agent's neighbourhood service (core/view_server.hpp).
#include <gtest/gtest.h>

#include <algorithm>

#include "pheromesh/core/view_server.hpp"
#include "unit_support.hpp"

namespace pheromesh::core {
namespace {

// 40 x 40 cells, tiles of 10, 2 x 2 regions.
MapGeometry geo() { return {40, 40, 10, 2, 2}; }

TileMsg tile(int layer, TileCoord t, uint32_t tick, float v) {
  return {static_cast<uint8_t>(layer), t, tick, 0, 10, 10, std::vector<float>(100, v)};
}

const auto uav = test::state_at;

TEST(ViewServer, AViewHoldsTheTilesWithinTheRadiusOfTheViewCellAndTheUavsOverThem) {
  const MapGeometry g = geo();
  ViewServer vs(g, 2, 3.0);
  for (int32_t tx = 0; tx < 4; ++tx) {
    for (int32_t ty = 0; ty < 4; ++ty) {
      for (int l = 0; l < 2; ++l) vs.update_tile(tile(l, {tx, ty}, 5, static_cast<float>(tx * 10 + ty)), 5);
    }
  }
  vs.update_state(uav(1, 5, 11, 11));  // view cell (11,11): radius 3 reaches tiles (0..1, 0..1)
  vs.update_state(uav(2, 5, 8, 8));    // over tile (0,0): a neighbour
  vs.update_state(uav(3, 5, 35, 35));  // over tile (3,3): far away
  ViewMsg v;
  ASSERT_TRUE(vs.compose(1, 5, 0, 5, v));
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
  EXPECT_FALSE(vs.compose(9, 5, 0, 5, v)) << "no state of UAV 9 is known";
}

TEST(ViewServer, APolicyThatReadsNoNeighboursGetsViewsOfTilesOnly) {
  // PolicyTraits::reads_neighbours false: the same view as above, without UAV 2.
  ViewServer vs(geo(), 1, 3.0, false);
  for (int32_t tx = 0; tx < 2; ++tx) {
    for (int32_t ty = 0; ty < 2; ++ty) vs.update_tile(tile(0, {tx, ty}, 5, 1.0F), 5);
  }
  vs.update_state(uav(1, 5, 11, 11));
  vs.update_state(uav(2, 5, 8, 8));
  ViewMsg v;
  v.uavs.push_back(uav(7, 4, 1, 1));  // what a reused message held is gone too
  ASSERT_TRUE(vs.compose(1, 5, 0, 5, v));
  EXPECT_EQ(v.tiles.size(), 4U);
  EXPECT_TRUE(v.uavs.empty());
  // UAV 2's own view is composed as well: it is served, only not shown.
  ASSERT_TRUE(vs.compose(2, 5, 0, 5, v));
  EXPECT_TRUE(v.uavs.empty());
}

TEST(ViewServer, AViewCrowdedPastTheIdlBoundKeepsTheNearestNeighboursInIdOrder) {
  ViewServer vs(geo(), 1, 3.0);
  vs.update_state(uav(1, 5, 5.0, 5.0));
  // 1100 neighbours over tile (0,0): UAV 2+k at distance 0.001 k from UAV 1,
  // all but the 76 farthest (ids 1026..1101) kept.
  for (uint32_t k = 0; k < 1100; ++k) vs.update_state(uav(2 + k, 5, 5.0 + 0.001 * k, 5.0));
  ViewMsg v;
  ASSERT_TRUE(vs.compose(1, 5, 0, 0, v));
  ASSERT_EQ(v.uavs.size(), kMaxViewUavs);
  EXPECT_EQ(v.uavs.front().uav, 2U);
  EXPECT_EQ(v.uavs.back().uav, 2U + kMaxViewUavs - 1);
  EXPECT_TRUE(std::is_sorted(v.uavs.begin(), v.uavs.end(), [](const auto& a, const auto& b) { return a.uav < b.uav; }));
}

TEST(ViewServer, NeighboursFollowTheirNewestStateAndOldOrFinishedOnesAreLeftOut) {
  ViewServer vs(geo(), 1, 3.0);
  vs.update_state(uav(1, 10, 5, 5));
  vs.update_state(uav(2, 9, 6, 6));
  ViewMsg v;
  ASSERT_TRUE(vs.compose(1, 10, 0, 0, v));
  EXPECT_TRUE(v.uavs.empty()) << "UAV 2's state is a tick older than UAV 1's and max_age is 0";
  ASSERT_TRUE(vs.compose(1, 10, 1, 0, v));
  EXPECT_EQ(v.uavs.size(), 1U);
  // UAV 2 moves away (its newer state), then an older state arrives late: ignored.
  vs.update_state(uav(2, 10, 35, 35));
  vs.update_state(uav(2, 8, 6, 6));
  ASSERT_TRUE(vs.compose(1, 10, 4, 0, v));
  EXPECT_TRUE(v.uavs.empty());
  EXPECT_EQ(vs.state(2)->tick, 10U);
  // A finished UAV is not a neighbour.
  UavStateMsg done = uav(3, 10, 4, 4);
  done.finished = true;
  vs.update_state(done);
  ASSERT_TRUE(vs.compose(1, 10, 4, 0, v));
  EXPECT_TRUE(v.uavs.empty());
}

TEST(ViewServer, TilesAndServedStatesOfATickAreHeldOnlyWhenEveryChunkOfEveryRegionArrived) {
  ViewServer vs(geo(), 1, 3.0);
  const std::vector<RegionId> regions{1, 2};
  std::vector<TileMsg> many;
  for (int i = 0; i < 300; ++i) many.push_back(tile(0, {0, 0}, 4, 1.0F));  // more than one chunk holds
  const auto chunks = make_field_chunks(1, 4, many, {});
  ASSERT_EQ(chunks.size(), 2U);
  EXPECT_EQ(chunks[0].tiles.size(), kMaxFieldTiles);
  EXPECT_EQ(chunks[1].tiles.size(), 300U - kMaxFieldTiles);
  vs.update_tiles(chunks[0], 4);
  for (const auto& f : make_field_chunks(2, 4, many, {})) vs.update_tiles(f, 4);
  EXPECT_FALSE(vs.holds_tiles(4, regions)) << "chunk 1 of region 1 is missing";
  EXPECT_EQ(vs.missing_tiles(4, regions), "region 1: tick 4, 1 of 2 chunks");
  vs.update_tiles(chunks[1], 4);
  EXPECT_TRUE(vs.holds_tiles(4, regions));
  EXPECT_EQ(vs.missing_tiles(4, regions), "");
  EXPECT_FALSE(vs.holds_tiles(5, regions));
  EXPECT_EQ(vs.missing_tiles(5, std::vector<RegionId>{2, 9}), "region 2: tick 4, 2 of 2 chunks; region 9: none");
  // Served states are counted apart from tiles; an empty region still sends one chunk.
  EXPECT_FALSE(vs.holds_served(4, regions));
  for (const auto& f : make_field_chunks(2, 4, {}, {uav(7, 4, 30, 30)})) vs.update_served(f);
  vs.update_served(make_field_chunks(1, 4, {}, {}).at(0));
  EXPECT_TRUE(vs.holds_served(4, regions));
  ASSERT_NE(vs.state(7), nullptr) << "a served chunk carries the states";
  EXPECT_EQ(vs.served_by(2), std::vector<uint32_t>{7});
  EXPECT_TRUE(vs.served_by(1).empty());
}

TEST(ViewServer, AServedListIsReplacedOnlyOnceEveryChunkOfANewerTickArrived) {
  ViewServer vs(geo(), 1, 3.0);
  std::vector<UavStateMsg> states;
  for (uint32_t u = 0; u < kMaxFieldUavs + 1; ++u) states.push_back(uav(u, 6, 5, 5));
  for (const auto& f : make_field_chunks(3, 5, {}, {uav(1, 5, 5, 5)})) vs.update_served(f);
  const auto chunks = make_field_chunks(3, 6, {}, states);
  ASSERT_EQ(chunks.size(), 2U);
  vs.update_served(chunks[1]);
  EXPECT_EQ(vs.served_by(3), std::vector<uint32_t>{1}) << "tick 6 is not complete: tick 5's list stands";
  vs.update_served(chunks[1]);  // a copy (re-sent) counts once
  vs.update_served(chunks[0]);
  EXPECT_EQ(vs.served_by(3).size(), kMaxFieldUavs + 1);
  vs.update_served(make_field_chunks(3, 5, {}, {}).at(0));  // older: ignored
  EXPECT_EQ(vs.served_by(3).size(), kMaxFieldUavs + 1);
}

TEST(ViewServer, APlaceClocksServedListIsEveryRegionsServedUavsAndDropsWhatIsMalformed) {
  // Lockstep: the place clock lists every served UAV with its gateway
  // (ClockMsg::served) instead of each region's chunk.
  ViewServer vs(geo(), 1, 3.0);
  const std::vector<RegionId> others{1, 2};
  std::vector<ServedUav> served{
      {4, 1, 12.5, 3.5, 1.0, 0.0, 2, 0, {12, 3}},
      {5, 0, 2.5, 2.5, 0.0, 0.0, 0, 0, {2, 2}},  // this place agent's own region: not taken
      {6, 1, 15.5, 8.5, 0.0, 1.0, 4, 2, {15, 8}, 30},
      {50, 1, 5.5, 5.5, 0.0, 0.0, 0, 0, {5, 5}},   // not a UAV of the swarm of 10
      {7, 1, 400.5, 5.5, 0.0, 0.0, 0, 0, {5, 5}},  // off the map
      {8, 9, 5.5, 5.5, 0.0, 0.0, 0, 0, {5, 5}},    // a region not asked for
  };
  std::vector<std::string> malformed;
  EXPECT_FALSE(vs.holds_served(7, others));
  vs.update_served(served, 7, others, 10, malformed);
  EXPECT_TRUE(vs.holds_served(7, others)) << "region 2 serves nobody: its (empty) list is complete too";
  EXPECT_EQ(vs.served_by(1), (std::vector<uint32_t>{4, 6}));
  EXPECT_TRUE(vs.served_by(2).empty());
  ASSERT_EQ(malformed.size(), 2U);
  EXPECT_NE(malformed[0].find("uav 50"), std::string::npos) << malformed[0];
  EXPECT_NE(malformed[1].find("uav 7"), std::string::npos) << malformed[1];
  EXPECT_EQ(vs.state(5), nullptr);
  EXPECT_EQ(vs.state(8), nullptr);
  // The state a neighbour is shown with: its pose of the tick.
  const UavStateMsg* s = vs.state(6);
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->tick, 7U);
  EXPECT_DOUBLE_EQ(s->x, 15.5);
  EXPECT_DOUBLE_EQ(s->vy, 1.0);
  EXPECT_EQ(s->heading, 4U);
  EXPECT_EQ(s->role, 2U);
  EXPECT_EQ(s->view, (Cell{15, 8}));
  EXPECT_EQ(s->deposits_sent, 30U) << "where a backup that adopts it counts its deposits from";
  EXPECT_EQ(vs.needed_tiles(vs.served_by(1)), (std::vector<TileCoord>{{0, 0}, {1, 0}, {1, 1}}));
}

TEST(ViewServer, ARegionNotHeardOfSinceAGivenTickServesNobody) {
  // Realtime: the owners stop sending tiles to a place agent that died (its
  // last served list would otherwise stand for ever).
  ViewServer vs(geo(), 1, 3.0);
  for (const auto& f : make_field_chunks(3, 40, {}, {uav(1, 40, 5, 5)})) vs.update_served(f, /*arrived=*/12);
  EXPECT_EQ(vs.served_by(3, 12), std::vector<uint32_t>{1});
  EXPECT_EQ(vs.served_by(3, 2), std::vector<uint32_t>{1});
  EXPECT_TRUE(vs.served_by(3, 13).empty()) << "nothing of region 3 arrived at tick 13 or later";
  vs.update_served(make_field_chunks(3, 40, {}, {uav(1, 40, 5, 5)}).at(0), 20);  // a re-sent copy: not news
  EXPECT_TRUE(vs.served_by(3, 13).empty());
  for (const auto& f : make_field_chunks(3, 41, {}, {uav(1, 41, 6, 5)})) vs.update_served(f, 21);
  EXPECT_EQ(vs.served_by(3, 13), std::vector<uint32_t>{1}) << "heard again at tick 21";
}

TEST(ViewServer, NeededTilesAreTheUnionOfTheServedUavsNeighbourhoods) {
  // 40 x 40 cells, tiles of 10, radius 3: a view cell at (11,11) needs tiles
  // (0..1, 0..1); one at (35,4) tile (3, 0); a margin of 2 cells at (35,4)
  // reaches x = 30..39, y = 0..9: still (3, 0); at (33,4) it reaches x = 28
  // and so also (2, 0).
  ViewServer vs(geo(), 1, 3.0);
  vs.update_state(uav(1, 2, 11, 11));
  vs.update_state(uav(2, 2, 35, 4));
  vs.update_state(uav(3, 2, 33, 4));
  const std::vector<uint32_t> a{1, 2, 9};  // 9: unknown, adds nothing
  const std::vector<TileCoord> want{{0, 0}, {0, 1}, {1, 0}, {1, 1}, {3, 0}};
  EXPECT_EQ(vs.needed_tiles(a), want);
  const std::vector<uint32_t> b{2};
  EXPECT_EQ(vs.needed_tiles(b, 2), (std::vector<TileCoord>{{3, 0}}));
  const std::vector<uint32_t> c{3};
  EXPECT_EQ(vs.needed_tiles(c, 0), (std::vector<TileCoord>{{3, 0}}));
  EXPECT_EQ(vs.needed_tiles(c, 2), (std::vector<TileCoord>{{2, 0}, {3, 0}}));
}

TEST(ViewServer, AViewComposedIntoAReusedMessageHoldsExactlyItsOwnTiles) {
  // compose overwrites the tiles a reused message held in place: a smaller
  // view after a larger one keeps none of the larger one's, and the values
  // are this view's.
  ViewServer vs(geo(), 1, 3.0);
  for (int32_t tx = 0; tx < 4; ++tx) {
    for (int32_t ty = 0; ty < 4; ++ty) vs.update_tile(tile(0, {tx, ty}, 5, static_cast<float>(tx * 10 + ty)), 5);
  }
  vs.update_state(uav(1, 5, 11, 11));  // tiles (0..1, 0..1)
  vs.update_state(uav(2, 5, 35, 35));  // tile (3, 3) only
  ViewMsg v;
  ASSERT_TRUE(vs.compose(1, 5, 0, 5, v));
  ASSERT_EQ(v.tiles.size(), 4U);
  ASSERT_TRUE(vs.compose(2, 5, 0, 5, v));
  ASSERT_EQ(v.tiles.size(), 1U);
  EXPECT_EQ(v.tiles[0].tile, (TileCoord{3, 3}));
  EXPECT_EQ(v.tiles[0].values, std::vector<float>(100, 33.0F));
  ASSERT_TRUE(vs.compose(1, 5, 0, 5, v));
  ASSERT_EQ(v.tiles.size(), 4U);
  EXPECT_EQ(v.tiles[3].tile, (TileCoord{1, 1}));
  EXPECT_EQ(v.tiles[3].values, std::vector<float>(100, 11.0F));
}

TEST(ViewServer, TheTileJoinFollowsTheNeededTilesWhateverTheOrderOfTheOwnersTiles) {
  // The owner's tiles in any order: what goes to a home is in the order of
  // needed_tiles, each tile's layers in their order among the owner's.
  ViewServer vs(geo(), 2, 3.0);
  FieldMsg served;
  served.region = 0;
  served.tick = 5;
  served.uavs.push_back(uav(1, 5, 11, 11));  // tiles (0..1, 0..1)
  vs.update_served(served, 5);
  std::vector<TileMsg> own;
  for (const TileCoord t : {TileCoord{1, 1}, TileCoord{3, 3}, TileCoord{0, 1}, TileCoord{1, 0}, TileCoord{0, 0}}) {
    own.push_back(tile(1, t, 5, 1.0F));
    own.push_back(tile(0, t, 5, 0.0F));
  }
  std::vector<TileMsg> out;
  vs.tiles_for(0, 0, 0, own, out);
  ASSERT_EQ(out.size(), 8U) << "four tiles, two layers each, not (3,3)";
  const std::vector<TileCoord> order{{0, 0}, {0, 1}, {1, 0}, {1, 1}};
  for (std::size_t i = 0; i < out.size(); ++i) {
    EXPECT_EQ(out[i].tile, order[i / 2]) << i;
    EXPECT_EQ(out[i].layer, i % 2 == 0 ? 1 : 0) << i << ": layer 1 came first among the owner's";
  }
}

TEST(ViewServer, ATileThatStoppedArrivingIsLeftOutOfViews) {
  // A dead owner sends nothing: its last tiles are not shown (dark, not frozen).
  ViewServer vs(geo(), 1, 3.0);
  vs.update_state(uav(1, 7, 11, 11));
  vs.update_tile(tile(0, {0, 0}, 7, 1.0F), 7);
  vs.update_tile(tile(0, {1, 1}, 3, 2.0F), 3);  // arrived at tick 3, not since
  ViewMsg v;
  ASSERT_TRUE(vs.compose(1, 7, 0, 7, v));
  ASSERT_EQ(v.tiles.size(), 1U);
  EXPECT_EQ(v.tiles[0].tile, (TileCoord{0, 0}));
  ASSERT_TRUE(vs.compose(1, 7, 0, 3, v));
  EXPECT_EQ(v.tiles.size(), 2U);
  // A newer tile replaces the older and carries its own arrival.
  vs.update_tile(tile(0, {1, 1}, 7, 3.0F), 7);
  ASSERT_TRUE(vs.compose(1, 7, 0, 7, v));
  EXPECT_EQ(v.tiles.size(), 2U);
}

}  // namespace
}  // namespace pheromesh::core
