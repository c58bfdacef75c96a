// bus::TickSlots: what a lockstep process remembers of one tick, in storage
// that outlives the tick (bus/resend.hpp).
#include <gtest/gtest.h>

#include <vector>

#include "pheromesh/bus/resend.hpp"

namespace pheromesh {
namespace {

core::ViewMsg view_of(uint32_t uav, uint32_t tick, std::size_t values) {
  core::ViewMsg v;
  v.uav = uav;
  v.tick = tick;
  v.tiles.push_back(core::TileMsg{0, {1, 2}, tick, 0, 4, 4, std::vector<float>(values, 0.5F)});
  return v;
}

TEST(TickSlots, ANewTickHoldsOnlyItsOwnSamplesInTheSlotsOfTheLast) {
  bus::TickSlots<core::ViewMsg> slots;
  EXPECT_TRUE(slots.empty());
  for (uint32_t u = 0; u < 3; ++u) slots.put(view_of(u, 7, 16));
  ASSERT_EQ(slots.size(), 3U);
  const float* first_values = slots.begin()->tiles[0].values.data();
  slots.clear();
  EXPECT_TRUE(slots.empty());
  EXPECT_EQ(slots.begin(), slots.end()) << "nothing of tick 7 is left to re-send";
  slots.put(view_of(5, 8, 16));
  ASSERT_EQ(slots.size(), 1U);
  EXPECT_EQ(slots.begin()->uav, 5U);
  EXPECT_EQ(slots.begin()->tick, 8U);
  EXPECT_EQ(slots.begin()->tiles[0].tick, 8U);
  // The slot's tile values kept their storage: no allocation for a sample
  // of the same size.
  EXPECT_EQ(slots.begin()->tiles[0].values.data(), first_values);
  // A sample with fewer tiles than the slot held leaves none of the old ones.
  core::ViewMsg bare = view_of(6, 8, 16);
  bare.tiles.clear();
  slots.put(bare);
  ASSERT_EQ(slots.size(), 2U);
  EXPECT_TRUE((slots.begin() + 1)->tiles.empty());
  EXPECT_EQ((slots.begin() + 1)->uav, 6U);
}

}  // namespace
}  // namespace pheromesh
