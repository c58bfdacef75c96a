// core::summarize: nearest-rank percentiles worked by hand.
#include <gtest/gtest.h>

#include "pheromesh/core/sample_summary.hpp"

namespace pheromesh::core {
namespace {

TEST(SampleSummary, TenSamplesGiveTheNearestRankPercentilesWorkedByHand) {
  // Sorted: 1 2 3 4 5 6 7 8 9 100. p50: rank ceil(5) = 5 -> 5; p90: rank 9 -> 9;
  // p99: rank ceil(9.9) = 10 -> 100; mean 145 / 10.
  const SampleSummary s = summarize({100, 3, 1, 2, 9, 8, 7, 6, 5, 4});
  EXPECT_EQ(s.n, 10U);
  EXPECT_DOUBLE_EQ(s.mean, 14.5);
  EXPECT_DOUBLE_EQ(s.p50, 5);
  EXPECT_DOUBLE_EQ(s.p90, 9);
  EXPECT_DOUBLE_EQ(s.p99, 100);
  EXPECT_DOUBLE_EQ(s.max, 100);
}

TEST(SampleSummary, OneSampleIsEveryPercentileAndNoneIsAllZero) {
  const SampleSummary one = summarize({2.5});
  EXPECT_EQ(one.n, 1U);
  EXPECT_DOUBLE_EQ(one.p50, 2.5);
  EXPECT_DOUBLE_EQ(one.p99, 2.5);
  const SampleSummary none = summarize({});
  EXPECT_EQ(none.n, 0U);
  EXPECT_DOUBLE_EQ(none.max, 0);
}

}  // namespace
}  // namespace pheromesh::core
