// Placeholder parser for scenario.policy.liu (see policy_liu.cpp).
#include "scenario_internal.hpp"

namespace pheromesh::core::scenario_detail {

void build_liu(const pb::LiuPolicy& /*msg*/, const Node& n, Validator& v, ScenarioConfig& /*cfg*/) {
  v.fail(n, "the liu policy is not available in this build yet");
}

}  // namespace pheromesh::core::scenario_detail
