// The policy table: one entry per policy, each exported by its paper's room
// (common/core/papers/<paper>/, pheromesh/<paper>/policy.hpp), listed one
// line each in core/src/policy/policy_table.cpp. Everything the rest of pheromesh
// does differently per policy goes through an entry: the scenario parser
// reads `policy { <name> { ... } }` with entry.parse, and policy_traits,
// make_uav_policy, make_place_model and field_summary (policy.hpp) call the
// entry of ScenarioConfig::policy. Nothing outside a room switches on the
// policy.
//
// An entry is a plain struct of a name, a flag and function pointers. A
// policy from a shared library (policy_plugin.hpp) gets one too when a
// scenario loads it (plugin_loader.hpp); find_policy finds it beside the
// built-in ones.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/world.hpp"

namespace google::protobuf {
class Message;
}

namespace pheromesh::core {

// The scenario parser's helpers (core/src/scenario/scenario_internal.hpp): where a
// field stands in the file, and the errors collected with file, line and
// field path.
namespace scenario_detail {
class Node;
class Validator;
}  // namespace scenario_detail

struct PolicyEntry {
  // The member of the scenario's `policy` oneof (common/proto/scenario.proto)
  // that chooses this policy; also its name in reports, logs and the console
  // ("liu"). ScenarioConfig::policy holds it.
  std::string_view name;

  // Reads the member's message (`msg`, at node `n` of the file) into `cfg`:
  // its PolicyConfig (cfg.set_policy_config) and an error through `v` for
  // every bad field. Called after the scenario's other fields are read.
  // Null for a plugin's entry, whose config PluginPolicy::parse reads.
  void (*parse)(const google::protobuf::Message& msg, const scenario_detail::Node& n, scenario_detail::Validator& v,
                ScenarioConfig& cfg);
  // Reads fields outside `policy` that the room owns (Shao: `shao { layers
  // aco }`) from the whole Scenario message; null if none. It runs for every
  // scenario, whatever its policy, so that a file is checked whole, and once
  // for entries that share it, before `parse`.
  void (*parse_scenario_fields)(const google::protobuf::Message& scenario, const scenario_detail::Node& root,
                                scenario_detail::Validator& v, ScenarioConfig& cfg);

  // What the policy looks like from outside (layers, radii, plausibility);
  // policy_traits adds `broadcasts` and the default layer ranges.
  PolicyTraits (*traits)(const ScenarioConfig& s);
  // Its UAVs may broadcast to the swarm (a UAV then creates its writer at start).
  bool broadcasts;
  std::unique_ptr<UavPolicy> (*make_uav)(const ScenarioConfig& s, const MapGeometry& geo, const World& world,
                                         uint32_t id);
  std::unique_ptr<PlaceModel> (*make_place)(const ScenarioConfig& s, const MapGeometry& geo, RegionId region);
  // The final field's judging numbers (metrics.json "field"); null if none.
  std::map<std::string, double> (*field_summary)(const ScenarioConfig& s, const FieldLookup& value);
};

// Every built-in policy, in the order of core/src/policy/policy_table.cpp (no plugin).
std::span<const PolicyEntry* const> policy_table();
// The entry named `name`, built in or of a plugin this process loaded; null if none.
const PolicyEntry* find_policy(std::string_view name);
// The entry of the policy `s` runs. Throws std::logic_error when no entry has
// that name: the scenario parser sets only names of the table, so it is a
// program that set another.
const PolicyEntry& policy_entry(const ScenarioConfig& s);
// "shao_search, shao_navigation, ...": the names of the table, for messages.
std::string policy_names();

}  // namespace pheromesh::core
