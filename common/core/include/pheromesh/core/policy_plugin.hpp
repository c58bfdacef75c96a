// A policy from a shared library: what a plugin defines and exports
// (docs/writing-a-policy.md walks through examples/repulsive_coverage).
//
// A plugin is a shared library built against the installed package
// (find_package(pheromesh), target pheromesh::core). It defines one
// PluginPolicy and exports it with one line:
//
//   PHEROMESH_POLICY_PLUGIN(kMyPolicy)
//
// A scenario names it:
//
//   policy { plugin { library: "libmy_policy.so" name: "my_policy"
//                     config { key: "evaporation" number: 0.02 } } }
//
// and every program that loads the scenario (sim, validate, run and the
// processes it starts, experiment, sweep) loads the library, checks its ABI
// version and SHA-256, and adds the entry to the policy table
// (policy_table.hpp), where find_policy finds it like a built-in one.
//
// The library runs inside pheromesh's processes and shares their types
// (ScenarioConfig, PolicyTraits, UavPolicy, PlaceModel, the messages), so it
// must be built against the same headers: kPolicyPluginAbi says which.
#pragma once

#include <cstdint>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/world.hpp"

namespace pheromesh::core {

// The plugin ABI. Bump it when anything a plugin compiles against changes
// its layout or its virtual functions: PluginPolicy, PluginConfig,
// ScenarioConfig, PolicyConfig, PolicyTraits, UavPolicy, UavView,
// UavActions, PlaceModel, HaloRing, TileCache, MapGeometry, World and the
// messages (messages.hpp) — or the meaning of a deposit kind. A loader
// refuses a library of another version, naming both. (A change that only adds
// a free function does not need a bump.)
// 3: PlaceModel::copy_rect; 4: ClockMsg::served, neighbours by pose; 5: PolicyTraits::reads_neighbours
inline constexpr uint32_t kPolicyPluginAbi = 5;

// A second guard beside the version, in case a bump was forgotten: the sizes
// of the types a plugin shares with pheromesh, folded into one number. A
// loader refuses a library whose fingerprint differs from its own.
constexpr uint64_t policy_plugin_layout() {
  uint64_t h = 1469598103934665603ULL;  // FNV-1a over the sizes
  for (const uint64_t v : {sizeof(ScenarioConfig), sizeof(PolicyTraits), sizeof(UavView), sizeof(UavActions),
                           sizeof(DepositMsg), sizeof(UavStateMsg), sizeof(BroadcastMsg), sizeof(DetectionMsg),
                           sizeof(TargetEventMsg), sizeof(TileMsg), sizeof(HaloRing), sizeof(TileCache),
                           sizeof(MapGeometry), sizeof(World), sizeof(std::string), sizeof(std::shared_ptr<int>)}) {
    h = (h ^ v) * 1099511628211ULL;
  }
  return h;
}

// The scenario's `config { key: ... number|text|flag: ... }` parameters, as
// the plugin's parse function reads them. Every error names the scenario
// file, the line and the field path of the parameter, like the errors of the
// built-in policies; the host collects them and refuses the scenario with all
// of them. A parameter the plugin never asks for is an error too (a typo must
// not silently run the default).
class PluginConfig {
 public:
  virtual ~PluginConfig() = default;
  // The value of parameter `key`, nullopt when the scenario does not set it.
  // A parameter of another kind (text where a number is asked) is an error at
  // its line, and nullopt.
  virtual std::optional<double> number(std::string_view key) = 0;
  virtual std::optional<std::string> text(std::string_view key) = 0;
  virtual std::optional<bool> flag(std::string_view key) = 0;
  // An error about parameter `key` (at its line; at the `plugin` block when
  // it is absent): "FILE:LINE:COL: field 'policy.plugin.config[2]' (key
  // "evaporation"): WHAT".
  virtual void fail(std::string_view key, std::string_view what) = 0;

  // `key` as a number in [lo, hi] (closed), `fallback` when absent; an error
  // saying the range when outside it (nan and infinities are outside).
  double number_in(std::string_view key, double fallback, double lo, double hi) {
    const std::optional<double> v = number(key);
    if (!v) return fallback;
    if (!(*v >= lo && *v <= hi)) {
      fail(key, "must be in [" + format(lo) + ", " + format(hi) + "] (got " + format(*v) + ")");
      return fallback;
    }
    return *v;
  }

 protected:
  static std::string format(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
  }
  PluginConfig() = default;
  PluginConfig(const PluginConfig&) = default;
  PluginConfig& operator=(const PluginConfig&) = default;
};

// What a plugin exports: PolicyEntry (policy_table.hpp) with a parser of the
// plugin's `config` in place of the built-in parsers of scenario.proto.
struct PluginPolicy {
  // The policy's name: `plugin { name: }` must say it, reports and the console
  // show it. Not the name of a built-in policy.
  std::string_view name;
  // One line for `pheromesh validate`: what the policy does.
  std::string_view summary;
  // Reads the scenario's parameters into `cfg` (cfg.set_policy_config(MyConfig{...}),
  // MyConfig::kPolicy == name); errors through `config`. The rest of `cfg`
  // (map, swarm, run) is read and valid when it is called.
  void (*parse)(PluginConfig& config, ScenarioConfig& cfg);
  // As in PolicyEntry: layers, radii, plausibility; UAV policy and place
  // model factories; the final field's judging numbers (may be null).
  PolicyTraits (*traits)(const ScenarioConfig& s);
  bool broadcasts;
  std::unique_ptr<UavPolicy> (*make_uav)(const ScenarioConfig& s, const MapGeometry& geo, const World& world,
                                         uint32_t id);
  std::unique_ptr<PlaceModel> (*make_place)(const ScenarioConfig& s, const MapGeometry& geo, RegionId region);
  std::map<std::string, double> (*field_summary)(const ScenarioConfig& s, const FieldLookup& value);
};

// The symbols PHEROMESH_POLICY_PLUGIN exports and a loader looks up.
inline constexpr const char* kPluginAbiSymbol = "pheromesh_policy_plugin_abi";
inline constexpr const char* kPluginLayoutSymbol = "pheromesh_policy_plugin_layout";
inline constexpr const char* kPluginEntrySymbol = "pheromesh_policy_plugin";

}  // namespace pheromesh::core

// Exports `entry` (a PluginPolicy with static storage) from a plugin library:
// three extern "C" functions, the ABI version and layout the library was
// built with, and the entry. Use it once per library, at namespace scope.
#define PHEROMESH_POLICY_PLUGIN(entry)                                                                        \
  extern "C" __attribute__((visibility("default"))) uint32_t pheromesh_policy_plugin_abi() {                 \
    return ::pheromesh::core::kPolicyPluginAbi;                                                               \
  }                                                                                                           \
  extern "C" __attribute__((visibility("default"))) uint64_t pheromesh_policy_plugin_layout() {              \
    return ::pheromesh::core::policy_plugin_layout();                                                         \
  }                                                                                                           \
  extern "C" __attribute__((visibility("default"))) const ::pheromesh::core::PluginPolicy*                   \
  pheromesh_policy_plugin() {                                                                                 \
    return &(entry);                                                                                          \
  }
