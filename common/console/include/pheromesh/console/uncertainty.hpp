// Environmental uncertainty for the console's plot: how stale the swarm's
// knowledge of the map is. A reachable cell last observed `age` ticks ago
// (within the sensor radius of some UAV) has uncertainty 1 - exp(-age / tau);
// a cell never observed has 1. The plot shows the mean over reachable cells,
// 0 (everything seen just now) .. 1 (nothing ever seen). This is pheromesh's
// own measure, the same for every policy; it is not from one of the papers.
#pragma once

#include <cstdint>
#include <vector>

#include "pheromesh/core/grid.hpp"

namespace pheromesh::console {

class UncertaintyTracker {
 public:
  // `reachable`: one byte per map cell (row-major), 1 if the cell counts.
  UncertaintyTracker(const core::MapGeometry& geo, std::vector<uint8_t> reachable, double sensor_radius, double tau_ticks);
  void observe(core::Cell uav, uint32_t tick);
  [[nodiscard]] double mean(uint32_t now_tick) const;

 private:
  core::MapGeometry geo_;
  std::vector<uint8_t> reachable_;
  std::vector<int64_t> last_seen_;  // -1: never
  std::vector<core::Cell> disk_;
  double tau_;
  int64_t reachable_count_ = 0;
};

}  // namespace pheromesh::console
