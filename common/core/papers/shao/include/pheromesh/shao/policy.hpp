// Scenario parameters of the Shao 2020 navigation policy (Shao 2020 Sec. 5): a leader on
// vector or scalar pheromones, followers flocking (shao/src/navigation_policy.cpp).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/policy_table.hpp"
#include "pheromesh/shao/navigation.hpp"

namespace pheromesh::core {

struct ShaoNavigationConfig final : PolicyConfig {
  static constexpr std::string_view kPolicy = "shao_navigation";
  [[nodiscard]] std::string_view policy() const override { return kPolicy; }

  ShaoNavParams params;  // Shao 2020 Table 2
  LeaderPheromones leader = LeaderPheromones::Vector;
  Cell region_centre{};  // centre of the target region [cell]
  // The swarm holds its start positions for this many ticks while the
  // place agents build up the potential field (the paper starts with a field).
  uint32_t hold_ticks = 0;
};

// --- Shao 2020 Sec. 4 search (search_policy.cpp): it reads
// ScenarioConfig::layers and ::aco. Without a config (policy_config null)
// it is the paper's pheromone search; `policy { shao_search { search: ... } }`
// (or a program) sets a ShaoSearchConfig to fly the exhaustive fixed-route
// baseline of Shao 2020 Sec. 4.3.3 instead (lawnmower.hpp) or our variant
// shao_search_frontier, with the same place agents, sensor and speed.
enum class ShaoRoute : uint8_t {
  Pheromone,         // Shao 2020 Algorithm 1 ("pheromone")
  LawnmowerTransit,  // fixed boustrophedon strips, flown from the start area ("lawnmower_transit")
  Frontier,          // shao_search_frontier, ours ("frontier", docs/policies/shao.md)
};
struct ShaoSearchConfig final : PolicyConfig {
  static constexpr std::string_view kPolicy = "shao_search";
  [[nodiscard]] std::string_view policy() const override { return kPolicy; }
  ShaoRoute route = ShaoRoute::Pheromone;
  // Shao 2020 Algorithm 1 line 4, "go there, mark them": false (default, our
  // reading) marks a target as soon as it is within the sensor radius; true
  // flies onto the target's cell first (`mark: "on_arrival"`). Acquisition
  // (first detection) is the same in both.
  bool mark_on_arrival = false;
};
// The route of a Shao search scenario (Pheromone without a config).
ShaoRoute shao_route(const ScenarioConfig& s);
bool shao_mark_on_arrival(const ScenarioConfig& s);

// The search's entry of the policy table (defined in src/scenario.cpp); the
// policy of a scenario without `policy` (kDefaultPolicy).
extern const PolicyEntry kShaoSearchPolicy;
PolicyTraits shao_search_traits(const ScenarioConfig& s);
std::unique_ptr<UavPolicy> make_shao_search_uav(const ScenarioConfig& s, const MapGeometry& geo, const World& world,
                                                uint32_t id);
// A Shao searcher that starts at `at` with `heading` (0..7): what a
// navigating UAV becomes once the leader is at the target region
// (Shao 2020 Algorithm 3 lines 1-2).
std::unique_ptr<UavPolicy> make_shao_search_uav_at(const ScenarioConfig& s, const MapGeometry& geo, const World& world,
                                                   uint32_t id, Cell at, uint8_t heading);
// `beacons`: targets emit target pheromone and obstacles obstacle pheromone
// from the start (the navigation scenario's potential field).
std::unique_ptr<PlaceModel> make_shao_place(const ScenarioConfig& s, const MapGeometry& geo, RegionId region,
                                            bool beacons);

// --- Shao 2020 Sec. 5 navigation (navigation_policy.cpp), reached through its
// entry of the policy table (defined in src/scenario.cpp)
extern const PolicyEntry kShaoNavigationPolicy;
PolicyTraits shao_navigation_traits(const ScenarioConfig& s);
std::unique_ptr<UavPolicy> make_shao_navigation_uav(const ScenarioConfig& s, const MapGeometry& geo, const World& world, uint32_t id);
std::unique_ptr<PlaceModel> make_shao_navigation_place(const ScenarioConfig& s, const MapGeometry& geo, RegionId region);
std::map<std::string, double> shao_navigation_field_summary(const ScenarioConfig& s, const FieldLookup& value);

}  // namespace pheromesh::core
