// Scenario parameters of the Shostak GPS-denied stigmergy policy (policy_shostak.cpp).
#pragma once

namespace pheromesh::core {

struct ShostakConfig {};

}  // namespace pheromesh::core
