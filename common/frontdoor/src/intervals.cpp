#include "pheromesh/frontdoor/intervals.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <vector>

#include "pheromesh/core/rng.hpp"

namespace pheromesh::frontdoor {

namespace {
constexpr double kZ95 = 1.959963984540054;  // the standard normal's 97.5th percentile

// The p-quantile of sorted values, interpolated between neighbours.
double quantile(const std::vector<double>& sorted, double p) {
  const double at = p * static_cast<double>(sorted.size() - 1);
  const auto below = static_cast<std::size_t>(std::floor(at));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  const double frac = at - static_cast<double>(below);
  return sorted[below] + frac * (sorted[above] - sorted[below]);
}
}  // namespace

const char* to_string(IntervalMethod m) {
  switch (m) {
    case IntervalMethod::Wilson:
      return "wilson";
    case IntervalMethod::Bootstrap:
      return "bootstrap";
    case IntervalMethod::None:
      break;
  }
  return "";
}

bool zero_or_one(std::span<const double> values) {
  bool any = false;
  for (double v : values) {
    if (!std::isfinite(v)) continue;
    if (v != 0.0 && v != 1.0) return false;
    any = true;
  }
  return any;
}

std::pair<double, double> wilson95(std::size_t successes, std::size_t n) {
  const auto nn = static_cast<double>(n);
  const double p = static_cast<double>(successes) / nn;
  const double z2 = kZ95 * kZ95;
  const double centre = (p + z2 / (2 * nn)) / (1 + z2 / nn);
  const double half = kZ95 / (1 + z2 / nn) * std::sqrt(p * (1 - p) / nn + z2 / (4 * nn * nn));
  // Rounding must not take the bounds out of [0, 1], nor past the estimate.
  return {std::clamp(std::min(centre - half, p), 0.0, 1.0), std::clamp(std::max(centre + half, p), 0.0, 1.0)};
}

std::pair<double, double> bootstrap95(std::span<const double> values, std::size_t resamples, uint64_t seed) {
  const auto [lo_it, hi_it] = std::minmax_element(values.begin(), values.end());
  if (*lo_it == *hi_it) return {*lo_it, *hi_it};  // every resample has the same mean
  core::Rng rng(seed);
  const auto n = static_cast<uint32_t>(values.size());
  std::vector<double> means(resamples);
  for (double& m : means) {
    double sum = 0;
    for (uint32_t i = 0; i < n; ++i) sum += values[rng.uniform_below(n)];
    m = sum / static_cast<double>(n);
  }
  std::sort(means.begin(), means.end());
  // A mean of values in [min, max] is in [min, max]; interpolation keeps it there.
  return {std::max(quantile(means, 0.025), *lo_it), std::min(quantile(means, 0.975), *hi_it)};
}

MeanInterval mean_interval(std::span<const double> values, bool proportion) {
  std::vector<double> finite;
  for (double v : values) {
    if (std::isfinite(v)) finite.push_back(v);
  }
  MeanInterval out;
  out.n = finite.size();
  if (finite.empty()) return out;
  double sum = 0;
  for (double v : finite) sum += v;
  out.mean = sum / static_cast<double>(out.n);
  if (out.n == 1) {
    out.lo = out.hi = out.mean;
    return out;
  }
  double ss = 0;
  for (double v : finite) ss += (v - out.mean) * (v - out.mean);
  out.sd = std::sqrt(ss / static_cast<double>(out.n - 1));
  if (proportion && zero_or_one(finite)) {
    const auto successes = static_cast<std::size_t>(std::count(finite.begin(), finite.end(), 1.0));
    std::tie(out.lo, out.hi) = wilson95(successes, out.n);
    out.method = IntervalMethod::Wilson;
  } else {
    std::tie(out.lo, out.hi) = bootstrap95(finite);
    out.method = IntervalMethod::Bootstrap;
  }
  return out;
}

}  // namespace pheromesh::frontdoor
