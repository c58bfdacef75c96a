// The vendor a process takes, and what make_bus.cpp and module_bus.cpp share
// (vendors.hpp).
#include "vendors.hpp"

#include <cstdlib>

namespace pheromesh::bus {

std::vector<std::string> available_vendors() { return {"cyclone", "fastdds"}; }

std::string default_vendor() {
  if (const char* v = std::getenv("PHEROMESH_DDS"); v != nullptr && *v != '\0') return v;
  return "cyclone";
}

core::Error unknown_vendor(const std::string& vendor) {
  std::string known;
  for (const auto& v : available_vendors()) known += (known.empty() ? "" : ", ") + v;
  if (vendor == "mixed") {
    return core::Error{
        "DDS vendor 'mixed' is for pheromesh run, which gives each process one vendor; a process takes one of: " +
        known};
  }
  return core::Error{"unknown DDS vendor '" + vendor + "' (this build has: " + known + ")"};
}

std::string module_file_name(const std::string& vendor) { return "libpheromesh_dds_" + vendor + ".so"; }

std::filesystem::path module_path(const std::string& vendor, const std::optional<std::string>& env_dir,
                                  const std::filesystem::path& exe_dir, const std::string& relative_dir) {
  const std::filesystem::path dir =
      env_dir && !env_dir->empty() ? std::filesystem::path(*env_dir) : exe_dir / relative_dir;
  return (dir / module_file_name(vendor)).lexically_normal();
}

std::optional<std::string> module_mismatch(const TransportModule* module, const std::string& vendor,
                                           const std::string& path) {
  if (module == nullptr) return "the DDS module " + path + " returned no entry";
  if (module->abi != kTransportModuleAbi || module->options_size != sizeof(BusOptions)) {
    return "the DDS module " + path + " was built for another pheromesh (interface " + std::to_string(module->abi) +
           ", options of " + std::to_string(module->options_size) + " bytes; this program has " +
           std::to_string(kTransportModuleAbi) + " and " + std::to_string(sizeof(BusOptions)) +
           "): install the module of this build";
  }
  if (module->vendor == nullptr || vendor != module->vendor || module->make == nullptr) {
    return "the DDS module " + path + " is not the '" + vendor + "' bus (it says '" +
           (module->vendor != nullptr ? module->vendor : "") + "')";
  }
  return std::nullopt;
}

}  // namespace pheromesh::bus
