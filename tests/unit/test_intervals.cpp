// Intervals of a sweep's means inside the measure's range
// (pheromesh/frontdoor/intervals.hpp), and the times to coverage and to all
// targets of metrics.json (core/run_metrics.hpp), censored when not reached.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

#include "experiments/experiment.hpp"
#include "pheromesh/core/metrics.hpp"
#include "pheromesh/core/run_metrics.hpp"
#include "pheromesh/frontdoor/intervals.hpp"

namespace sweep_intervals = pheromesh::frontdoor;
using pheromesh::core::AcquisitionTracker;
using pheromesh::core::TickRow;

TEST(Intervals, WilsonsIntervalIsTheHandWorkedOneAndStaysInsideZeroToOne) {
  // z = 1.959964, z² = 3.841459, n = 20.
  // 20 of 20: centre (1 + z²/40) / (1 + z²/20) = 0.919437, half
  // z / (1 + z²/20) · sqrt(z² / 1600) = 0.080563: [0.838875, 1].
  auto [lo, hi] = sweep_intervals::wilson95(20, 20);
  EXPECT_NEAR(lo, 0.838875, 1e-6);
  EXPECT_EQ(hi, 1.0);
  // 0 of 20: the mirror image.
  std::tie(lo, hi) = sweep_intervals::wilson95(0, 20);
  EXPECT_EQ(lo, 0.0);
  EXPECT_NEAR(hi, 0.161125, 1e-6);
  // 10 of 20: centre 0.5, half z / (1 + z²/20) · sqrt(0.25/20 + z²/1600) = 0.200702.
  std::tie(lo, hi) = sweep_intervals::wilson95(10, 20);
  EXPECT_NEAR(lo, 0.5 - 0.200702, 1e-6);
  EXPECT_NEAR(hi, 0.5 + 0.200702, 1e-6);
}

TEST(Intervals, AMeanNearItsBoundGetsAnIntervalInsideTheRangeWhereStudentsTLeftIt) {
  // The case: coverage 1 in most runs, lower in a few.
  const std::vector<double> coverage = {1, 1, 1, 1, 1, 1, 1, 0.62, 1, 1};
  // The guard: Student's t goes past 1 on these values.
  EXPECT_GT(pheromesh::cli::experiments::ci95(coverage).hi, 1.0);
  const auto c = sweep_intervals::mean_interval(coverage, sweep_intervals::zero_or_one(coverage));
  EXPECT_EQ(c.method, sweep_intervals::IntervalMethod::Bootstrap);
  EXPECT_GE(c.lo, 0.62);
  EXPECT_LE(c.hi, 1.0);
  EXPECT_LT(c.lo, c.mean);
  // A count that is mostly 0: t went below 0; the bootstrap stays in [0, 2].
  const std::vector<double> found = {0, 0, 0, 2, 0, 0, 0, 0, 1, 0};
  EXPECT_LT(pheromesh::cli::experiments::ci95(found).lo, 0.0);
  const auto f = sweep_intervals::mean_interval(found, sweep_intervals::zero_or_one(found));
  EXPECT_GE(f.lo, 0.0);
  EXPECT_LE(f.hi, 2.0);
  EXPECT_GT(f.hi, f.mean);
}

TEST(Intervals, AZeroOrOneMeasureIsAProportionWithWilsonsInterval) {
  const std::vector<double> v = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
  ASSERT_TRUE(sweep_intervals::zero_or_one(v));
  const auto p = sweep_intervals::mean_interval(v, true);
  EXPECT_EQ(p.method, sweep_intervals::IntervalMethod::Wilson);
  EXPECT_EQ(p.mean, 1.0);
  EXPECT_NEAR(p.lo, 0.838875, 1e-6);  // not [1, 1]: twenty successes do not make a certainty
  EXPECT_FALSE(sweep_intervals::zero_or_one(std::vector<double>{0, 1, 0.5}));
  EXPECT_FALSE(sweep_intervals::zero_or_one(std::vector<double>{}));
  // The caller decides for the whole measure: not a proportion, the bootstrap.
  EXPECT_EQ(sweep_intervals::mean_interval(std::vector<double>{0, 1, 1}, false).method, sweep_intervals::IntervalMethod::Bootstrap);
}

TEST(Intervals, TheBootstrapIsTheSameForTheSameValuesAndShrinksWithMoreRuns) {
  std::vector<double> few, many;
  for (int i = 0; i < 8; ++i) few.push_back(i % 4);
  for (int i = 0; i < 200; ++i) many.push_back(i % 4);
  EXPECT_EQ(sweep_intervals::bootstrap95(few), sweep_intervals::bootstrap95(few));
  const auto [flo, fhi] = sweep_intervals::bootstrap95(few);
  const auto [mlo, mhi] = sweep_intervals::bootstrap95(many);
  EXPECT_LT(mhi - mlo, (fhi - flo) / 3);  // width ~ 1/sqrt(n): 200 runs vs 8
  EXPECT_LT(mlo, 1.5);
  EXPECT_GT(mhi, 1.5);
  EXPECT_EQ(sweep_intervals::bootstrap95(std::vector<double>{3, 3, 3}), (std::pair<double, double>{3, 3}));
  const auto one = sweep_intervals::mean_interval(std::vector<double>{7, std::numeric_limits<double>::quiet_NaN()}, false);
  EXPECT_EQ(one.n, 1U);
  EXPECT_EQ(one.lo, 7.0);
  EXPECT_EQ(one.method, sweep_intervals::IntervalMethod::None);
}

TEST(TimesToReach, TheFirstTickAtACoverageAndTheTickOfTheLastTargetAreCensoredWhenNotReached) {
  std::vector<TickRow> rows(4);
  const double coverage[] = {0.1, 0.5, 0.8, 0.85};
  for (uint32_t k = 0; k < 4; ++k) {
    rows[k].tick = k;
    rows[k].coverage = coverage[k];
  }
  EXPECT_EQ(pheromesh::core::first_tick_at_coverage(rows, 0.5), std::optional<uint32_t>(1));
  EXPECT_EQ(pheromesh::core::first_tick_at_coverage(rows, 0.9), std::nullopt);
  AcquisitionTracker a(2);
  a.acquire(1, 40);
  EXPECT_EQ(pheromesh::core::all_targets_found_tick(a), std::nullopt);  // one of two
  a.acquire(0, 75);
  EXPECT_EQ(pheromesh::core::all_targets_found_tick(a), std::optional<uint32_t>(75));
  EXPECT_EQ(pheromesh::core::all_targets_found_tick(AcquisitionTracker(0)), std::nullopt);  // no target
}
