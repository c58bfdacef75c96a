#pragma once
#include "pheromesh/bus/bus.hpp"

namespace pheromesh::bus {
core::Result<std::unique_ptr<Bus>> make_cyclone_bus(const BusOptions& options);
}
