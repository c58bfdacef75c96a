// The in-process simulator: the same UavCore and PlaceCore the processes run,
// wired together in memory with the lockstep schedule (DESIGN.md, "Time"):
// tick k = UAV phase (read tiles of place tick k-1, decide, move, deposit),
// then place phase (apply exactly the deposits of tick k in canonical order,
// exchange halos of tick k, update, publish tiles of tick k). No DDS, no
// threads: deterministic for a scenario and seed.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <vector>

#include "pheromesh/core/place_core.hpp"
#include "pheromesh/core/run_metrics.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/uav_core.hpp"
#include "pheromesh/core/world.hpp"

namespace pheromesh::core {

class Simulator {
 public:
  explicit Simulator(ScenarioConfig scenario);
  // world_ and the agents point into this object: pinned in memory.
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;

  // Runs ticks 0..scenario.ticks; `on_tick(k)` (optional) is called after each.
  void run(const std::function<void(uint32_t)>& on_tick = {});
  // One tick (both phases).
  void step(uint32_t tick);

  [[nodiscard]] const RunRecorder& recorder() const { return recorder_; }
  [[nodiscard]] const ScenarioConfig& scenario() const { return scenario_; }
  // Final field value of layer `layer` at c (from the place agent owning c).
  [[nodiscard]] float field_value(int layer, Cell c) const;
  [[nodiscard]] int layer_count() const;
  [[nodiscard]] uint64_t uav_steps() const { return uav_steps_; }

 private:
  ScenarioConfig scenario_;
  MapGeometry geo_;
  World world_;
  RunRecorder recorder_;
  std::vector<std::unique_ptr<UavCore>> uavs_;
  std::vector<std::unique_ptr<PlaceCore>> places_;
  std::vector<uint64_t> deposits_sent_;
  std::vector<uint64_t> tile_samples_;
  std::map<std::pair<int32_t, int32_t>, std::vector<TileMsg>> tiles_;  // tile -> its layers, latest place tick
  std::vector<std::vector<DepositMsg>> inbox_;                         // per region
  std::map<std::pair<int32_t, int32_t>, std::vector<UavStateMsg>> states_by_tile_;  // UAV states of the last tick
  std::vector<BroadcastMsg> broadcasts_;                                            // broadcasts of the last tick
  uint64_t uav_steps_ = 0;
};

}  // namespace pheromesh::core
