// Shao 2020 ACO direction choice (Shao 2020 eq. (9), Shao 2020 eq. (10), Shao 2020 eq. (11)) over five headings.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

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

// --- shao_search_frontier (ours, not the paper's; docs/policies/shao.md) ---
// The paper's path pheromone starts at σ0 everywhere and only decreases
// within D0 of a UAV (Shao 2020 eq. (5), Shao 2020 eq. (7), no recovery term), and D0 = SD in
// Shao 2020 Table 1: a cell whose σ is below σ0 has been inside some UAV's sensor
// range. The variant reads it as a shared visited map and flies to the
// forward heading that brings the most unvisited cells into its sensor
// range, or, when none does, towards the nearest unvisited cell, with the
// paper's kinematics (the five forward headings of Shao 2020 eq. (10)).
struct VisitedMap {
  int32_t width = 0, height = 0;
  std::vector<uint8_t> visited;  // row-major, 1 = known visited
  [[nodiscard]] bool in_map(Cell c) const { return c.x >= 0 && c.y >= 0 && c.x < width && c.y < height; }
  [[nodiscard]] bool is_visited(Cell c) const {
    return visited[static_cast<std::size_t>(c.y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(c.x)] != 0;
  }
};
// New cells a step to `next` brings into the sensor disk (radius sd,
// Euclidean): the unvisited in-map cells within sd of `next`.
int32_t coverage_gain(Cell next, const VisitedMap& m, double sd);
// The forward candidate (index 0..4 = turn -2..2 eighths, as
// evaluate_candidates) with the largest coverage_gain among those not
// `blocked`; ties go to the smaller |turn|, then the clockwise (negative)
// turn. nullopt when no candidate gains a cell (then fly to the nearest
// unvisited cell).
std::optional<std::size_t> coverage_candidate(Cell pos, Heading heading, const VisitedMap& m, double sd,
                                              const std::function<bool(Cell)>& blocked);
// The nearest (8-connected steps through cells not `blocked`) unvisited cell
// from `pos`; among equally near ones the first reached in breadth-first
// order with neighbours taken E, NE, N, NW, W, SW, S, SE. nullopt if every
// reachable cell is visited.
std::optional<Cell> nearest_unvisited(Cell pos, const VisitedMap& m, const std::function<bool(Cell)>& blocked);
// Which of the five forward candidates (index 0..4 = turn -2..2 eighths, as
// evaluate_candidates) brings the UAV nearest to `goal` by 8-connected steps
// through unblocked cells; ties go to the smaller |turn|, then the
// clockwise (negative) turn. nullopt if no accessible candidate can reach it.
std::optional<std::size_t> frontier_candidate(Cell pos, Heading heading, Cell goal, int32_t width, int32_t height,
                                              const std::function<bool(Cell)>& blocked);

}  // namespace pheromesh::core
