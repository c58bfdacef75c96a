// Loading policy plugins (policy_plugin.hpp): find the library, check its
// SHA-256 against the pins before any of its code runs, dlopen it, check its
// ABI, and add its entry to the policy table (find_policy). The scenario
// parser calls this for `policy { plugin { ... } }`, so every program that
// loads a scenario file loads its plugin the same way.
//
// A loaded library stays loaded until the process ends: the table's entry,
// the policies' vtables and the configs point into it.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "pheromesh/core/policy_plugin.hpp"
#include "pheromesh/core/policy_table.hpp"
#include "pheromesh/core/result.hpp"

namespace pheromesh::core {

// Folders searched, in order, for a relative `library` after the scenario's
// own folder (':'-separated).
inline constexpr const char* kPluginPathEnv = "PHEROMESH_PLUGIN_PATH";
// The SHA-256 every process of a run requires of the plugin library: set by
// `pheromesh run` for the processes it starts (and by hand or a container
// for processes started otherwise).
inline constexpr const char* kPluginPinEnv = "PHEROMESH_PLUGIN_SHA256";

// The file `library` names: itself when absolute; else the first that exists
// of `scenario_dir`/library and each $PHEROMESH_PLUGIN_PATH folder/library.
// The error names every path tried.
Result<std::string> resolve_plugin_library(const std::string& library, const std::string& scenario_dir);

// A required SHA-256 and who requires it, for messages ("the scenario",
// "$PHEROMESH_PLUGIN_SHA256").
struct PluginPin {
  std::string sha256;  // 64 hex digits
  std::string by;
};

struct LoadedPlugin {
  std::string library;  // the absolute path loaded
  std::string sha256;
  const PluginPolicy* plugin = nullptr;
  PolicyEntry entry{};  // what find_policy returns for plugin->name
};

// Loads the library at `path` (absolute) once per process: hashes it and
// checks every pin (refusing, with this host's name, before the library's
// code runs), dlopens it, checks its ABI version and layout, that it exports
// a policy named `name` and that no other policy has that name. A second
// call for the same path hashes the file again and refuses a file that
// changed since. Errors name the path, the symbol, both versions.
Result<const LoadedPlugin*> load_policy_plugin(const std::string& path, std::string_view name,
                                               const std::vector<PluginPin>& pins);

// The plugin entry named `name`, null if no library loaded so far exports it.
const PolicyEntry* find_plugin_policy(std::string_view name);

// This host's name, for messages that must say where a check failed.
std::string host_name();

}  // namespace pheromesh::core
