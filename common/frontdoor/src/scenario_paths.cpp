#include "pheromesh/frontdoor/scenario_paths.hpp"

#include <algorithm>
#include <set>
#include <system_error>

namespace pheromesh::frontdoor {

namespace fs = std::filesystem;

namespace {

bool same_folder(const fs::path& a, const fs::path& b) {
  std::error_code ec1, ec2;
  const fs::path ca = fs::weakly_canonical(a, ec1);
  const fs::path cb = fs::weakly_canonical(b, ec2);
  return !ec1 && !ec2 && ca == cb;
}

bool is_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

std::string join_names(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

std::string describe_dirs(const std::vector<fs::path>& dirs) {
  std::string s;
  for (const auto& d : dirs) s += (s.empty() ? "" : ", ") + d.string();
  return s.empty() ? "no folder" : s;
}

}  // namespace

fs::path find_shipped(const std::string& name, const std::vector<fs::path>& dirs) {
  const bool has_ext =
      name.size() > std::char_traits<char>::length(kScenarioExtension) && name.ends_with(kScenarioExtension);
  const std::string file = has_ext ? name : name + kScenarioExtension;
  for (const auto& d : dirs) {
    if (is_file(d / file)) return d / file;
  }
  return {};
}

std::vector<fs::path> scenario_dirs(const ScenarioSearch& search) {
  std::vector<fs::path> dirs;
  if (!search.exe_dir.empty()) dirs.push_back((search.exe_dir / search.installed_rel).lexically_normal());
  if (!search.exe_dir.empty() && !search.build_bin_dir.empty() && !search.source_scenarios.empty() &&
      same_folder(search.exe_dir, search.build_bin_dir)) {
    dirs.push_back(search.source_scenarios);
  }
  return dirs;
}

std::vector<std::string> shipped_scenario_names(const std::vector<fs::path>& dirs) {
  std::set<std::string> names;
  for (const auto& d : dirs) {
    std::error_code ec;
    for (fs::directory_iterator it(d, ec), end; !ec && it != end; it.increment(ec)) {
      const fs::path& p = it->path();
      if (p.extension() == kScenarioExtension && is_file(p)) names.insert(p.stem().string());
    }
  }
  return {names.begin(), names.end()};
}

core::Result<std::string> resolve_scenario(const std::string& arg, const std::vector<fs::path>& dirs) {
  if (arg.empty()) return core::Error{"no scenario given"};
  if (is_file(arg)) return arg;
  const auto names = shipped_scenario_names(dirs);
  std::vector<fs::path> existing;
  for (const auto& d : dirs) {
    std::error_code ec;
    if (fs::is_directory(d, ec)) existing.push_back(d);
  }
  const std::string shipped = names.empty()
                                  ? "no shipped scenarios found in " + describe_dirs(dirs)
                                  : "shipped scenarios (in " + describe_dirs(existing) + "): " + join_names(names);
  const auto is_dir = [&arg] {
    std::error_code ec;
    return fs::is_directory(arg, ec);
  };
  const std::string a_directory =
      "'" + arg + "' is a directory; give a scenario file (.textproto) or a shipped scenario's name; " + shipped;
  if (arg.find('/') != std::string::npos && is_dir()) return core::Error{a_directory};
  if (arg.find('/') != std::string::npos) {
    // A path: never quietly replaced by a shipped file of the same name, but
    // say that one exists (e.g. scenarios/small-test.textproto run from
    // another folder after installing).
    std::string msg = "'" + arg + "': no such file";
    const std::string base = fs::path(arg).filename().string();
    if (!base.empty() && !find_shipped(base, dirs).empty()) {
      msg +=
          " (a shipped scenario has that name: give it without the folder, '" + fs::path(base).stem().string() + "')";
    }
    return core::Error{msg};
  }
  if (const fs::path p = find_shipped(arg, dirs); !p.empty()) return p.string();
  if (is_dir()) return core::Error{a_directory};
  return core::Error{"'" + arg + "' is neither a file nor a shipped scenario; " + shipped};
}

}  // namespace pheromesh::frontdoor
