// Test helper shared by the Duan tests: the sharpest turn along a path.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "pheromesh/duan/aco.hpp"

namespace pheromesh::core::testing_duan {

inline double max_turn_of(const ThreatMesh& mesh, const std::vector<NodeId>& nodes) {
  double worst = 0.0;
  for (std::size_t i = 2; i < nodes.size(); ++i) {
    worst = std::max(worst, turn_angle_rad(mesh.position(nodes[i - 2]), mesh.position(nodes[i - 1]),
                                           mesh.position(nodes[i])));
  }
  return worst;
}

}  // namespace pheromesh::core::testing_duan
