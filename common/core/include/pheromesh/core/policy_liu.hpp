// Scenario parameters of the Liu 2022 ESUSTPM policy (policy_liu.cpp).
#pragma once

namespace pheromesh::core {

struct LiuConfig {};

}  // namespace pheromesh::core
