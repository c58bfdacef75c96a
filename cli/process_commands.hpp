// The subcommands that need more than the core: `run`, `attach`, `bench`,
// `security` (DDS) and `replay` (the web console's HTTP server and page).
// cli/main.cpp registers the core's own (validate, sim, experiment, sweep,
// key) and asks for these; a full build registers them from
// process_commands.cpp, a core-only build (PHEROMESH_CORE_ONLY=ON) from
// core_only_commands.cpp, where each one only says what it needs.
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <optional>

namespace pheromesh::cli {

class ProcessCommands {
 public:
  virtual ~ProcessCommands() = default;
  // The exit code of the subcommand the command line named, if it is one of
  // these (nullopt: it was one of main's).
  virtual std::optional<int> run_parsed() = 0;
};

// Adds the subcommands to `app`; the result owns their options and must
// outlive the parse.
std::unique_ptr<ProcessCommands> add_process_commands(CLI::App& app);

// True in a build with both DDS vendors and the web console; false in a
// core-only build, whose `--distributed` options refuse to start.
bool processes_built();

// The message of a core-only build asked for `what`.
inline constexpr const char* kCoreOnlyHint =
    "this pheromesh was built core-only (cmake -DPHEROMESH_CORE_ONLY=ON: no DDS vendor, no web console); "
    "build it without PHEROMESH_CORE_ONLY for run, attach, bench, security, replay and --distributed (README, "
    "\"Without DDS\")";

}  // namespace pheromesh::cli
