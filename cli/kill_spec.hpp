// --kill "uav:3@5s,place:1@2500ms": SIGKILL these processes at these times
// after the swarm started.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "pheromesh/core/result.hpp"

namespace pheromesh::cli {

struct KillEvent {
  std::string role;  // "uav" or "place"
  uint32_t index = 0;
  std::chrono::milliseconds at{0};
  [[nodiscard]] std::string process_name() const { return role + "-" + std::to_string(index); }
};

// Parses a comma-separated list of ROLE:INDEX@TIME, TIME = number followed by
// "s" or "ms". Sorted by time.
core::Result<std::vector<KillEvent>> parse_kill_spec(const std::string& spec);

}  // namespace pheromesh::cli
