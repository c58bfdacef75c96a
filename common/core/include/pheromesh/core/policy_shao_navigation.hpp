// Scenario parameters of the Shao 2020 navigation policy (Shao 2020 Sec. 5): a leader on
// vector or scalar pheromones, followers flocking (policy_shao_navigation.cpp).
#pragma once

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/shao_navigation.hpp"

namespace pheromesh::core {

struct ShaoNavigationConfig {
  ShaoNavParams params;  // Shao 2020 Table 2
  LeaderPheromones leader = LeaderPheromones::Vector;
  Cell region_centre{};  // centre of the target region [cell]
  // The swarm holds its start positions for this many ticks while the
  // place agents build up the potential field (the paper starts with a field).
  uint32_t hold_ticks = 0;
};

}  // namespace pheromesh::core
