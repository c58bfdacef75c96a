// The two halves of every search policy, without any transport:
//  * UavPolicy: what one UAV decides each tick from what it can see (its
//    neighbourhood tiles, the UAVs over those tiles, swarm broadcasts, its
//    simulated sensor);
//  * PlaceModel: what one place agent does with the deposits it receives
//    (aggregation, evaporation, diffusion, timers) over the layers it owns.
// UavCore and PlaceCore wrap them with the parts every policy shares
// (sequence numbers, the deposit ledger, tiles, neighbour bookkeeping), and
// the processes and the in-process simulator drive those cores, so a policy
// behaves identically in `pheromesh run` and `pheromesh sim`.
//
// A scenario picks the policy (scenario.policy in the textproto; the Shao
// search when absent). Each policy lives in its paper's room,
// common/core/papers/<paper>/ (pheromesh/<paper>/policy.hpp), which exports
// its entry of the policy table (policy_table.hpp); the functions below call
// the entry of the scenario's policy.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <limits>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/layers.hpp"
#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/plausibility.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/world.hpp"

namespace pheromesh::core {

// What a policy looks like from outside.
struct PolicyTraits {
  std::vector<std::string> layers;  // layer names, index = TileState.layer
  double sensor_radius = 4.0;       // [cell] for the coverage metric
  double view_radius = 5.0;         // [cell] tiles (and the UAVs over them) a UAV reads
  // Its step reads UavView::neighbours. A policy that never does says false:
  // its UAVs' views then carry no neighbours (the place agents compose none,
  // the simulator shows none), and a crowded swarm's views are mostly those.
  // The default keeps them, so that a policy that reads them gets them.
  bool reads_neighbours = true;
  // Its UAVs may broadcast to the swarm (PolicyEntry::broadcasts); a UAV then
  // creates its writer at start.
  bool broadcasts = false;
  // Plausibility (plausibility.hpp): the farthest a UAV flies in one tick
  // [cell/tick], and each layer's physical range (index = layer).
  double max_step = 1.5;
  // How far from the UAV's cell its deposits land [cell] (check_deposit_reach;
  // docs/writing-a-policy.md). Infinite: its deposits are not judged by place
  // (a policy that marks a planned path or a region's corner, Duan's).
  double deposit_reach = std::numeric_limits<double>::infinity();
  std::vector<ValueRange> layer_ranges;  // policy_traits fills [0, kMaxLayerValue] where a policy gives none
  std::vector<Cell> starts;              // UAV i's start cell, if the policy does not use start_cell(s, i)
};
// A pheromone layer without a range of its own holds nonnegative values
// below the largest deposit (messages.cpp): 1e30 is no pheromone.
inline constexpr float kMaxLayerValue = 1e6F;
// Where UAV `id` starts flying (traits.starts, else start_cell).
Cell uav_start(const ScenarioConfig& s, const PolicyTraits& traits, uint32_t id);
PolicyTraits policy_traits(const ScenarioConfig& s);

// The pheromone tiles a UAV has received, by tile and layer.
class TileCache {
 public:
  TileCache(const MapGeometry& geo, int layers) : geo_(&geo), layers_(layers) {}
  void update(const TileMsg& m);  // m must have passed check_tile
  [[nodiscard]] std::optional<float> value(int layer, Cell c) const;
  // Tick of the oldest layer held for tile t (nullopt if a layer is missing).
  [[nodiscard]] std::optional<uint32_t> oldest_tick(TileCoord t) const;
  void forget_except(const std::vector<TileCoord>& keep);
  void clear() { tiles_.clear(); }
  [[nodiscard]] int layers() const { return layers_; }

 private:
  struct Tile {
    std::vector<std::vector<float>> layers;
    std::vector<uint32_t> tick;
  };
  const MapGeometry* geo_;
  int layers_;
  std::map<std::pair<int32_t, int32_t>, Tile> tiles_;
};

// What a UAV knows at the start of its tick.
struct UavView {
  uint32_t tick = 0;
  const TileCache* tiles = nullptr;
  // States (of tick - 1 in lockstep and in the simulator) of the other UAVs
  // over the tiles of this UAV's neighbourhood, by id: each its pose (uav,
  // tick, x, y, vx, vy, heading, role, view) and `finished`; the counters
  // of a state are zero here.
  std::span<const UavStateMsg> neighbours;
  // Broadcasts (of tick - 1 in lockstep and in the simulator; those received
  // since the last tick in realtime), own included, by UAV id.
  std::span<const BroadcastMsg> broadcasts;
};

// What a UAV does in its tick. UavCore fills uav, tick and seq of deposits,
// uav and tick of broadcasts and detections, uav and tick of the state.
struct UavActions {
  std::vector<DepositMsg> deposits;
  std::vector<DetectionMsg> detections;
  std::optional<BroadcastMsg> broadcast;  // at most one per UAV and tick
  UavStateMsg state;                      // x, y, vx, vy, heading, role
  void clear() {
    deposits.clear();
    detections.clear();
    broadcast.reset();
    state = {};
  }
};

class UavPolicy {
 public:
  virtual ~UavPolicy() = default;
  // Tick 0 starts the policy (sense and deposit at the start); later ticks move first.
  virtual void step(const UavView& view, UavActions& out) = 0;
  [[nodiscard]] virtual Cell cell() const = 0;  // the cell the UAV is over
};

class PlaceModel {
 public:
  virtual ~PlaceModel() = default;
  // Applies one deposit that passed check_deposit and the sequence check.
  // Returns a rejection reason, or nullopt when applied.
  virtual std::optional<std::string> apply(const DepositMsg& d, uint32_t tick, std::vector<TargetEventMsg>& events) = 0;
  // After the deposits of `tick`: timers, then the border ring of the
  // diffusion sources for the neighbours (empty rings: no diffusion).
  virtual HaloRing begin_step(uint32_t tick, std::vector<TargetEventMsg>& events) = 0;
  virtual void accept_halo(const Rect& neighbour_rect, const HaloRing& ring) = 0;
  // The layer update of the tick.
  virtual void finish_step() = 0;
  [[nodiscard]] virtual float value(int layer, Cell c) const = 0;  // c inside the region
  // The values of `layer` over `r` (inside the region), row-major into out
  // (r.area() values): what value() gives cell by cell. A model that holds
  // its layers as arrays copies rows instead (a tile a tick for every view).
  virtual void copy_rect(int layer, const Rect& r, float* out) const {
    for (int32_t y = r.y0; y < r.y0 + r.h; ++y) {
      for (int32_t x = r.x0; x < r.x0 + r.w; ++x) *out++ = value(layer, {x, y});
    }
  }
};

std::unique_ptr<UavPolicy> make_uav_policy(const ScenarioConfig& s, const MapGeometry& geo, const World& world,
                                           uint32_t id);
std::unique_ptr<PlaceModel> make_place_model(const ScenarioConfig& s, const MapGeometry& geo, RegionId region);

// Quantities of the final field that judge a run of this policy (for
// metrics.json "field"), e.g. Liu's visited cells and environmental
// uncertainty. `value(layer, c)` reads the final field.
using FieldLookup = std::function<float(int layer, Cell c)>;
std::map<std::string, double> field_summary(const ScenarioConfig& s, const FieldLookup& value);

// Each paper's factories (traits, UAV policy, place model, field summary)
// are declared in its room (pheromesh/<paper>/policy.hpp) and reached through
// its entry of the policy table (policy_table.hpp, core/src/policy/policy_table.cpp).

// Heading (0..7) closest to a velocity; `fallback` for a zero velocity.
uint8_t heading_of_velocity(double vx, double vy, uint8_t fallback);

// A LayerAdd deposit of `amount` to `layer` at c, for the region owning c.
DepositMsg layer_add(const MapGeometry& geo, int layer, Cell c, double amount);

// Fills x, y, vx, vy [cell units, cell centre = integer] and heading of a
// UAV state from positions in metres on a map of `cell_size_m` cells
// (cell c spans [c·s, (c+1)·s)); `heading` keeps the last one at rest.
void set_state_from_metres(UavStateMsg& state, double x_m, double y_m, double before_x_m, double before_y_m,
                           double cell_size_m, uint8_t& heading);

}  // namespace pheromesh::core
