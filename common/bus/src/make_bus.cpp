// Both vendors linked in: the library pheromesh::bus, for tests and for
// programs built against an installed pheromesh. The pheromesh programs load
// the one they use instead (module_bus.cpp).
#include "cyclone_bus.hpp"
#include "fastdds_bus.hpp"
#include "pheromesh/bus/bus.hpp"
#include "vendors.hpp"

namespace pheromesh::bus {

core::Result<std::unique_ptr<Transport>> make_transport(const std::string& vendor, const BusOptions& options) {
  if (vendor == "cyclone") return make_cyclone_transport(options);
  if (vendor == "fastdds") return make_fastdds_transport(options);
  return unknown_vendor(vendor);
}

}  // namespace pheromesh::bus
