// Where `pheromesh` finds a scenario: the SCENARIO argument of run, sim,
// validate and bench scale is either a file (used as given, relative to the
// current directory) or the name of a shipped scenario (`small-test` or
// `small-test.textproto`), looked up
//   1. in the installed scenarios folder, relative to the running executable
//      (<prefix>/bin/../share/pheromesh/scenarios), so a relocated prefix
//      works;
//   2. in the source tree's scenarios/, only when the executable is the one in
//      this build tree's bin/ (an installed copy never reads the source tree).
// docs/install.md describes the layout.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "pheromesh/core/result.hpp"

namespace pheromesh::cli {

inline constexpr const char* kScenarioExtension = ".textproto";
// The help text of every SCENARIO argument.
inline constexpr const char* kScenarioArgHelp =
    "Scenario file (protobuf text format), or the name of a shipped scenario, e.g. small-test "
    "(an unknown name lists them)";

// Where this build looks, as configured by CMake (cmake/InstallDirs.cmake).
struct ScenarioSearch {
  std::filesystem::path exe_dir;           // folder of the running executable
  std::filesystem::path installed_rel;     // from the bin folder to the shipped scenarios
  std::filesystem::path build_bin_dir;     // this build tree's bin/
  std::filesystem::path source_scenarios;  // the source tree's scenarios/
};

// The folders searched for a shipped scenario, in order (they need not exist).
std::vector<std::filesystem::path> scenario_dirs(const ScenarioSearch& search);

// The sorted names (without extension) of the scenarios in `dirs`.
std::vector<std::string> shipped_scenario_names(const std::vector<std::filesystem::path>& dirs);

// SCENARIO as a path to open: an existing file as given; else a name (no '/')
// found in `dirs`; else an error that names the argument and lists the
// shipped scenarios.
core::Result<std::string> resolve_scenario(const std::string& arg, const std::vector<std::filesystem::path>& dirs);

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
