// Loading a DDS module (vendors.hpp).
#include <dlfcn.h>

#include <map>
#include <mutex>
#include <system_error>

#include "vendors.hpp"

namespace pheromesh::bus {

core::Result<const TransportModule*> load_transport_module(const std::string& vendor, const std::string& path) {
  static std::mutex mutex;
  static std::map<std::string, const TransportModule*> loaded;  // by path
  const std::lock_guard lock(mutex);
  if (const auto it = loaded.find(path); it != loaded.end()) {
    if (auto why = module_mismatch(it->second, vendor, path)) return core::Error{*why};
    return it->second;
  }
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    return core::Error{"the '" + vendor + "' DDS module " + path + " is missing"};
  }
  // RTLD_NOW: a symbol the module lacks is an error here, not in the middle of
  // a run. RTLD_LOCAL: its vendor's symbols stay its own.
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* e = dlerror();
    return core::Error{"cannot load the '" + vendor + "' DDS module " + path + ": " + (e != nullptr ? e : "?")};
  }
  using Entry = const TransportModule* (*)();
  auto entry = reinterpret_cast<Entry>(dlsym(handle, kTransportModuleSymbol));  // NOLINT: dlsym returns void*
  if (entry == nullptr) {
    return core::Error{"the DDS module " + path + " does not export " + kTransportModuleSymbol};
  }
  const TransportModule* module = entry();
  if (auto why = module_mismatch(module, vendor, path)) return core::Error{*why};
  loaded.emplace(path, module);
  return module;
}

}  // namespace pheromesh::bus
