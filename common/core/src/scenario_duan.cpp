// Placeholder parser for scenario.policy.duan (see policy_duan.cpp).
#include "scenario_internal.hpp"

namespace pheromesh::core::scenario_detail {

void build_duan(const pb::DuanPolicy& /*msg*/, const Node& n, Validator& v, ScenarioConfig& /*cfg*/) {
  v.fail(n, "the duan policy is not available in this build yet");
}

}  // namespace pheromesh::core::scenario_detail
