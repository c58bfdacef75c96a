// The policy registry: the one place besides the scenario parser that knows
// every paper. It turns a scenario's PolicyKind into that paper's traits,
// UAV policy, place model and field summary (each room's policy.hpp).
#include <map>
#include <memory>
#include <string>

#include "pheromesh/core/policy.hpp"
#include "pheromesh/duan/policy.hpp"
#include "pheromesh/liu/policy.hpp"
#include "pheromesh/ravankar/policy.hpp"
#include "pheromesh/shao/policy.hpp"
#include "pheromesh/shostak/policy.hpp"

namespace pheromesh::core {

// ------------------------------------------------------------------ dispatch
namespace {
PolicyTraits traits_of(const ScenarioConfig& s) {
  switch (s.policy) {
    case PolicyKind::ShaoSearch: return shao_search_traits(s);
    case PolicyKind::ShaoNavigation: return shao_navigation_traits(s);
    case PolicyKind::Liu: return liu_traits(s);
    case PolicyKind::Shostak: return shostak_traits(s);
    case PolicyKind::Ravankar: return ravankar_traits(s);
    case PolicyKind::Duan: return duan_traits(s);
  }
  return shao_search_traits(s);
}
}  // namespace

PolicyTraits policy_traits(const ScenarioConfig& s) {
  PolicyTraits t = traits_of(s);
  // The leader's state (Shao 2020 Sec. 5), "target found" (Shostak), the ETA
  // intervals (Duan 2009 eq. (4)); the other policies never broadcast.
  t.broadcasts = s.policy == PolicyKind::ShaoNavigation || s.policy == PolicyKind::Shostak || s.policy == PolicyKind::Duan;
  t.layer_ranges.resize(t.layers.size(), ValueRange{0.0F, kMaxLayerValue});
  return t;
}

Cell uav_start(const ScenarioConfig& s, const PolicyTraits& traits, uint32_t id) {
  return id < traits.starts.size() ? traits.starts[id] : start_cell(s, id);
}

std::unique_ptr<UavPolicy> make_uav_policy(const ScenarioConfig& s, const MapGeometry& geo, const World& world,
                                           uint32_t id) {
  switch (s.policy) {
    case PolicyKind::ShaoSearch: return make_shao_search_uav(s, geo, world, id);
    case PolicyKind::ShaoNavigation: return make_shao_navigation_uav(s, geo, world, id);
    case PolicyKind::Liu: return make_liu_uav(s, geo, world, id);
    case PolicyKind::Shostak: return make_shostak_uav(s, geo, world, id);
    case PolicyKind::Ravankar: return make_ravankar_uav(s, geo, world, id);
    case PolicyKind::Duan: return make_duan_uav(s, geo, world, id);
  }
  return make_shao_search_uav(s, geo, world, id);
}

std::unique_ptr<PlaceModel> make_place_model(const ScenarioConfig& s, const MapGeometry& geo, RegionId region) {
  switch (s.policy) {
    case PolicyKind::ShaoSearch: return make_shao_place(s, geo, region, false);
    case PolicyKind::ShaoNavigation: return make_shao_navigation_place(s, geo, region);
    case PolicyKind::Liu: return make_liu_place(s, geo, region);
    case PolicyKind::Shostak: return make_shostak_place(s, geo, region);
    case PolicyKind::Ravankar: return make_ravankar_place(s, geo, region);
    case PolicyKind::Duan: return make_duan_place(s, geo, region);
  }
  return make_shao_place(s, geo, region, false);
}

std::map<std::string, double> field_summary(const ScenarioConfig& s, const FieldLookup& value) {
  switch (s.policy) {
    case PolicyKind::ShaoSearch: return {};
    case PolicyKind::ShaoNavigation: return shao_navigation_field_summary(s, value);
    case PolicyKind::Liu: return liu_field_summary(s, value);
    case PolicyKind::Shostak: return shostak_field_summary(s, value);
    case PolicyKind::Ravankar: return ravankar_field_summary(s, value);
    case PolicyKind::Duan: return duan_field_summary(s, value);
  }
  return {};
}

}  // namespace pheromesh::core
