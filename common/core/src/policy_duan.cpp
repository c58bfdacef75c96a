// Placeholder: the Duan policy is not wired into scenarios yet. scenario_duan.cpp
// refuses scenario.policy.duan, so none of these is ever called.
#include <stdexcept>

#include "pheromesh/core/policy.hpp"

namespace pheromesh::core {

PolicyTraits duan_traits(const ScenarioConfig& s) { return shao_search_traits(s); }
std::unique_ptr<UavPolicy> make_duan_uav(const ScenarioConfig& /*s*/, const MapGeometry& /*geo*/, const World& /*world*/,
                                         uint32_t /*id*/) {
  throw std::logic_error("policy duan is not available");
}
std::unique_ptr<PlaceModel> make_duan_place(const ScenarioConfig& /*s*/, const MapGeometry& /*geo*/, RegionId /*region*/) {
  throw std::logic_error("policy duan is not available");
}
std::map<std::string, double> duan_field_summary(const ScenarioConfig& /*s*/, const FieldLookup& /*value*/) { return {}; }

}  // namespace pheromesh::core
