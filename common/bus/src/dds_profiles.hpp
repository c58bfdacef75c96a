#pragma once
#include <string>

namespace pheromesh::bus {
// Cyclone configuration for a profile name ("onehost", "default") or a file
// path; "" means vendor defaults. Throws std::runtime_error on an unreadable file.
std::string cyclone_config(const std::string& profile);
}  // namespace pheromesh::bus
