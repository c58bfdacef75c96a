// How well a realtime tick loop kept its clock (issue 14, "survivors keep
// their clock"): the longest gap between the starts of two consecutive ticks
// and how many gaps exceeded two tick periods. A fault elsewhere in the swarm
// (a process killed or stopped) must not stall a survivor's loop; a UAV
// reports these in its state, a place agent in its health, and metrics.json
// sums them per role (uav_tick_gap_max_periods, place_tick_gaps_over_2, ...).
// Time is passed in, so tests drive it by hand.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>

namespace pheromesh::core {

class TickGaps {
 public:
  using Clock = std::chrono::steady_clock;

  // `period`: the loop's tick period (> 0).
  explicit TickGaps(std::chrono::nanoseconds period) : period_(period) {}

  // A tick starts at `t`. Returns the gap since the previous start when it
  // exceeds two periods (for a log line), else nullopt.
  std::optional<std::chrono::nanoseconds> on_tick_start(Clock::time_point t);

  // Forget the previous start (e.g. after a pause from the console, whose
  // silence is not a gap of the loop).
  void restart() { last_.reset(); }

  [[nodiscard]] std::chrono::nanoseconds period() const { return period_; }
  [[nodiscard]] std::chrono::nanoseconds max_gap() const { return max_gap_; }
  // The longest gap [ms], rounded up, for the wire.
  [[nodiscard]] uint32_t max_gap_ms() const;
  // The longest gap in tick periods (1.0 for a loop that kept its clock).
  [[nodiscard]] double max_gap_periods() const;
  // Gaps longer than two periods.
  [[nodiscard]] uint32_t gaps_over_2() const { return over_2_; }
  [[nodiscard]] uint64_t ticks() const { return ticks_; }

 private:
  std::chrono::nanoseconds period_;
  std::optional<Clock::time_point> last_;
  std::chrono::nanoseconds max_gap_{0};
  uint32_t over_2_ = 0;
  uint64_t ticks_ = 0;
};

// A gap of `gap_ms` in periods of a clock at `rate_hz` (0 when the rate is not positive).
double gap_periods(uint32_t gap_ms, double rate_hz);

}  // namespace pheromesh::core
