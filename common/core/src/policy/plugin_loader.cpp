// Policy plugins (plugin_loader.hpp): resolve, hash, pin, dlopen, check, register.
#include "pheromesh/core/plugin_loader.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <array>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <mutex>
#include <system_error>

#include "pheromesh/core/sha256.hpp"

namespace pheromesh::core {
namespace {

namespace fs = std::filesystem;

std::mutex g_mutex;
std::deque<LoadedPlugin> g_loaded;  // deque: the entries' addresses stay put

bool file_exists(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

std::string dl_error() {
  const char* e = dlerror();
  return e != nullptr ? std::string(e) : std::string("unknown dlopen error");
}

std::string lower(std::string s) {
  for (char& c : s) {
    if (c >= 'A' && c <= 'F') c = static_cast<char>(c - 'A' + 'a');
  }
  return s;
}

// Every pin against the file's digest, before any of its code runs.
std::optional<std::string> check_pins(const std::string& path, const std::string& sha,
                                      const std::vector<PluginPin>& pins) {
  for (const PluginPin& p : pins) {
    if (lower(p.sha256) != sha) {
      return "host " + host_name() + ": the plugin library " + path + " has SHA-256 " + sha + ", but " + p.by +
             " pins " + lower(p.sha256) +
             ": this host has another build of the plugin (copy the same file here, or pin the new build)";
    }
  }
  return std::nullopt;
}

template <class F>
F symbol(void* handle, const char* name) {
  return reinterpret_cast<F>(dlsym(handle, name));  // NOLINT: dlsym returns void*
}

}  // namespace

std::string host_name() {
  std::array<char, 256> buf{};
  if (gethostname(buf.data(), buf.size() - 1) != 0) return "(unknown host)";
  return buf.data();
}

Result<std::string> resolve_plugin_library(const std::string& library, const std::string& scenario_dir) {
  if (library.empty()) return Error{"the library's path is empty"};
  const fs::path lib(library);
  // Canonical (symbolic links resolved): one file is one library, however a
  // scenario names it, and a process loads it once.
  const auto canonical = [](const fs::path& p) {
    std::error_code ec;
    const fs::path c = fs::canonical(p, ec);
    return (ec ? fs::absolute(p, ec) : c).lexically_normal().string();
  };
  if (lib.is_absolute()) {
    if (file_exists(lib)) return canonical(lib);
    return Error{"library " + library + " not found (tried " + library + ")"};
  }
  std::vector<fs::path> tried;
  if (!scenario_dir.empty()) tried.push_back(fs::path(scenario_dir) / lib);
  if (const char* env = std::getenv(kPluginPathEnv); env != nullptr) {
    std::string_view rest(env);
    while (!rest.empty()) {
      const std::size_t colon = rest.find(':');
      const std::string_view dir = rest.substr(0, colon);
      if (!dir.empty()) tried.push_back(fs::path(std::string(dir)) / lib);
      if (colon == std::string_view::npos) break;
      rest.remove_prefix(colon + 1);
    }
  }
  std::string list;
  for (const fs::path& p : tried) {
    if (file_exists(p)) return canonical(p);
    list += (list.empty() ? "" : ", ") + p.string();
  }
  return Error{"library " + library + " not found (tried " + (list.empty() ? std::string("no folder") : list) +
               "; a relative path is looked for in the scenario's folder, then in $" + kPluginPathEnv + ")"};
}

Result<const LoadedPlugin*> load_policy_plugin(const std::string& path, std::string_view name,
                                               const std::vector<PluginPin>& pins) {
  auto sha = sha256_file_hex(path);
  if (!sha) return sha.error();
  if (auto refused = check_pins(path, sha.value(), pins)) return Error{*refused};

  std::lock_guard lock(g_mutex);
  for (const LoadedPlugin& l : g_loaded) {
    if (l.library != path) continue;
    if (l.sha256 != sha.value()) {
      return Error{"the plugin library " + path + " changed on disk (SHA-256 " + sha.value() +
                   ") since this process loaded it (SHA-256 " + l.sha256 + "); a process runs one build of a plugin"};
    }
    if (l.plugin->name != name) {
      return Error{path + " exports the policy '" + std::string(l.plugin->name) + "', not '" + std::string(name) + "'"};
    }
    return &l;
  }

  // RTLD_NOW: a symbol the library needs and this process lacks is an error
  // here, not a crash in the middle of a run. RTLD_LOCAL: its symbols do not
  // serve other libraries.
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) return Error{"cannot load the plugin library " + path + ": " + dl_error()};
  // Never dlclose'd, even when refused: a library's static destructors may
  // already be registered with the process.
  const auto abi = symbol<uint32_t (*)()>(handle, kPluginAbiSymbol);
  const auto layout = symbol<uint64_t (*)()>(handle, kPluginLayoutSymbol);
  const auto get = symbol<const PluginPolicy* (*)()>(handle, kPluginEntrySymbol);
  if (abi == nullptr || layout == nullptr || get == nullptr) {
    const char* missing = abi == nullptr ? kPluginAbiSymbol : layout == nullptr ? kPluginLayoutSymbol : kPluginEntrySymbol;
    return Error{path + " is not a pheromesh policy plugin: it exports no symbol " + missing +
                 " (a plugin exports its entry with PHEROMESH_POLICY_PLUGIN(entry), policy_plugin.hpp)"};
  }
  if (const uint32_t v = abi(); v != kPolicyPluginAbi) {
    return Error{path + " was built for plugin ABI version " + std::to_string(v) + ", this pheromesh has version " +
                 std::to_string(kPolicyPluginAbi) + ": rebuild the plugin against this pheromesh"};
  }
  if (const uint64_t l = layout(); l != policy_plugin_layout()) {
    return Error{path + " was built with ABI version " + std::to_string(kPolicyPluginAbi) +
                 " but against headers whose types differ in size (layout " + std::to_string(l) + ", here " +
                 std::to_string(policy_plugin_layout()) + "): rebuild the plugin against this pheromesh"};
  }
  const PluginPolicy* p = get();
  if (p == nullptr || p->parse == nullptr || p->traits == nullptr || p->make_uav == nullptr ||
      p->make_place == nullptr) {
    return Error{path + ": its PluginPolicy is incomplete (parse, traits, make_uav and make_place are required)"};
  }
  if (p->name != name) {
    return Error{path + " exports the policy '" + std::string(p->name) + "', not '" + std::string(name) + "'"};
  }
  for (const PolicyEntry* e : policy_table()) {
    if (e->name == p->name) {
      return Error{path + " exports the policy '" + std::string(p->name) +
                   "', which is the name of a built-in policy; a plugin needs a name of its own"};
    }
  }
  for (const LoadedPlugin& l : g_loaded) {
    if (l.plugin->name == p->name) {
      return Error{path + " exports the policy '" + std::string(p->name) + "', already loaded from " + l.library};
    }
  }
  LoadedPlugin& l = g_loaded.emplace_back();
  l.library = path;
  l.sha256 = sha.value();
  l.plugin = p;
  l.entry = PolicyEntry{
      .name = p->name,
      .parse = nullptr,  // the scenario parser reads a plugin's config through PluginPolicy::parse
      .parse_scenario_fields = nullptr,
      .traits = p->traits,
      .broadcasts = p->broadcasts,
      .make_uav = p->make_uav,
      .make_place = p->make_place,
      .field_summary = p->field_summary,
  };
  return &l;
}

const PolicyEntry* find_plugin_policy(std::string_view name) {
  std::lock_guard lock(g_mutex);
  for (const LoadedPlugin& l : g_loaded) {
    if (l.entry.name == name) return &l.entry;
  }
  return nullptr;
}

}  // namespace pheromesh::core
