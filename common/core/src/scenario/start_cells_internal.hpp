// The free cells of a start area, shared by the scenario parser (which checks
// that a swarm fits its start area) and start_cell (which places it). Apart
// from the parser so that start_cell does not link it: a policy plugin calls
// start_cell, and the parser carries the scenario schema's generated code,
// which may be linked into a process only once (policy_plugin.hpp).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "pheromesh/core/grid.hpp"

namespace pheromesh::core::scenario_detail {

// Obstacle intervals [x_begin, x_end) of row y inside `area`, merged and sorted.
std::vector<std::pair<int32_t, int32_t>> blocked_intervals(const Rect& area, const std::vector<Rect>& obstacles, int32_t y);
int64_t free_in_row(const Rect& area, const std::vector<Rect>& obstacles, int32_t y);
int64_t free_cells(const Rect& area, const std::vector<Rect>& obstacles);

}  // namespace pheromesh::core::scenario_detail
