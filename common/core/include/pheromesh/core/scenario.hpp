// Scenario loading: protobuf text format against common/proto/scenario.proto.
// Errors name the file, the line and the field ("f.textproto:12:3: field
// 'map.tile_size': must be between 4 and 32").
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "pheromesh/core/faults.hpp"
#include "pheromesh/core/geodetic.hpp"
#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/result.hpp"
#include "pheromesh/core/shao_params.hpp"

namespace pheromesh::core {

// The policy of a scenario without `policy { ... }`: the Shao 2020 search.
// A scenario names its policy by the entry of the policy table
// (policy_table.hpp) that runs it: "shao_search", "liu", ...
inline constexpr std::string_view kDefaultPolicy = "shao_search";

// The configuration of one policy. Each room derives its own
// (pheromesh/<paper>/policy.hpp: ShaoNavigationConfig, LiuConfig,
// ShostakConfig, RavankarConfig, DuanConfig) with `static constexpr
// std::string_view kPolicy`, the name of its policy's table entry, so that a
// scenario holds only the policy it runs and this header knows no paper.
struct PolicyConfig {
  virtual ~PolicyConfig() = default;
  [[nodiscard]] virtual std::string_view policy() const = 0;  // the policy's name, as kPolicy

 protected:
  PolicyConfig() = default;
  PolicyConfig(const PolicyConfig&) = default;
  PolicyConfig(PolicyConfig&&) = default;
  PolicyConfig& operator=(const PolicyConfig&) = default;
  PolicyConfig& operator=(PolicyConfig&&) = default;
};

// One change to a scenario's fields given on the command line (`--set
// PATH=VALUE`, or a flag that stands for one such as `--uavs 20`), applied to
// the parsed message before validation, so that the changed scenario is
// validated exactly like a file; errors about the field it sets name
// `source` instead of a line of the file.
struct ScenarioOverride {
  std::string path;    // textproto field path into the Scenario message: "swarm.uavs", "map.targets[2].x"
  std::string value;   // as typed: "20", "true", "frontier"
  std::string source;  // how the user gave it, for messages: "--set swarm.uavs=20", "--uavs 20"
};
using ScenarioOverrides = std::vector<ScenarioOverride>;

// "PATH=VALUE" as given to `flag` (--set): split at the first '='; an error
// names the flag and shows the form. The path is checked when applied.
Result<ScenarioOverride> parse_override(std::string_view arg, std::string_view flag = "--set");

// "--set a=1, --uavs 4": the sources, for messages and reports.
std::string describe_overrides(const ScenarioOverrides& overrides);

struct ScenarioConfig {
  std::string name;
  std::string source_path;  // file it was loaded from ("" for text)
  // The text it was parsed from. What a program changes in the config
  // afterwards is not in it: a program that must hand the same scenario to
  // real processes (`pheromesh experiment --distributed`) changes the text
  // (patch_scenario) and parses it again.
  std::string source_text;
  // The overrides applied to the file's text, in order (source_text is then
  // the changed message printed in text format, headed by a comment naming
  // the file and the overrides).
  ScenarioOverrides overrides;
  // map
  int32_t width = 0, height = 0;  // [cell]
  int32_t tile_size = 10;         // [cell], 4..32 (a tile fits one DDS sample)
  int32_t regions_x = 1, regions_y = 1;
  std::vector<Rect> obstacles;
  std::vector<Cell> targets;
  // swarm
  uint32_t uavs = 10;
  Rect start_area{};           // UAVs start at distinct free cells in here
  uint32_t ticks = 1000;       // default run length [tick]
  double tick_rate_hz = 10.0;  // realtime clock rate [Hz]
  uint64_t seed = 1;
  bool standby = false;        // a hot-standby replica of every place agent (pheromesh run --standby)
  // `shao { layers aco }`, read by the Shao room (papers/shao/src/scenario.cpp)
  // in every scenario; used by the Shao search and navigation.
  ShaoLayerParams layers;  // the Shao field (layers.hpp)
  ShaoAcoParams aco;       // Shao 2020 eq. (9)
  // The name of the policy's entry in the policy table (policy_table.hpp),
  // as in the scenario file: "shao_search", "liu", ...
  std::string policy{kDefaultPolicy};
  // Where the policy's code came from when it is a plugin (`policy { plugin
  // { ... } }`, policy_plugin.hpp); empty for a built-in policy.
  struct PluginSource {
    std::string library;    // the file loaded, absolute
    std::string sha256;     // its SHA-256, 64 lowercase hex digits
    std::string pinned_by;  // what pinned it: "" (nothing), "the scenario", "$PHEROMESH_PLUGIN_SHA256"
  };
  std::optional<PluginSource> plugin;
  // Where the policy's code came from when it is written in Python (`policy {
  // python { ... } }`, python_policy.hpp); empty otherwise.
  struct PythonSource {
    std::string module;      // as the scenario names it
    std::string class_name;  // the class in it
    std::string file;        // the module's file, as Python imported it
  };
  std::optional<PythonSource> python;
  // The config of `policy`; null for the Shao search, which has none beyond
  // `layers` and `aco`. Immutable and shared by copies of the scenario.
  std::shared_ptr<const PolicyConfig> policy_config;
  // The scenario's `fault:` lines (docs/faults.md), sorted by time; `pheromesh
  // run` adds --faults to them.
  FaultSchedule faults;
  // `geo`: where the map lies on the Earth (geodetic.hpp), for MAVLink.
  GeoFrame geo;

  [[nodiscard]] MapGeometry geometry() const { return {width, height, tile_size, regions_x, regions_y}; }

  // Sets the policy and its config: set_policy_config(LiuConfig{...}).
  template <class C>
  void set_policy_config(C config) {
    policy = std::string(C::kPolicy);
    policy_config = std::make_shared<const C>(std::move(config));
  }
  // The config of policy C; throws std::logic_error when the scenario runs
  // another policy (a programming error: a policy's own code reads its config).
  template <class C>
  [[nodiscard]] const C& config_of() const {
    if (policy_config == nullptr || policy_config->policy() != C::kPolicy) {
      throw std::logic_error(std::string("scenario '") + name + "': asked for the " + std::string(C::kPolicy) +
                             " config of a scenario whose policy is " + policy +
                             (policy_config == nullptr ? " (no policy config set)" : ""));
    }
    return static_cast<const C&>(*policy_config);
  }
};

Result<ScenarioConfig> load_scenario(const std::string& path);
// `display_name` is used in error messages in place of a path.
Result<ScenarioConfig> parse_scenario(std::string_view text, const std::string& display_name);
// The file with `overrides` applied in order (a later one of the same field
// wins), then validated as a file is; the limits from the environment.
Result<ScenarioConfig> load_scenario(const std::string& path, const ScenarioOverrides& overrides);

// `base`'s text with `patch` (textproto of the same Scenario message) merged
// in: scalars of the patch replace the base's, messages merge field by field,
// repeated fields are appended (`map { obstacles {...} }` adds an obstacle).
// Returns the merged text, parsed again (so it is validated like a file;
// errors name `display_name`), with source_path kept. `base`'s overrides are
// applied again after the patch: what the user set on the command line wins
// over what a program patches.
Result<ScenarioConfig> patch_scenario(const ScenarioConfig& base, std::string_view patch, const std::string& display_name);

// Start cell of UAV `id` (0-based): deterministic for the scenario (free cells
// of start_area in row-major order, distributed round-robin).
Cell start_cell(const ScenarioConfig& s, uint32_t id);
// start_cell of every UAV 0..s.uavs-1, the start area walked once.
std::vector<Cell> start_cells(const ScenarioConfig& s);

}  // namespace pheromesh::core
