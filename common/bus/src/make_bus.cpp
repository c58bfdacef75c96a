// Which transports this build has, and the vendor's bus for a process.
#include <cstdlib>

#include "cyclone_bus.hpp"
#include "fastdds_bus.hpp"
#include "pheromesh/bus/bus.hpp"

namespace pheromesh::bus {

std::vector<std::string> available_vendors() { return {"cyclone", "fastdds"}; }

std::string default_vendor() {
  if (const char* v = std::getenv("PHEROMESH_DDS"); v != nullptr && *v != '\0') return v;
  return "cyclone";
}

core::Result<std::unique_ptr<Transport>> make_transport(const std::string& vendor, const BusOptions& options) {
  if (vendor == "cyclone") return make_cyclone_transport(options);
  if (vendor == "fastdds") return make_fastdds_transport(options);
  std::string known;
  for (const auto& v : available_vendors()) known += (known.empty() ? "" : ", ") + v;
  if (vendor == "mixed") {
    return core::Error{
        "DDS vendor 'mixed' is for pheromesh run, which gives each process one vendor; a process takes one of: " +
        known};
  }
  return core::Error{"unknown DDS vendor '" + vendor + "' (this build has: " + known + ")"};
}

core::Result<std::unique_ptr<Bus>> make_bus(const std::string& vendor, const BusOptions& options) {
  auto t = make_transport(vendor, options);
  if (!t) return t.error();
  return std::make_unique<Bus>(std::move(t).value());
}

}  // namespace pheromesh::bus
