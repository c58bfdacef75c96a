// Where a front door (`pheromesh`, the Python package) finds a scenario: a
// SCENARIO argument is either a file (used as given, relative to the current
// directory) or the name of a shipped scenario (`small-test` or
// `small-test.textproto`), looked up
//   1. in the installed scenarios folder, relative to the running program's
//      folder (<prefix>/bin/../share/pheromesh/scenarios for `pheromesh`), so
//      a relocated prefix works;
//   2. in the source tree's scenarios/, only when the program is the one in
//      this build tree (an installed copy never reads the source tree).
// The CLI fills ScenarioSearch for its executable (cli/scenario_paths.hpp),
// the Python package for its extension module (python/src/module.cpp).
// docs/install.md describes the layout.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "pheromesh/core/result.hpp"

namespace pheromesh::frontdoor {

inline constexpr const char* kScenarioExtension = ".textproto";

// Where a program looks, as configured by CMake (cmake/InstallDirs.cmake).
struct ScenarioSearch {
  std::filesystem::path exe_dir;           // folder of the running program (or module)
  std::filesystem::path installed_rel;     // from that folder to the shipped scenarios, once installed
  std::filesystem::path build_bin_dir;     // where the program is in this build tree
  std::filesystem::path source_scenarios;  // the source tree's scenarios/
};

// The folders searched for a shipped scenario, in order (they need not exist).
std::vector<std::filesystem::path> scenario_dirs(const ScenarioSearch& search);

// The sorted names (without extension) of the scenarios in `dirs`.
std::vector<std::string> shipped_scenario_names(const std::vector<std::filesystem::path>& dirs);

// The file of `name` (with or without the extension) in the first folder of
// `dirs` that has it, or empty.
std::filesystem::path find_shipped(const std::string& name, const std::vector<std::filesystem::path>& dirs);

// SCENARIO as a path to open: an existing file as given; else a name (no '/')
// found in `dirs`; else an error that names the argument and lists the
// shipped scenarios.
core::Result<std::string> resolve_scenario(const std::string& arg, const std::vector<std::filesystem::path>& dirs);

}  // namespace pheromesh::frontdoor
