// pheromesh bench scale's summary: which runs held their size (issue 28: a
// run that flew 0 ticks and exited 1 was named the "largest N with late
// share <= 1 %").
#include <gtest/gtest.h>

#include "bench/commands/bench_scale.hpp"

namespace pheromesh::cli {
namespace {

TEST(BenchScaleVerdict, ARunThatExitedNonZeroDidNotHoldItsSizeWhateverItsLateShare) {
  const auto why = why_not_held({500, 1, 0.0, 19800.0}, 100);
  ASSERT_TRUE(why.has_value());
  EXPECT_EQ(*why, "exited 1");
}

TEST(BenchScaleVerdict, ARunThatFlewTooFewTicksDidNotHoldItsSize) {
  const auto nothing = why_not_held({300, 0, 0.0, std::nullopt}, 100);
  ASSERT_TRUE(nothing.has_value());
  EXPECT_EQ(*nothing, "flew no of 30000 UAV ticks");
  const auto part = why_not_held({300, 0, 0.0, 29000.0}, 100);  // 96.7 %
  ASSERT_TRUE(part.has_value());
  EXPECT_EQ(*part, "flew 29000 of 30000 UAV ticks");
  EXPECT_FALSE(why_not_held({300, 0, 0.5, 29800.0}, 100).has_value());  // 99.3 %: a late starter's tick or two
}

TEST(BenchScaleVerdict, LateTicksAboveOnePercentOrNoLateShareDoNotHold) {
  const auto late = why_not_held({150, 0, 14.9, 15000.0}, 100);
  ASSERT_TRUE(late.has_value());
  EXPECT_EQ(*late, "14.90 % of its ticks late");
  const auto unknown = why_not_held({150, 0, std::nullopt, 15000.0}, 100);
  ASSERT_TRUE(unknown.has_value());
  EXPECT_EQ(*unknown, "no late share reported");
  EXPECT_FALSE(why_not_held({150, 0, 1.0, 15000.0}, 100).has_value());
}

TEST(BenchScaleVerdict, ASizeHoldsOnlyIfEveryOneOfItsRunsHeldIt) {
  // 500 held twice, 750 held once and then flew too few ticks: 750 is not
  // held, whatever its first run did, and 1000 is not looked at.
  const std::vector<ScaleRun> runs{{500, 0, 0.1, 50000.0},  {500, 0, 0.2, 50000.0},  {750, 0, 0.3, 75000.0},
                                   {750, 0, 0.3, 43379.0},  {1000, 0, 0.1, 100000.0}};
  const HeldVerdict v = held_verdict(runs, 100);
  EXPECT_EQ(v.largest_held, 500U);
  EXPECT_EQ(v.first_not_held, 750U);
  EXPECT_EQ(v.why, "flew 43379 of 75000 UAV ticks");
  const HeldVerdict all = held_verdict({{500, 0, 0.1, 50000.0}, {500, 0, 0.2, 50000.0}}, 100);
  EXPECT_EQ(all.largest_held, 500U);
  EXPECT_FALSE(all.first_not_held.has_value());
  EXPECT_FALSE(held_verdict({{100, 1, 0.0, 10000.0}}, 100).largest_held.has_value());
}

}  // namespace
}  // namespace pheromesh::cli
