#include "pheromesh/console/uncertainty.hpp"

#include <algorithm>
#include <cmath>

#include "pheromesh/core/metrics.hpp"

namespace pheromesh::console {

UncertaintyTracker::UncertaintyTracker(const core::MapGeometry& geo, std::vector<uint8_t> reachable, double sensor_radius,
                                       double tau_ticks)
    : geo_(geo), reachable_(std::move(reachable)), tau_(tau_ticks > 0 ? tau_ticks : 1.0) {
  reachable_.resize(static_cast<std::size_t>(geo_.width()) * static_cast<std::size_t>(geo_.height()), 0);
  last_seen_.assign(reachable_.size(), -1);
  reachable_count_ = std::count(reachable_.begin(), reachable_.end(), uint8_t{1});
  disk_ = core::sensor_disk_offsets(sensor_radius, std::max(geo_.width(), geo_.height()));
}

void UncertaintyTracker::observe(core::Cell uav, uint32_t tick) {
  for (const auto& d : disk_) {
    const core::Cell c{uav.x + d.x, uav.y + d.y};
    if (!geo_.in_map(c)) continue;
    auto& seen = last_seen_[geo_.index(c)];
    seen = std::max<int64_t>(seen, tick);
  }
}

double UncertaintyTracker::mean(uint32_t now_tick) const {
  if (reachable_count_ == 0) return 0.0;
  double sum = 0.0;
  for (std::size_t i = 0; i < reachable_.size(); ++i) {
    if (reachable_[i] == 0) continue;
    if (last_seen_[i] < 0) {
      sum += 1.0;
    } else {
      const double age = std::max<double>(0.0, double(int64_t{now_tick} - last_seen_[i]));
      sum += 1.0 - std::exp(-age / tau_);
    }
  }
  return sum / double(reachable_count_);
}

}  // namespace pheromesh::console
