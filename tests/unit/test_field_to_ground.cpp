// core::FieldToGround: what of its field a place agent sends the ground
// station, and when (core/field_to_ground.hpp).
#include <gtest/gtest.h>

#include <vector>

#include "pheromesh/core/field_to_ground.hpp"

namespace pheromesh::core {
namespace {

TileMsg tile(int32_t tx, uint8_t layer, float v) {
  TileMsg t;
  t.tile = {tx, 0};
  t.layer = layer;
  t.width = 1;
  t.height = 1;
  t.values = {v};
  return t;
}

TEST(FieldToGround, LockstepSendsEveryTileEveryTick) {
  FieldToGround g;
  const std::vector<TileMsg> all{tile(0, 0, 1.0F), tile(1, 0, 0.0F)};
  for (uint32_t tick = 0; tick < 5; ++tick) {
    ASSERT_TRUE(g.due(tick, false));
    std::vector<TileMsg> out;
    g.select(all, false, out);
    EXPECT_EQ(out.size(), 2U) << "tick " << tick << ": unchanged tiles too";
  }
}

TEST(FieldToGround, RealtimeSendsAtTheConsoleRateAndAFullFieldEveryTwoSeconds) {
  // 20 Hz ticks, a 5 Hz console: every 4th tick; 5 sends a second, so every
  // 10th send is full.
  FieldToGround g = FieldToGround::at_rate(20.0, 5.0);
  EXPECT_EQ(g.every(), 4U);
  EXPECT_TRUE(g.due(0, false));
  EXPECT_FALSE(g.due(1, false));
  EXPECT_FALSE(g.due(3, false));
  EXPECT_TRUE(g.due(4, false));
  EXPECT_TRUE(g.due(7, true)) << "the last tick always goes out";

  std::vector<TileMsg> all{tile(0, 0, 1.0F), tile(1, 0, 0.0F), tile(1, 1, 2.0F)};
  std::vector<TileMsg> out;
  g.select(all, false, out);
  EXPECT_EQ(out.size(), 3U) << "the first send is full";
  all[0].values = {0.5F};  // evaporated; the other two did not change
  out.clear();
  g.select(all, false, out);
  ASSERT_EQ(out.size(), 1U);
  EXPECT_EQ(out[0].tile.tx, 0);
  EXPECT_EQ(out[0].values, std::vector<float>{0.5F});
  for (int send = 2; send < 10; ++send) {
    out.clear();
    g.select(all, false, out);
    EXPECT_TRUE(out.empty()) << "send " << send << ": nothing changed";
  }
  out.clear();
  g.select(all, false, out);
  EXPECT_EQ(out.size(), 3U) << "the 11th send (2 s later) is full again";
  out.clear();
  g.select(all, /*last=*/true, out);
  EXPECT_EQ(out.size(), 3U) << "the last tick is full";
}

TEST(FieldToGround, ATickRateBelowTheConsoleRateSendsEveryTick) {
  const FieldToGround g = FieldToGround::at_rate(2.0, 5.0);
  EXPECT_EQ(g.every(), 1U);
  EXPECT_TRUE(g.due(1, false));
}

}  // namespace
}  // namespace pheromesh::core
