// A core-only build (PHEROMESH_CORE_ONLY=ON; process_commands.hpp): `run`,
// `attach`, `bench`, `security` and `replay` are listed, take any arguments,
// and say that this build cannot run them instead of CLI11's "unknown
// subcommand", which would suggest a typo.
#include <cstdio>
#include <string>
#include <vector>

#include "process_commands.hpp"

namespace pheromesh::cli {

namespace {

struct Absent {
  const char* name;
  const char* needs;
};
constexpr Absent kAbsent[] = {
    {"run", "DDS (every UAV and place agent is a DDS process)"},
    {"attach", "DDS (it joins a running swarm's domain)"},
    {"cell", "DDS (it names a DDS process's discovery peers)"},
    {"bench", "DDS (it runs swarms of processes)"},
    {"security", "DDS Security"},
    {"replay", "the web console (its HTTP server and the page built with npm)"},
};

class CoreOnlyCommands final : public ProcessCommands {
 public:
  explicit CoreOnlyCommands(CLI::App& app) {
    for (const Absent& a : kAbsent) {
      auto* sub = app.add_subcommand(a.name, std::string("Not in this build: needs ") + a.needs);
      sub->allow_extras();
      sub->prefix_command();
      subs_.push_back({sub, a});
    }
  }

  std::optional<int> run_parsed() override {
    for (const auto& [sub, a] : subs_) {
      if (!sub->parsed()) continue;
      std::fprintf(stderr, "pheromesh %s needs %s: %s\n", a.name, a.needs, kCoreOnlyHint);
      return 2;
    }
    return std::nullopt;
  }

 private:
  std::vector<std::pair<CLI::App*, Absent>> subs_;
};

}  // namespace

std::unique_ptr<ProcessCommands> add_process_commands(CLI::App& app) { return std::make_unique<CoreOnlyCommands>(app); }

bool processes_built() { return false; }

}  // namespace pheromesh::cli
