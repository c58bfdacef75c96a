// The in-memory bus: the same Bus and Transport as the DDS vendors, no DDS
// and no sockets, for unit tests of what a shell wires. The buses of one
// MemoryDomain exchange samples within the process as DDS would: a reader
// gets what writers of its topic write into a partition it matches (DDS
// fnmatch patterns, either side), keep-last readers hold the latest `depth`
// samples per instance (Topic<M>::key), a transient-local reader opened late
// gets the writers' history, and a reader that watches departures hears of
// every instance of a writer whose bus was destroyed. Writes are delivered
// at once, so flush() is always true. Not modelled: exclusive ownership,
// liveliness leases, and losses.
#pragma once

#include <memory>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/bus/transport.hpp"

namespace pheromesh::bus {

class MemoryDomain;  // what the buses of one test share

std::shared_ptr<MemoryDomain> make_memory_domain();
std::unique_ptr<Transport> make_memory_transport(std::shared_ptr<MemoryDomain> domain, const BusOptions& options = {});
std::unique_ptr<Bus> make_memory_bus(std::shared_ptr<MemoryDomain> domain, const BusOptions& options = {});

}  // namespace pheromesh::bus
