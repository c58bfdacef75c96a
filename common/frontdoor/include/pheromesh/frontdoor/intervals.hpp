// The 95 % interval of a mean over a sweep's runs, inside the range the
// measure can take (issue 45: Student's t gave coverage [0.885, 1.061] and
// targets_found [-1.101, 1.768]). `pheromesh sweep`'s summary.csv, sweep.md
// and plots use it.
//   * A measure whose every value in the sweep is 0 or 1 (a flag, or a count
//     that can only be 0 or 1, such as targets found with one target): the
//     mean is the share of runs, and its interval is Wilson's score interval
//     (Wilson 1927), inside [0, 1].
//   * Any other: the percentile bootstrap of the mean (Efron & Tibshirani
//     1993, ch. 13), inside [min, max] of the values and so inside any range
//     the measure has. Deterministic: a fixed number of resamples from a
//     seeded core::Rng, so the same values give the same interval.
// Neither needs the values to be normal; the bootstrap's coverage falls
// short of 95 % for a handful of runs (docs/sweeps.md says so).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>

namespace pheromesh::frontdoor {

enum class IntervalMethod : uint8_t { None, Wilson, Bootstrap };
// "" (no interval: fewer than two values), "wilson", "bootstrap".
const char* to_string(IntervalMethod m);

struct MeanInterval {
  std::size_t n = 0;  // finite values
  double mean = std::numeric_limits<double>::quiet_NaN();
  double sd = std::numeric_limits<double>::quiet_NaN();  // sample standard deviation (n - 1); NaN for n < 2
  double lo = std::numeric_limits<double>::quiet_NaN();
  double hi = std::numeric_limits<double>::quiet_NaN();
  IntervalMethod method = IntervalMethod::None;
};

// At least one finite value, and every finite value 0 or 1.
bool zero_or_one(std::span<const double> values);

// Wilson's 95 % score interval of a proportion of `successes` in n > 0 trials.
std::pair<double, double> wilson95(std::size_t successes, std::size_t n);

// The 95 % percentile bootstrap interval of the mean of `values` (all finite,
// at least one): the 2.5th and 97.5th percentiles of the means of
// `resamples` samples of values.size() values drawn with replacement.
inline constexpr std::size_t kBootstrapResamples = 4000;
std::pair<double, double> bootstrap95(std::span<const double> values, std::size_t resamples = kBootstrapResamples,
                                      uint64_t seed = 1);

// n, mean, sd and the interval of the finite values of `values`: Wilson when
// `proportion` (the caller decides for the measure as a whole, zero_or_one
// over every run), else the bootstrap. One value: {v, v}, method None; none:
// NaN.
MeanInterval mean_interval(std::span<const double> values, bool proportion);

}  // namespace pheromesh::frontdoor
