// Shao 2020 ACO direction choice (Shao 2020 eq. (9), Shao 2020 eq. (10), Shao 2020 eq. (11)) over five headings.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/heading.hpp"
#include "pheromesh/core/rng.hpp"
#include "pheromesh/core/shao_params.hpp"

namespace pheromesh::core {

// What a UAV knows locally: pheromone values of cells in its neighbourhood
// (from the tiles it received) and cells it knows to be obstacles.
struct LocalView {
  // Target, obstacle and path pheromone at c; nullopt if the UAV has no tile for c.
  std::function<std::optional<std::array<float, 3>>(Cell)> pheromones;
  std::function<bool(Cell)> blocked;  // obstacle known at c (or outside the map)
};

struct Candidate {
  Heading heading = Heading::E;
  Cell next{};
  int turn_eighths = 0;        // -2..2, θ = 45°·|turn|
  bool accessible = false;     // next is in J_ik
  double eta = 0.0;            // η_ijk, Shao 2020 eq. (10), Shao 2020 eq. (11)
  double tau = 0.0;            // mean target pheromone in the sector
  double eps = 0.0;            // mean obstacle pheromone in the sector
  double sigma = 0.0;          // mean path pheromone in the sector
  double attractiveness = 0.0; // max(λTa τ + λTh ε + λTr σ, floor)
  double probability = 0.0;    // P_ijk, Shao 2020 eq. (9), information sub-group
  double random_probability = 0.0;  // physical costs only (random sub-group)
};

// η_ij of Shao 2020 eq. (11) for a step of squared length d2 (1 or 2).
double eta_distance(int32_t d2);
// Turn coefficient of Shao 2020 eq. (10) for |turn| = 0, 1, 2 eighths; 0 otherwise.
double eta_turn(int abs_turn_eighths);

// Evaluates the five candidates from `pos` with current `heading`.
std::array<Candidate, 5> evaluate_candidates(Cell pos, Heading heading, const LocalView& view,
                                             const ShaoAcoParams& p);

struct Decision {
  std::optional<Candidate> chosen;  // nullopt: no accessible candidate (stay)
  bool random_group = false;
};
// One step of Shao 2020 Algorithm 1 lines 10-11: draws the sub-group, then the
// information sub-group takes the most probable candidate (ties broken by
// the stream) and the random sub-group draws by physical costs only.
Decision decide(Cell pos, Heading heading, const LocalView& view, const ShaoAcoParams& p, Rng& rng);

}  // namespace pheromesh::core
