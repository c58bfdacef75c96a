// The pheromesh programs' vendor: loaded from its DDS module when the process
// makes its bus (vendors.hpp), so that a Cyclone process never maps Fast DDS
// and its libraries, nor a Fast DDS process Cyclone's.
#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "pheromesh/bus/bus.hpp"
#include "vendors.hpp"

namespace pheromesh::bus {
namespace {

std::filesystem::path exe_dir() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::current_path(ec) : exe.parent_path();
}

}  // namespace

core::Result<std::unique_ptr<Transport>> make_transport(const std::string& vendor, const BusOptions& options) {
  bool known = false;
  for (const auto& v : available_vendors()) known = known || v == vendor;
  if (!known) return unknown_vendor(vendor);
  std::optional<std::string> env;
  if (const char* d = std::getenv(kModuleDirEnv); d != nullptr && *d != '\0') env = d;
  const std::string path = module_path(vendor, env, exe_dir(), PHEROMESH_DDS_MODULE_REL).string();
  auto module = load_transport_module(vendor, path);
  if (!module) {
    return core::Error{module.error().message + (env ? std::string(" ($") + kModuleDirEnv + " names its folder)"
                                                     : std::string(" (installed in lib/pheromesh beside bin/; $") +
                                                           kModuleDirEnv + " names another folder)")};
  }
  return module.value()->make(options);
}

}  // namespace pheromesh::bus
