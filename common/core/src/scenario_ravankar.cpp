// Placeholder parser for scenario.policy.ravankar (see policy_ravankar.cpp).
#include "scenario_internal.hpp"

namespace pheromesh::core::scenario_detail {

void build_ravankar(const pb::RavankarPolicy& /*msg*/, const Node& n, Validator& v, ScenarioConfig& /*cfg*/) {
  v.fail(n, "the ravankar policy is not available in this build yet");
}

}  // namespace pheromesh::core::scenario_detail
