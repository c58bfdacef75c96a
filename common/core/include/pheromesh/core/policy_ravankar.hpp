// Scenario parameters of the Ravankar 2016 uncertainty-aware deposition policy (policy_ravankar.cpp).
#pragma once

namespace pheromesh::core {

struct RavankarConfig {};

}  // namespace pheromesh::core
