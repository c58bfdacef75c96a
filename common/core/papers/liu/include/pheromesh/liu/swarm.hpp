// Liu 2022 (ESUSTPM), Liu 2022 Sec. 5: the whole simulation — 10 UAVs on a 10x10
// grid for 200 time cycles, with three static targets (Liu 2022 Sec. 5.2, Liu 2022 Sec. 5.3) or none
// (Liu 2022 Sec. 5.1), a noisy sensor, a shared target probability map (TPM) and one of
// the five search policies of Liu 2022 Sec. 5. Built only from the pure pieces of
// pheromesh/liu/tpm.hpp; deterministic for a seed (pheromesh::core::Rng streams).
//
// Time and motion (Liu 2022 Algorithm 1, Liu 2022 eq. (10), Liu 2022 eq. (11), Liu 2022 eq. (12), Liu 2022 eq. (13), Liu 2022 eq. (14)), with LiuParams' reading of the
// paper's time scales:
//  * every time cycle (cycle_s = 1 s, ours) each UAV decides a velocity once,
//    from the state at the start of the cycle (all UAVs at once) — Liu 2022 Sec. 5.1.2 "the
//    directions of the UAV agents are random, and the step size is constant in
//    each cycle";
//  * the UAV then flies that velocity for the cycle in steps of Δt = 10 ms
//    (Liu 2022 eq. (10), Liu 2022 eq. (11), advance_uav: reflected at the map border);
//  * the sensor looks at a cell each time a UAV *enters* it (the TPM is
//    updated once per cell entry, Liu 2022 eq. (4), Liu 2022 eq. (5)), not once per Δt or per cycle:
//    that is the reading under which pheromesh/liu/tpm.hpp's EU fits Liu 2022 Table 2 (the mower
//    enters each cell once or twice: 52.34). The start cell is not observed
//    (the UAV has not "arrived" in it), but it counts as visited.
// Mower (Liu 2022 eq. (14)): UAV i sweeps its lane (lawnmower_lane) along x at l, b
// reversed at the map border; a lane of more than one row is climbed to the
// next row's centre line at the border. 10 UAVs on 10 rows: one row each,
// exactly Liu 2022 eq. (14). Mowers start at the centre of their lane's lower-left cell,
// not at Liu 2022 Sec. 5's start positions (which cover only rows 1-5).
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "pheromesh/core/result.hpp"
#include "pheromesh/liu/tpm.hpp"

namespace pheromesh::core {

enum class LiuPolicy : uint8_t {
  kEsustpm,      // Liu 2022 eq. (6), Liu 2022 eq. (7), Liu 2022 eq. (8), Liu 2022 eq. (9), esustpm_step
  kLawnmower,    // Liu 2022 eq. (14)
  kRandom,       // Liu 2022 eq. (12), Liu 2022 eq. (13), random_search_step
  kBoids,        // Liu 2022 Sec. 5.1.4, boids_step
  kGuidedBoids,  // Liu 2022 Sec. 5.1.5, boids_guided_step
  // Ours, not the paper's: ESUSTPM whose neighbour rules only repel
  // (esustpm_disperse_step, docs/policies/liu.md).
  kEsustpmDisperse,
};
std::string_view to_string(LiuPolicy p);

enum class LiuPrior : uint8_t {
  kUniform,   // every cell at params.initial_probability (0.5, Liu 2022 Sec. 5)
  kAccurate,  // Liu 2022 eq. (2) mixture, one component on the cell of each real target (Liu 2022 Sec. 5.3.1)
  kWrong,     // Liu 2022 eq. (2) mixture on LiuSwarmConfig::wrong_prior_centres (Liu 2022 Sec. 5.3.2)
};
std::string_view to_string(LiuPrior p);

// What the sensor reports when a UAV enters a cell.
enum class LiuSensor : uint8_t {
  // Detection with probability P_d on a target cell, false alarm with P_f
  // elsewhere (Liu 2022 Sec. 2.1), drawn from the run's sensor stream.
  kNoisy,
  // Liu 2022 Algorithm 1 as printed: Liu 2022 eq. (4) on a target cell, Liu 2022 eq. (5) elsewhere — the
  // update branches on the truth, so P_d and P_f only enter the equations.
  kAlgorithm1,
};

// Velocity of the UAVs at cycle 0 (the paper does not say).
enum class LiuStartVelocity : uint8_t {
  // Max speed along Liu 2022 eq. (12)'s random direction, from the UAV's stream: Liu 2022 Sec. 2.2
  // "mass points with the maximum velocity".
  kRandomHeading,
  // At rest. On Liu 2022 Sec. 5's start lattice (100 m apart) Boids without guidance are
  // then in equilibrium (separation and cohesion cancel) and never move.
  kRest,
};

struct LiuSwarmConfig {
  LiuParams params;  // grid, UAV count, cycles, sensor, θ, rule constants
  LiuPolicy policy = LiuPolicy::kEsustpm;
  // Real targets [m]; a target is in the cell cell_of(position). Empty = the
  // no-target variant of Liu 2022 Sec. 5.1.
  std::vector<Vec2> targets{kLiuTargets.begin(), kLiuTargets.end()};
  // Start positions [m] of UAVs 0..uav_count-1 (not used by the mower).
  std::vector<Vec2> starts{kLiuStartPositions.begin(), kLiuStartPositions.end()};
  LiuPrior prior = LiuPrior::kUniform;
  // Where the kWrong prior expects targets [m]. Default: Liu 2022 Sec. 5.3's three prior
  // targets; pair it with `targets` that differ (Liu 2022 Fig. 27a: the one at
  // (700, 500) absent; Liu 2022 Fig. 27b: the only target at (300, 200)).
  std::vector<Vec2> wrong_prior_centres{kLiuTargets.begin(), kLiuTargets.end()};
  // Mixture components: the paper gives neither σ0 nor α_i. Ours: σ0 = one
  // cell, α_i = 1 (each expected target is one unit of probability mass, so a
  // cell's value is the chance that the target lies in it: 0.147 at the
  // centre). Components are centred on the centre of the cell holding the
  // coordinate — Liu 2022 Sec. 5.3.2 speaks of "the grid (700, 500)".
  double prior_sigma_cells = 1.0;  // σ0 [cell]
  double prior_weight = 1.0;       // α_i
  // Liu 2022 Sec. 4: "After the targets are found, the agents will continue to execute the
  // coverage of the remaining area": a confirmed cell (P > θ once) is no
  // longer a guidance candidate for rule 4 / guided Boids. Its TPM value is
  // still updated and still counts in the EU.
  bool release_confirmed_cells = true;
  LiuSensor sensor = LiuSensor::kNoisy;
  LiuStartVelocity start_velocity = LiuStartVelocity::kRandomHeading;
};

struct LiuSwarmResult {
  int64_t visited_cells = 0;               // Liu 2022 Table 2 "visited grid number" at the end
  double final_eu = 0.0;                   // [bit] environmental_uncertainty of the final TPM
  std::vector<double> eu_per_cycle;        // [bit] index 0 = the prior, k = after cycle k
  std::vector<int64_t> visited_per_cycle;  // index 0 = start cells, k = after cycle k
  std::vector<uint32_t> found_per_cycle;   // real targets confirmed by the end of cycle k
  uint32_t targets_found = 0;              // real targets whose cell was ever confirmed (latched)
  // Per target, in LiuSwarmConfig::targets order: the cycle (1-based) in which
  // its cell's P first exceeded θ; nullopt if never. Targets sharing a cell
  // share a confirmation.
  std::vector<std::optional<uint32_t>> confirmation_cycle;
  // Cycle by which every real target was confirmed; nullopt if some never was
  // (or there are none).
  std::optional<uint32_t> all_found_cycle;
  uint32_t false_confirmations = 0;  // cells with no target that were confirmed
  int64_t observations = 0;          // sensor looks (cell entries)
  std::vector<double> final_tpm;     // row-major grid_width x grid_height
};

// The mower of Liu 2022 eq. (14) in continuous space: along x at l, b reversed at the
// map border; a lane of more than one row is climbed to the next row's
// centre line at the border (see the header comment).
struct LiuMower {
  Rect lane;
  int32_t dx = 1;  // b along x
  int32_t dy = 1;  // row change at the border
  bool climbing = false;
  double climb_to_y = 0.0;  // [m] centre line of the next row
};
// One Δt of the mower.
void mower_advance(LiuMower& m, LiuUav& uav, double dt_s, const LiuParams& p);

// The prior TPM of a configuration (row-major), as the simulation starts it.
std::vector<double> liu_prior_map(const LiuSwarmConfig& config);

// Runs one simulation. Errors for configurations that cannot run: a grid or
// cell size <= 0, fewer start positions than UAVs, a mower with more UAVs
// than rows, sensor probabilities outside [0, 1], a prior component that is
// not a density.
Result<LiuSwarmResult> run_liu_swarm(const LiuSwarmConfig& config, uint64_t seed);

}  // namespace pheromesh::core
