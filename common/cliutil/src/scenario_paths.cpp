#include "pheromesh/cliutil/scenario_paths.hpp"

#include <system_error>

namespace pheromesh::cli {

namespace fs = std::filesystem;

// --- this executable --------------------------------------------------------

namespace {

fs::path running_executable_dir() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : self.parent_path();
}

}  // namespace

std::vector<fs::path> default_scenario_dirs() {
  // Set by cmake/InstallDirs.cmake for every target that compiles this file.
  return scenario_dirs(ScenarioSearch{running_executable_dir(), PHEROMESH_INSTALLED_SCENARIOS_REL,
                                      PHEROMESH_BUILD_BIN_DIR, PHEROMESH_SOURCE_SCENARIOS_DIR});
}

std::string shipped_scenario(const std::string& file) {
  const auto dirs = default_scenario_dirs();
  if (const fs::path p = find_shipped(file, dirs); !p.empty()) return p.string();
  return dirs.empty() ? file : (dirs.front() / file).string();
}

std::string resolve_scenario_argument(std::string& arg) {
  auto r = resolve_scenario(arg, default_scenario_dirs());
  if (!r) return r.error().message;
  arg = std::move(r).value();
  return {};
}

}  // namespace pheromesh::cli
