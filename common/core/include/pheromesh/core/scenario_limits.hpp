// What a scenario may ask of the machines that run it: map size, place
// agents, processes and memory. Checked by scenario validation (every
// command and every process that loads a scenario), so that a scenario that
// would abort (bad_alloc on a 4096 x 4096 map), exhaust memory or ask for a
// million place agents is refused up front with a message that says which
// limit and how to raise it. Limits come from compiled defaults, each
// overridable by an environment variable (inherited by every process that
// `pheromesh run` launches, so one setting reaches the whole swarm).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "pheromesh/core/result.hpp"
#include "pheromesh/core/scenario.hpp"

namespace pheromesh::core {

struct ScenarioLimits {
  // Defaults chosen from measurements (docs/scenario-format.md, "Limits").
  int64_t max_map_cells = int64_t{2048} * 2048;  // width x height [cell]   $PHEROMESH_MAX_MAP_CELLS
  int64_t max_regions = 256;                     // place-agent regions     $PHEROMESH_MAX_REGIONS
  int64_t max_processes = 1024;                  // UAVs + place agents (x2 with standby) + ground  $PHEROMESH_MAX_PROCESSES
  int64_t max_process_mib = 2048;                // estimated RSS of the largest process [MiB]  $PHEROMESH_MAX_PROCESS_MIB
  int64_t max_swarm_mib = 32768;  // estimated memory of all processes, libraries once [MiB]  $PHEROMESH_MAX_SWARM_MIB

  // The defaults, with each limit whose variable is set replaced by it; an
  // error names a variable that is not a positive integer.
  static Result<ScenarioLimits> from_environment();
};

// Environment variable names, for messages and docs.
inline constexpr const char* kMaxMapCellsEnv = "PHEROMESH_MAX_MAP_CELLS";
inline constexpr const char* kMaxRegionsEnv = "PHEROMESH_MAX_REGIONS";
inline constexpr const char* kMaxProcessesEnv = "PHEROMESH_MAX_PROCESSES";
inline constexpr const char* kMaxProcessMibEnv = "PHEROMESH_MAX_PROCESS_MIB";
inline constexpr const char* kMaxSwarmMibEnv = "PHEROMESH_MAX_SWARM_MIB";

// What running a scenario costs, estimated from its geometry and swarm.
// Memory is resident memory (RSS) per process from a linear model fitted to
// runs of 256 x 256 and 1024 x 1024 maps (Cyclone DDS, docs/scenario-format.md).
struct ScenarioCost {
  int64_t map_cells = 0;
  int64_t regions = 0;
  int64_t processes = 0;  // uavs + regions (x2 with standby) + 1 ground station
  double uav_mib = 0;
  double place_mib = 0;   // the place agent of the largest region
  double ground_mib = 0;
  double swarm_mib = 0;  // every process together, the libraries they share counted once
  [[nodiscard]] double largest_mib() const;
  [[nodiscard]] const char* largest_role() const;  // "ground station", "place agent" or "UAV"
};
ScenarioCost estimate_cost(const ScenarioConfig& s);

// Which limit a violation concerns (where scenario validation reports it).
enum class LimitKind : uint8_t { MapCells, Regions, Processes, ProcessMemory, SwarmMemory };
struct LimitViolation {
  LimitKind kind;
  std::string what;  // says the figure, the limit, and the variable that raises it
};
std::vector<LimitViolation> limit_violations(const ScenarioConfig& s, const ScenarioLimits& limits);

// For a scenario changed after loading (--uavs, --standby): an error listing
// every violation, prefixed with `source`.
Result<bool> check_limits(const ScenarioConfig& s, const ScenarioLimits& limits, const std::string& source);

// Parsing with explicit limits: a pure function of its arguments (no
// environment), for tests and fuzzing. parse_scenario(text, name) and
// load_scenario(path) use ScenarioLimits::from_environment().
Result<ScenarioConfig> parse_scenario(std::string_view text, const std::string& display_name,
                                      const ScenarioLimits& limits);
Result<ScenarioConfig> load_scenario(const std::string& path, const ScenarioLimits& limits);
// With overrides (scenario.hpp, ScenarioOverride): applied to the parsed
// message, then validated as the file is.
Result<ScenarioConfig> parse_scenario(std::string_view text, const std::string& display_name,
                                      const ScenarioLimits& limits, const ScenarioOverrides& overrides);
Result<ScenarioConfig> load_scenario(const std::string& path, const ScenarioLimits& limits,
                                     const ScenarioOverrides& overrides);

// Whether `s` is well-formed UTF-8 (no overlong forms, surrogates or code
// points above U+10FFFF); on failure `bad_offset` is the first bad byte.
bool valid_utf8(std::string_view s, std::size_t* bad_offset = nullptr);

}  // namespace pheromesh::core
