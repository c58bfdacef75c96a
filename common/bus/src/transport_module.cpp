// The entry point of a DDS module (vendors.hpp): libpheromesh_dds_cyclone.so
// when compiled with PHEROMESH_MODULE_CYCLONE, libpheromesh_dds_fastdds.so
// otherwise. Everything else in the module stays hidden.
#ifdef PHEROMESH_MODULE_CYCLONE
#include "cyclone_bus.hpp"
#else
#include "fastdds_bus.hpp"
#endif
#include "vendors.hpp"

namespace {

const pheromesh::bus::TransportModule& entry() {
#ifdef PHEROMESH_MODULE_CYCLONE
  static const pheromesh::bus::TransportModule m{.vendor = "cyclone", .make = &pheromesh::bus::make_cyclone_transport};
#else
  static const pheromesh::bus::TransportModule m{.vendor = "fastdds", .make = &pheromesh::bus::make_fastdds_transport};
#endif
  return m;
}

}  // namespace

extern "C" __attribute__((visibility("default"))) const pheromesh::bus::TransportModule* pheromesh_transport_module() {
  return &entry();
}
