// A plugin whose policy takes the name of a built-in one ("liu"): refused.
#include "pheromesh/core/policy_plugin.hpp"

namespace {
using namespace pheromesh::core;
void parse(PluginConfig&, ScenarioConfig&) {}
PolicyTraits traits(const ScenarioConfig&) { return {}; }
std::unique_ptr<UavPolicy> make_uav(const ScenarioConfig&, const MapGeometry&, const World&, uint32_t) { return nullptr; }
std::unique_ptr<PlaceModel> make_place(const ScenarioConfig&, const MapGeometry&, RegionId) { return nullptr; }
const PluginPolicy kEntry{.name = "liu", .summary = "", .parse = &parse, .traits = &traits, .broadcasts = false,
                          .make_uav = &make_uav, .make_place = &make_place, .field_summary = nullptr};
}  // namespace

PHEROMESH_POLICY_PLUGIN(kEntry)
