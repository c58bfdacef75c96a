// One UAV without any transport: the tiles it has received, the states of
// the UAVs near it, the swarm broadcasts, and the scenario's policy
// (policy.hpp), which decides, senses and deposits. UavCore numbers the
// deposits and keeps the neighbourhood. The pheromesh-uav process and the
// in-process simulator both drive this class, so they make the same decisions.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/world.hpp"

namespace pheromesh::core {

class UavCore {
 public:
  // Deposits are numbered first + 1, first + 2, ... (a restarted UAV starts
  // above the numbers of its earlier life, which place agents already saw).
  void set_first_seq(uint32_t first) { seq_ = first; }
  // `world` is the simulated ground truth the sensor reads; it must outlive this.
  // `exact_ticks`: decide on the neighbour states and broadcasts of exactly
  // the previous tick (lockstep, simulator); otherwise on the latest ones.
  UavCore(const ScenarioConfig& scenario, const World& world, uint32_t id, bool exact_ticks = true);
  // The tile cache and the policy keep pointers to geo_: pinned in memory.
  UavCore(const UavCore&) = delete;
  UavCore& operator=(const UavCore&) = delete;

  // A view arrived: it replaces what the tile cache held, so a tile its
  // view no longer carries (a dark region, core/faults.hpp) is not read.
  // Without a view the cache keeps what it held.
  void begin_view() { cache_.clear(); }
  void receive_tile(const TileMsg& m) { cache_.update(m); }
  void receive_neighbour(const UavStateMsg& s);   // other UAVs over the neighbourhood tiles
  void receive_broadcast(const BroadcastMsg& b);  // the swarm's broadcasts

  struct Output {
    std::vector<DepositMsg> deposits;  // in sequence order
    std::vector<DetectionMsg> detections;
    std::optional<BroadcastMsg> broadcast;
    UavStateMsg state;  // deposits_sent / tile_samples_received left to the caller
  };
  void step(uint32_t tick, Output& out);

  // Lockstep: true once this UAV holds, for tick t, the states of every
  // other UAV over its neighbourhood tiles (`occupancy` counts all UAVs per
  // tile, this one included) and `broadcasts` broadcasts.
  [[nodiscard]] bool holds_tick(uint32_t t, const std::vector<TileCount>& occupancy, uint32_t broadcasts) const;

  // Tiles this UAV reads: those within the policy's view radius.
  [[nodiscard]] const std::vector<TileCoord>& neighbourhood() const { return hood_; }
  [[nodiscard]] const TileCache& tiles() const { return cache_; }
  [[nodiscard]] Cell cell() const { return policy_->cell(); }
  [[nodiscard]] const UavStateMsg& last_state() const { return last_state_; }
  // How many other UAVs it holds states of: those heard within the last few
  // ticks (a step forgets the others).
  [[nodiscard]] std::size_t neighbours_held() const { return neighbours_.size(); }
  [[nodiscard]] uint32_t id() const { return id_; }
  // What the last step decided on (for debug traces).
  [[nodiscard]] std::size_t last_view_neighbours() const { return view_states_.size(); }
  // The neighbours' states the last step decided on (UavView::neighbours).
  [[nodiscard]] std::span<const UavStateMsg> last_view_states() const { return view_states_; }
  [[nodiscard]] std::size_t last_view_broadcasts() const { return view_broadcasts_.size(); }

 private:
  void update_neighbourhood();
  [[nodiscard]] bool in_hood(const UavStateMsg& s) const;

  const ScenarioConfig* scenario_;
  MapGeometry geo_;
  uint32_t id_;
  bool exact_;
  PolicyTraits traits_;
  TileCache cache_;
  std::unique_ptr<UavPolicy> policy_;
  uint32_t seq_ = 0;
  std::map<uint32_t, std::map<uint32_t, UavStateMsg>> neighbours_;    // uav -> tick -> state (a few ticks)
  std::map<uint32_t, std::map<uint32_t, BroadcastMsg>> broadcasts_;   // tick -> uav -> broadcast (a few ticks)
  uint32_t broadcasts_consumed_ = 0;  // realtime: broadcasts of earlier ticks were handed to the policy
  std::vector<TileCoord> hood_;
  UavStateMsg last_state_{};
  UavActions actions_;
  std::vector<UavStateMsg> view_states_;
  std::vector<BroadcastMsg> view_broadcasts_;
};

// Cell a UAV state is over (its position rounded to the nearest cell centre).
Cell state_cell(const UavStateMsg& s);

}  // namespace pheromesh::core
