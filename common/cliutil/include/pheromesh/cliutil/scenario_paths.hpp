// Where `pheromesh` finds a scenario: the SCENARIO argument of run, sim,
// validate and bench scale is a file or the name of a shipped scenario
// (pheromesh/frontdoor/scenario_paths.hpp has the rules, shared with the
// Python package); this file fills them in for the running executable.
// docs/install.md describes the layout.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "pheromesh/core/result.hpp"
#include "pheromesh/frontdoor/scenario_paths.hpp"

namespace pheromesh::cli {

using frontdoor::find_shipped;
using frontdoor::kScenarioExtension;
using frontdoor::resolve_scenario;
using frontdoor::scenario_dirs;
using frontdoor::ScenarioSearch;
using frontdoor::shipped_scenario_names;

// The help text of every SCENARIO argument.
inline constexpr const char* kScenarioArgHelp =
    "Scenario file (protobuf text format), or the name of a shipped scenario, e.g. small-test "
    "(an unknown name lists them)";

// --- this executable --------------------------------------------------------

// scenario_dirs() for the running executable and this build's configuration.
std::vector<std::filesystem::path> default_scenario_dirs();

// A shipped scenario file by name for the experiments, e.g.
// "shao2020-50x50.textproto": the first folder that has it (the first folder
// when none does, so that loading it fails naming a path).
std::string shipped_scenario(const std::string& file);

// The CLI11 transform of a SCENARIO argument: resolve_scenario() against
// default_scenario_dirs(); the argument becomes the path to open.
std::string resolve_scenario_argument(std::string& arg);

}  // namespace pheromesh::cli
