// Scenario parameters of the Ravankar 2016 uncertainty-aware deposition policy
// (ravankar/src/policy.cpp, docs/policies/ravankar.md). The paper's quantities
// keep the structs of pheromesh/ravankar/model.hpp; the rest are our choices for a swarm.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/policy_table.hpp"
#include "pheromesh/ravankar/model.hpp"

namespace pheromesh::core {

struct RavankarConfig final : PolicyConfig {
  static constexpr std::string_view kPolicy = "ravankar";
  [[nodiscard]] std::string_view policy() const override { return kPolicy; }

  double dt_s = 1.0;             // [s] one tick
  double cell_size_m = 1.0;      // [m] "cells of unit area"; deposit.cell_size_m is kept equal
  uint32_t leaders = 1;          // UAVs 0 .. leaders-1 lead (Role::Leader), the others follow
  std::vector<Cell> route;       // leaders' waypoints [cell], flown in order
  double leader_speed_mps = 0.5;  // [m/s]
  RavankarDepositParams deposit;          // τ, cap, z_rng, Ravankar 2016 eq. (14) reading
  RavankarEvaporationParams evaporation;  // K, P_a
  RavankarFollowerParams follower;        // P0, δ, Ravankar 2016 Table 2
  RavankarMotionParams motion;            // W_r, wheel noise
  uint32_t fix_every_ticks = 1;           // [tick] 0 = never
  double fix_sigma_m = 0.05;              // [m]
  std::optional<Rect> fix_area;           // nullopt: everywhere
  uint32_t deposit_every_ticks = 1;       // [tick]
  bool followers_deposit = false;
  uint32_t follower_delay_ticks = 0;  // [tick]
  double explore_speed_mps = 0.5;     // [m/s]
  // Where a follower's own exploration starts when it rejects a trail (the
  // paper: it "carries its own exploration", direction unstated). Onward:
  // the correlated walk goes on from the heading it had. Retreat (ours, the
  // ravankar_retreat variant, docs/policies/ravankar.md): the walk starts
  // turned by π from the direction in which the follower last moved along the
  // trail, away from where the trail became unreliable (Ravankar 2016 Fig. 24: explore B, not A).
  enum class RejectExplore : uint8_t { Onward = 0, Retreat = 1 };
  RejectExplore reject_explore = RejectExplore::Onward;
};

// The heading [rad, in [0, 2π)] a follower's exploration starts from when it
// rejects a trail: `heading` (Onward) or heading + π (Retreat).
double ravankar_reject_heading(double heading_rad, RavankarConfig::RejectExplore mode);

// What a follower does in a tick (exposed for the unit tests).
enum class RavankarFollowerMode : uint8_t { Waiting = 0, Following = 1, Holding = 2, Exploring = 3 };

// A follower's choice at the cell `at` under its estimated position: the
// strongest not yet visited 8-neighbour (ties: the first in the order E, NE,
// N, NW, W, SW, S, SE) if it holds at least δ·P0 (Following, toward it);
// failing that the strongest not yet visited cell of the ring at Chebyshev
// distance 2 (ties: row-major) if it holds at least δ·P0;
// else, if `at` itself holds at least δ·P0, stay (Holding: at the head of a
// fresh trail, e.g. just behind the leader); else the trail is rejected
// (Exploring). Cells whose value the follower does not have count as 0.
struct RavankarChoice {
  RavankarFollowerMode mode = RavankarFollowerMode::Exploring;
  Cell target{};       // Following: the cell to go to; Holding: `at`
  double sensed = 0.0;  // pheromone of `target` (Following / Holding), else of `at`
};
RavankarChoice ravankar_follower_choice(Cell at, const std::function<std::optional<float>(Cell)>& value,
                                        const std::function<bool(Cell)>& visited, const RavankarFollowerParams& p);

// --- the policy (policy.cpp), reached through the room's entry of the policy
// table, kRavankarPolicy (defined in src/scenario.cpp)
extern const PolicyEntry kRavankarPolicy;
PolicyTraits ravankar_traits(const ScenarioConfig& s);
std::unique_ptr<UavPolicy> make_ravankar_uav(const ScenarioConfig& s, const MapGeometry& geo, const World& world, uint32_t id);
std::unique_ptr<PlaceModel> make_ravankar_place(const ScenarioConfig& s, const MapGeometry& geo, RegionId region);
std::map<std::string, double> ravankar_field_summary(const ScenarioConfig& s, const FieldLookup& value);

}  // namespace pheromesh::core
