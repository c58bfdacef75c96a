// The ground station's /metrics page: the console state just published and
// the station's counters, in the Prometheus text format (docs/console.md
// lists every family).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "pheromesh/console/request.hpp"
#include "pheromesh/console/state.hpp"

namespace pheromesh::console {

struct SwarmCounters {
  double coverage = 0;      // reachable cells seen, 0..1
  double uncertainty = 1;   // mean environmental uncertainty, 0..1
  uint64_t targets_found = 0, targets_total = 0;
  uint64_t deposits_sent = 0;
  uint64_t samples_rejected = 0;  // malformed samples dropped by the ground station
  // Well-formed samples refused as implausible (core/plausibility.hpp): by
  // who refused them ("places", "uavs", "ground"), then by reason.
  std::map<std::string, std::map<std::string, uint64_t>> samples_refused;
  uint64_t frames = 0;
  uint64_t commands_ok = 0, commands_refused = 0;
  std::optional<uint64_t> http_requests, http_body_bytes;  // with the HTTP server
  std::optional<RefusalCounts> http_refused;               // by Refusal
  std::optional<uint64_t> http_connections;                // open now
  std::optional<uint64_t> http_long_polls_unheld;          // answered at once beyond the long-poll limits
  std::optional<uint64_t> recording_bytes;                 // with a recording
};

std::string swarm_metrics_text(const ConsoleState& st, const SwarmCounters& c);

}  // namespace pheromesh::console
