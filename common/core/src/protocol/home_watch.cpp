#include "pheromesh/core/home_watch.hpp"

#include <algorithm>

namespace pheromesh::core {

std::chrono::milliseconds HomeWatch::silence_for(uint32_t lease_ms, bool standby) {
  const int64_t leases = standby ? 4 : 2;
  return std::max(std::chrono::milliseconds(2000), std::chrono::milliseconds(leases * int64_t{lease_ms}));
}

bool HomeWatch::move_to_backup(Clock::time_point now) {
  if (moved_ || !has_backup_ || now - last_heard_ <= silence_) return false;
  moved_ = true;
  return true;
}

}  // namespace pheromesh::core
