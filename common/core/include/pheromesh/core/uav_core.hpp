// One UAV's logic without any transport: the tiles it has received, the Shao
// 2020 search policy, its simulated sensor, and the deposits, detections and
// state it produces each tick. The pheromesh-uav process and the in-process
// simulator both drive this class, so they make the same decisions.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <vector>

#include "pheromesh/core/aco.hpp"
#include "pheromesh/core/layers.hpp"
#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/rng.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/world.hpp"

namespace pheromesh::core {

// The pheromone tiles a UAV has received, by tile.
class TileCache {
 public:
  explicit TileCache(const MapGeometry& geo) : geo_(&geo) {}
  void update(const TileMsg& m);  // m must have passed check_tile
  // Target, obstacle, path values at c, if the tiles of all three layers are known.
  [[nodiscard]] std::optional<std::array<float, 3>> pheromones(Cell c) const;
  [[nodiscard]] std::optional<float> value(Layer l, Cell c) const;
  // Tick of the oldest layer held for tile t (nullopt if a layer is missing).
  [[nodiscard]] std::optional<uint32_t> oldest_tick(TileCoord t) const;
  void forget_except(const std::vector<TileCoord>& keep);

 private:
  struct Tile {
    std::array<std::vector<float>, kLayerCount> layers;
    std::array<uint32_t, kLayerCount> tick{};
  };
  const MapGeometry* geo_;
  std::map<std::pair<int32_t, int32_t>, Tile> tiles_;
};

class UavCore {
 public:
  // `world` is the simulated ground truth the sensor reads; it must outlive this.
  UavCore(const ScenarioConfig& scenario, const World& world, uint32_t id);
  // The tile cache keeps a pointer to geo_: pinned in memory.
  UavCore(const UavCore&) = delete;
  UavCore& operator=(const UavCore&) = delete;

  void receive_tile(const TileMsg& m) { cache_.update(m); }
  void receive_neighbour(const UavStateMsg& s);

  struct Output {
    std::vector<DepositMsg> deposits;  // in sequence order
    std::vector<DetectionMsg> detections;
    UavStateMsg state;  // deposits_sent / tile_samples_received left to the caller
  };
  // Tick 0 senses and deposits at the start cell; every later tick moves
  // first (Shao 2020 Algorithm 1), then senses and deposits.
  void step(uint32_t tick, Output& out);

  // Tiles this UAV needs: those within its sensor radius plus one step.
  [[nodiscard]] const std::vector<TileCoord>& neighbourhood() const { return hood_; }
  [[nodiscard]] const TileCache& tiles() const { return cache_; }
  [[nodiscard]] Cell cell() const { return pos_; }
  [[nodiscard]] Heading heading() const { return heading_; }
  [[nodiscard]] uint32_t id() const { return id_; }

 private:
  void move();
  void sense_and_deposit(uint32_t tick, Output& out);
  void add_deposit(DepositKind kind, Cell cell, RegionId region, uint32_t tick, Output& out);
  void update_neighbourhood();

  const ScenarioConfig* scenario_;
  MapGeometry geo_;
  const World* world_;
  uint32_t id_;
  Rng rng_;
  TileCache cache_;
  Cell pos_{};
  Cell last_step_{};
  Heading heading_ = Heading::E;
  uint32_t seq_ = 0;
  std::set<std::pair<int32_t, int32_t>> known_obstacles_;
  std::set<std::pair<int32_t, int32_t>> marked_obstacles_;
  std::map<int32_t, uint32_t> target_mark_sent_tick_;  // target index -> tick of the last mark sent
  std::set<int32_t> targets_in_range_;
  std::map<uint32_t, UavStateMsg> neighbours_;
  std::vector<TileCoord> hood_;
};

}  // namespace pheromesh::core
