// Small threat meshes for the tests of the Duan 2009 planners' variants
// (test_duan_line_of_sight.cpp, test_duan_safe_line_of_sight.cpp).
#pragma once

#include <numbers>
#include <optional>
#include <vector>

#include "pheromesh/duan/aco.hpp"

namespace pheromesh::core::duan_test {

inline constexpr double kEps = 1e-9;
inline constexpr double kQuarterPi = std::numbers::pi / 4.0;

// A mesh with 2 km spacing over [0, w] x [0, h] km.
inline ThreatMesh mesh_of(double w_km, double h_km, std::vector<Threat> threats = {}) {
  return ThreatMesh(MeshSpec{{0.0, 0.0},
                             w_km,
                             h_km,
                             static_cast<int32_t>(w_km / 2.0),
                             static_cast<int32_t>(h_km / 2.0),
                             kDuanThreatWeight},
                    std::move(threats));
}

// The node nearest (x, y) km.
inline NodeId at(const ThreatMesh& m, double x_km, double y_km) { return *m.nearest_node({x_km, y_km}); }

// Every corner of `previous` (if any) followed by `p` turns by at most `limit`.
inline bool turns_within(const ThreatMesh& m, const std::vector<NodeId>& p, std::optional<NodeId> previous,
                         double limit) {
  std::vector<NodeId> q;
  if (previous) q.push_back(*previous);
  q.insert(q.end(), p.begin(), p.end());
  for (std::size_t i = 2; i < q.size(); ++i) {
    if (!turn_allowed(m.position(q[i - 2]), m.position(q[i - 1]), m.position(q[i]), limit)) return false;
  }
  return true;
}

}  // namespace pheromesh::core::duan_test
