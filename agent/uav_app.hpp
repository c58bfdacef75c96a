// pheromesh-uav: one UAV running the Shao 2020 ACO policy. It reads only the
// tiles (and UAV states) around it, decides, moves, senses, deposits to the
// place agents owning the cells it affects, and publishes its state.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <vector>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/core/aco.hpp"
#include "pheromesh/core/layers.hpp"
#include "pheromesh/core/rng.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/world.hpp"
#include "pheromesh/runtime/process.hpp"

namespace spdlog {
class logger;
}

namespace pheromesh::agent {

struct UavConfig {
  runtime::CommonOptions common;
  uint32_t id = 0;
  double wait_for_places_s = 15.0;  // [s] wait at start until every place agent is matched
};

// The pheromone tiles a UAV has received, by tile.
class TileCache {
 public:
  explicit TileCache(const core::MapGeometry& geo) : geo_(&geo) {}
  void update(const core::TileMsg& m);
  // Target, obstacle, path values at c, if the tiles of all three layers are known.
  [[nodiscard]] std::optional<std::array<float, 3>> pheromones(core::Cell c) const;
  [[nodiscard]] std::optional<float> value(core::Layer l, core::Cell c) const;
  void forget_except(const std::vector<core::TileCoord>& keep);

 private:
  struct Tile {
    std::array<std::vector<float>, core::kLayerCount> layers;
    std::array<uint32_t, core::kLayerCount> tick{};
  };
  const core::MapGeometry* geo_;
  std::map<std::pair<int32_t, int32_t>, Tile> tiles_;
};

class UavApp {
 public:
  UavApp(UavConfig cfg, core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus);
  int run();

 private:
  void receive();
  void move();
  void sense_and_deposit();
  void deposit(core::DepositKind kind, core::Cell cell, core::RegionId region, float amount);
  void publish_state(bool finished);
  void update_neighbourhood();

  UavConfig cfg_;
  core::ScenarioConfig scenario_;
  core::MapGeometry geo_;
  core::World world_;
  std::unique_ptr<bus::Bus> bus_;
  std::shared_ptr<spdlog::logger> log_;
  core::Rng rng_;
  TileCache cache_;
  core::Cell pos_{};
  core::Cell last_step_{};
  core::Heading heading_ = core::Heading::E;
  uint32_t tick_ = 0;
  uint32_t seq_ = 0;
  uint64_t deposits_sent_ = 0;
  uint64_t deposits_undeliverable_ = 0;
  uint64_t samples_rejected_ = 0;
  uint64_t tile_samples_received_ = 0;
  std::set<std::pair<int32_t, int32_t>> known_obstacles_;
  std::set<std::pair<int32_t, int32_t>> marked_obstacles_;
  std::map<int32_t, uint32_t> target_mark_sent_tick_;  // target index -> tick of last mark sent
  std::set<int32_t> targets_in_range_;
  std::map<uint32_t, core::UavStateMsg> neighbours_;
  std::vector<core::TileCoord> hood_;
  std::vector<core::TileMsg> tile_inbox_;
  std::vector<core::UavStateMsg> state_inbox_;
};

}  // namespace pheromesh::agent
