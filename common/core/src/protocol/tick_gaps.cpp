#include "pheromesh/core/tick_gaps.hpp"

#include <algorithm>

namespace pheromesh::core {

std::optional<std::chrono::nanoseconds> TickGaps::on_tick_start(Clock::time_point t) {
  ++ticks_;
  std::optional<std::chrono::nanoseconds> big;
  if (last_ && t > *last_) {
    const auto gap = std::chrono::duration_cast<std::chrono::nanoseconds>(t - *last_);
    max_gap_ = std::max(max_gap_, gap);
    if (gap > 2 * period_) {
      ++over_2_;
      big = gap;
    }
  }
  last_ = t;
  return big;
}

uint32_t TickGaps::max_gap_ms() const {
  const auto ms = (max_gap_.count() + 999'999) / 1'000'000;
  return static_cast<uint32_t>(std::min<int64_t>(ms, UINT32_MAX));
}

double TickGaps::max_gap_periods() const {
  return period_.count() > 0 ? static_cast<double>(max_gap_.count()) / static_cast<double>(period_.count()) : 0.0;
}

double gap_periods(uint32_t gap_ms, double rate_hz) { return rate_hz > 0 ? gap_ms * rate_hz / 1000.0 : 0.0; }

}  // namespace pheromesh::core
