#include "pheromesh/bus/bus.hpp"

#include <cstdlib>

#include "cyclone_bus.hpp"

namespace pheromesh::bus {

std::vector<std::string> available_vendors() { return {"cyclone"}; }

std::string default_vendor() {
  if (const char* v = std::getenv("PHEROMESH_DDS"); v != nullptr && *v != '\0') return v;
  return "cyclone";
}

core::Result<std::unique_ptr<Bus>> make_bus(const std::string& vendor, const BusOptions& options) {
  if (vendor == "cyclone") return make_cyclone_bus(options);
  std::string known;
  for (const auto& v : available_vendors()) known += (known.empty() ? "" : ", ") + v;
  return core::Error{"unknown DDS vendor '" + vendor + "' (this build has: " + known + ")"};
}

}  // namespace pheromesh::bus
