// The tick-gap meter (core/tick_gaps.hpp): the longest gap between two tick
// starts and the gaps over two periods, with time driven by hand.
#include <gtest/gtest.h>

#include "pheromesh/core/tick_gaps.hpp"

namespace pheromesh::core {
namespace {

using namespace std::chrono_literals;

TEST(TickGaps, ALoopThatKeepsItsClockHasOnePeriodGapsAndNoneOverTwo) {
  TickGaps g(100ms);
  auto t = TickGaps::Clock::time_point{} + 10s;
  for (int i = 0; i < 50; ++i, t += 100ms) EXPECT_FALSE(g.on_tick_start(t).has_value());
  EXPECT_EQ(g.ticks(), 50U);
  EXPECT_EQ(g.max_gap(), 100ms);
  EXPECT_EQ(g.max_gap_ms(), 100U);
  EXPECT_DOUBLE_EQ(g.max_gap_periods(), 1.0);
  EXPECT_EQ(g.gaps_over_2(), 0U);
}

TEST(TickGaps, AStallIsCountedOnceWithItsLengthAndTwoPeriodsExactlyIsNotAGap) {
  TickGaps g(100ms);
  auto t = TickGaps::Clock::time_point{} + 10s;
  g.on_tick_start(t);
  t += 200ms;
  EXPECT_FALSE(g.on_tick_start(t).has_value()) << "two periods are allowed";
  t += 1003ms;
  const auto big = g.on_tick_start(t);
  ASSERT_TRUE(big.has_value());
  EXPECT_EQ(*big, 1003ms);
  t += 250ms;
  EXPECT_TRUE(g.on_tick_start(t).has_value());
  t += 100ms;
  g.on_tick_start(t);
  EXPECT_EQ(g.gaps_over_2(), 2U);
  EXPECT_EQ(g.max_gap_ms(), 1003U);
  EXPECT_NEAR(g.max_gap_periods(), 10.03, 1e-9);
  EXPECT_NEAR(gap_periods(g.max_gap_ms(), 10.0), 10.03, 1e-9);
  EXPECT_EQ(gap_periods(500, 0.0), 0.0);
}

TEST(TickGaps, RestartForgetsThePreviousStartSoAPauseIsNoGap) {
  TickGaps g(50ms);
  auto t = TickGaps::Clock::time_point{} + 1s;
  g.on_tick_start(t);
  g.restart();
  t += 5s;
  EXPECT_FALSE(g.on_tick_start(t).has_value());
  EXPECT_EQ(g.gaps_over_2(), 0U);
  EXPECT_EQ(g.max_gap(), 0ms);
  // The guard: without restart the same silence is a gap.
  TickGaps h(50ms);
  h.on_tick_start(TickGaps::Clock::time_point{} + 1s);
  EXPECT_TRUE(h.on_tick_start(TickGaps::Clock::time_point{} + 6s).has_value());
}

TEST(TickGaps, MillisecondsAreRoundedUpSoASubMillisecondStallIsNotHidden) {
  TickGaps g(1ms);
  const auto t = TickGaps::Clock::time_point{} + 1s;
  g.on_tick_start(t);
  g.on_tick_start(t + 2500us);
  EXPECT_EQ(g.max_gap_ms(), 3U);
  EXPECT_EQ(g.gaps_over_2(), 1U);
}

}  // namespace
}  // namespace pheromesh::core
