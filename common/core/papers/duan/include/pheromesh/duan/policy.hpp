// Scenario parameters of the Duan 2009 Max-Min ACO replanning policy
// (duan/src/policy.cpp, docs/policies/duan.md). The map cells are the nodes of the
// paper's 2-D mesh (cell (x, y) = node L(x, y) at (x, y) · node_spacing_km).
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/policy_table.hpp"
#include "pheromesh/duan/aco.hpp"

namespace pheromesh::core {

// A threat that appears during the run (Duan 2009 Table 4).
struct DuanPopup {
  Threat threat;
  uint32_t appear_tick = 0;  // [tick] announced to every UAV at this tick (Duan 2009 Sec. 4: "shared immediately")
};

// One UAV's mission (Duan 2009 Table 2), in mesh nodes = cells.
struct DuanMission {
  Cell start{};
  Cell target{};
};

struct DuanConfig final : PolicyConfig {
  static constexpr std::string_view kPolicy = "duan";
  [[nodiscard]] std::string_view policy() const override { return kPolicy; }

  double node_spacing_km = 2.0;  // [km] mesh spacing: 60 x 70 km at 2 km = 31 x 36 nodes (Duan 2009 Sec. 4)
  double f = kDuanThreatWeight;  // Duan 2009 eq. (3)
  // α, β, ρ, Q, Nc_max, m, τ_min, τ_max, the turn limit, candidates, deposit rule.
  DuanAcoParams aco;
  SpeedLimits speeds;             // V_min, V_max [m/s] (Duan 2009 Sec. 4)
  double dt_s = 1.0;              // [s] flight time of one tick (planning ticks are ACO iterations)
  uint32_t eta_wait_ticks = 10;   // [tick] realtime: coordinate with the intervals present after this long
  std::vector<Threat> threats;    // Duan 2009 Table 1, positions [km]
  std::vector<DuanPopup> popups;  // Duan 2009 Table 4
  std::vector<DuanMission> uavs;  // one per UAV of the swarm
};

// --- the policy (policy.cpp), reached through the room's entry of the policy
// table, kDuanPolicy (defined in src/scenario.cpp)
extern const PolicyEntry kDuanPolicy;
PolicyTraits duan_traits(const ScenarioConfig& s);
std::unique_ptr<UavPolicy> make_duan_uav(const ScenarioConfig& s, const MapGeometry& geo, const World& world, uint32_t id);
std::unique_ptr<PlaceModel> make_duan_place(const ScenarioConfig& s, const MapGeometry& geo, RegionId region);
std::map<std::string, double> duan_field_summary(const ScenarioConfig& s, const FieldLookup& value);

}  // namespace pheromesh::core

// Small pure pieces of duan/src/policy.cpp, exposed for the unit tests.
namespace pheromesh::core::duan_detail {

// Layers of the Duan place model (TileState.layer).
enum DuanLayer : int {
  kPointSum = 0,   // Σ over the swarm's UAVs of their point pheromone τ^p at the node (Duan 2009 eq. (10))
  kThreat = 1,     // mean Duan 2009 eq. (2) J_threat of the node's edges under the threats present (display)
  kEtaS = 2,       // report at a UAV's target node: T_a of its first agreed plan [s]
  kPlannedKm = 3,  // report at a UAV's target node: length of its first agreed trajectory [km]
  kArrivalS = 4,   // report at a UAV's target node: flight time from take-off to arrival [s]
  kFlownKm = 5,    // report at a UAV's target node: distance flown from start to target [km]
  kDuanLayerCount = 6,
};
const char* layer_name(int layer);

// Duan 2009 eq. (10) input at one node: Σ_{j≠i} τ^p_j from the published Σ_j τ^p_j
// minus this UAV's own share. The place counts a UAV that set no value at the
// node with τ_min (the floor its pheromone sits at), and a set value arrives
// as a float: the own share is float(own) where own != τ_min, else τ_min.
double others_point_sum(float published_sum, double own_tau, double tau_min);

// Contents of an EtaIntervals broadcast: the planning phase, then
// (T_min, T_max) of Duan 2009 eq. (4) per candidate length [km], in the given order.
std::vector<double> eta_broadcast(uint32_t phase, const std::vector<double>& lengths_km, const SpeedLimits& speeds);

struct EtaDecision {
  bool agreed = false;        // S (Duan 2009 eq. (6)) was not empty
  double eta_s = 0.0;         // T_a [s] (min S; fallback: max_i min_j T_min,ij)
  std::size_t chosen = 0;     // index of this UAV's candidate
  double speed_mps = 0.0;     // V = L / T_a, within the limits
};
// Duan 2009 eq. (5), Duan 2009 eq. (6) and Duan 2009 Fig. 6 on the broadcasts (values after the phase number,
// by UAV id; empty entries = UAVs without candidates are left out), then this
// UAV's cheapest candidate feasible at T_a (candidates are cost-ascending).
// nullopt if `self` has no candidates.
std::optional<EtaDecision> decide_eta(const std::map<uint32_t, std::vector<double>>& intervals, uint32_t self,
                                      const std::vector<double>& own_lengths_km, const SpeedLimits& speeds);

// Mean Duan 2009 eq. (2) J_threat over the edges of node (x, y) of a columns x rows
// mesh with spacing `spacing_km`.
double node_threat(std::span<const Threat> threats, int32_t x, int32_t y, int32_t columns, int32_t rows,
                   double spacing_km);

}  // namespace pheromesh::core::duan_detail
