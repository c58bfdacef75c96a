// Placeholder parser for scenario.policy.shostak (see policy_shostak.cpp).
#include "scenario_internal.hpp"

namespace pheromesh::core::scenario_detail {

void build_shostak(const pb::ShostakPolicy& /*msg*/, const Node& n, Validator& v, ScenarioConfig& /*cfg*/) {
  v.fail(n, "the shostak policy is not available in this build yet");
}

}  // namespace pheromesh::core::scenario_detail
