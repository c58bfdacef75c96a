// Scenario parameters of the Liu 2022 ESUSTPM policy (liu/src/policy.cpp,
// docs/policies/liu.md): the target probability map (TPM) lives in the place
// agents, the UAVs are flocking processes that read it from their tiles.
//
// Units: the scenario map is the Liu grid, one scenario cell = one Liu grid
// cell of `params.cell_size_m` metres; one tick = one Liu "time cycle" of
// `params.cycle_s` seconds, flown in steps of `params.dt_s`.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/policy_table.hpp"
#include "pheromesh/liu/swarm.hpp"
#include "pheromesh/liu/tpm.hpp"

namespace pheromesh::core {

// Where in its start cell (scenario start_cell) a UAV starts.
enum class LiuStartPoint : uint8_t {
  kCentre,  // the cell centre (the framework's convention: integer cell units)
  kCorner,  // the cell's low-x low-y corner, p = cell · cell_size_m: Liu 2022 Sec. 5's start
            // coordinates (100, 100) ... (200, 500) m are such corners
};

struct LiuConfig final : PolicyConfig {
  static constexpr std::string_view kPolicy = "liu";
  [[nodiscard]] std::string_view policy() const override { return kPolicy; }

  // Liu 2022 Table 1 constants, P_d, P_f, θ, speeds, Δt, cycle length, cell size. The
  // grid size and the UAV count are taken from the scenario's map and swarm
  // (the parser copies them in); `cycles` is unused (the run length is
  // run.ticks).
  LiuParams params;
  LiuPolicy search = LiuPolicy::kEsustpm;  // ESUSTPM or a Liu 2022 Sec. 5.1 baseline
  LiuPrior prior = LiuPrior::kUniform;
  // kWrong: where the prior expects targets [cell] (Liu 2022 Sec. 5.3.2).
  std::vector<Cell> wrong_prior_cells;
  double prior_sigma_cells = 1.0;  // σ0 [cell] of Liu 2022 eq. (1), as liu_swarm
  double prior_weight = 1.0;       // α_i of Liu 2022 eq. (2), as liu_swarm
  // Liu 2022 Sec. 4: a confirmed cell is no longer a guidance candidate (as liu_swarm).
  bool release_confirmed_cells = true;
  LiuSensor sensor = LiuSensor::kNoisy;
  LiuStartVelocity start_velocity = LiuStartVelocity::kRandomHeading;
  LiuStartPoint start_point = LiuStartPoint::kCentre;
  // Tiles (and the UAVs over them) a UAV reads [cell]; nullopt = the default
  // of liu_view_radius_cells.
  std::optional<double> view_radius_cells;
};

// Default view radius [cell]: the distance beyond which a neighbour's ESUSTPM
// gain |β_i(d)| (Liu 2022 eq. (7), Liu 2022 eq. (8), Liu 2022 eq. (9)) is below 1e-3 m/s for every rule i, or the Boids
// safe distance, whichever is larger, in cells, rounded up, at least 1 (the
// eight cells around the UAV for rule 4). Liu 2022 Table 1 with 100 m cells: 3.
double liu_view_radius_cells(const LiuParams& p);

// The run_liu_swarm configuration equivalent to a scenario's Liu policy (for
// the prior map and for comparisons): targets and wrong-prior centres at the
// centres [m] of their cells.
LiuSwarmConfig liu_swarm_config_of(const LiuConfig& c, const std::vector<Cell>& targets);

// --- the policy (policy.cpp), reached through the room's entry of the policy
// table, kLiuPolicy (defined in src/scenario.cpp)
extern const PolicyEntry kLiuPolicy;
PolicyTraits liu_traits(const ScenarioConfig& s);
std::unique_ptr<UavPolicy> make_liu_uav(const ScenarioConfig& s, const MapGeometry& geo, const World& world, uint32_t id);
std::unique_ptr<PlaceModel> make_liu_place(const ScenarioConfig& s, const MapGeometry& geo, RegionId region);
std::map<std::string, double> liu_field_summary(const ScenarioConfig& s, const FieldLookup& value);

}  // namespace pheromesh::core
