#include "pheromesh/core/view_pacing.hpp"

#include <algorithm>
#include <stdexcept>

namespace pheromesh::core {

ViewPacing::ViewPacing(std::chrono::nanoseconds period, Clock::time_point start) : period_(period) {
  if (period.count() <= 0) throw std::invalid_argument("ViewPacing: the period must be positive");
  due_ = start + period;
}

void ViewPacing::ran(Clock::time_point now, bool by_view) {
  if (now > timer_at() + period_) {
    // More than a period after the timer would have run it: late; no burst
    // to catch up.
    ++late_;
    due_ = now + period_;
  } else if (by_view) {
    due_ = now + period_;
  } else {
    due_ += period_;
  }
  ++(by_view ? by_view_ : by_timer_);
}

std::chrono::milliseconds start_wait_period(std::chrono::milliseconds lease) {
  if (lease.count() <= 0) throw std::invalid_argument("start_wait_period: the lease must be positive");
  return std::clamp(lease / 4, std::chrono::milliseconds(1), std::chrono::milliseconds(1000));
}

}  // namespace pheromesh::core
