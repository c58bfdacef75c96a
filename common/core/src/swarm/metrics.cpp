// Run metrics: coverage of reachable cells and first target acquisitions.
#include "pheromesh/core/metrics.hpp"

#include <algorithm>
#include <cmath>

namespace pheromesh::core {

CoverageTracker::CoverageTracker(const World& world, const std::vector<Cell>& starts, double sensor_radius)
    : world_(&world), radius_(sensor_radius), reachable_(world.reachable_from(starts)), first_covered_(reachable_.size(), kNever) {
  reachable_count_ = std::count(reachable_.begin(), reachable_.end(), uint8_t{1});
  if (!(radius_ >= 0.0)) {
    return;  // negative or NaN radius: a UAV covers nothing
  }
  // Offsets of the sensor disk, computed once; observe() only shifts them.
  const MapGeometry& geo = world.geometry();
  disk_offsets_ = sensor_disk_offsets(radius_, std::max(geo.width(), geo.height()));
}

std::vector<Cell> sensor_disk_offsets(double radius, int32_t max_extent) {
  std::vector<Cell> out;
  if (!(radius >= 0.0)) return out;  // negative or NaN radius: nothing
  const auto r = static_cast<int32_t>(std::floor(std::min(radius, static_cast<double>(max_extent))));
  for (int32_t dy = -r; dy <= r; ++dy) {
    for (int32_t dx = -r; dx <= r; ++dx) {
      if (static_cast<double>(int64_t{dx} * dx + int64_t{dy} * dy) <= radius * radius) out.push_back(Cell{dx, dy});
    }
  }
  return out;
}

void CoverageTracker::observe(Cell uav, uint32_t tick) {
  const MapGeometry& geo = world_->geometry();
  for (const Cell o : disk_offsets_) {
    const Cell c{uav.x + o.x, uav.y + o.y};
    if (!geo.in_map(c)) {
      continue;
    }
    const std::size_t i = geo.index(c);
    if (reachable_[i] == 0) continue;
    if (first_covered_[i] == kNever) ++covered_count_;
    first_covered_[i] = std::min(first_covered_[i], tick);
  }
}

std::vector<int64_t> CoverageTracker::covered_by_tick(uint32_t last_tick) const {
  std::vector<int64_t> n(static_cast<std::size_t>(last_tick) + 1, 0);
  for (const uint32_t t : first_covered_) {
    if (t <= last_tick) ++n[t];
  }
  for (std::size_t k = 1; k < n.size(); ++k) n[k] += n[k - 1];
  return n;
}

double CoverageTracker::coverage() const {
  return reachable_count_ == 0 ? 0.0 : static_cast<double>(covered_count_) / static_cast<double>(reachable_count_);
}

bool AcquisitionTracker::acquire(int32_t target, uint32_t tick) {
  if (target < 0 || static_cast<std::size_t>(target) >= first_.size()) {
    return false;  // unknown target index (e.g. from a bad sample)
  }
  auto& slot = first_[static_cast<std::size_t>(target)];
  if (slot) {
    slot = std::min(*slot, tick);
    return false;
  }
  slot = tick;
  return true;
}

std::size_t AcquisitionTracker::found() const {
  return static_cast<std::size_t>(
      std::count_if(first_.begin(), first_.end(), [](const std::optional<uint32_t>& t) { return t.has_value(); }));
}

std::vector<uint32_t> AcquisitionTracker::acquisition_ticks() const {
  std::vector<uint32_t> ticks;
  for (const auto& t : first_) {
    if (t) {
      ticks.push_back(*t);
    }
  }
  std::sort(ticks.begin(), ticks.end());
  return ticks;
}

}  // namespace pheromesh::core
