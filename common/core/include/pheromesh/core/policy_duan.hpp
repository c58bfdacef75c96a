// Scenario parameters of the Duan 2009 Max-Min ACO replanning policy (policy_duan.cpp).
#pragma once

namespace pheromesh::core {

struct DuanConfig {};

}  // namespace pheromesh::core
