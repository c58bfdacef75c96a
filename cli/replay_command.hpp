// `pheromesh replay FILE`: serves the web console from a recording, with a
// time slider (docs/console.md, docs/recording.md); with --mavlink, streams
// the recording to a MAVLink ground-control station at its recorded pace
// (docs/mavlink.md).
#pragma once

#include <cstdint>
#include <string>

#include "pheromesh/console/mavlink_feed.hpp"

namespace pheromesh::cli {

struct ReplayOptions {
  std::string file;
  uint16_t port = 8080;  // 0: any free port
  std::string bind = "127.0.0.1";
  bool check = false;    // read the file, print what it holds, do not serve
  std::string mavlink;   // udp:HOST:PORT, or "": no MAVLink stream
  double mavlink_rate_hz = console::kMavlinkDefaultRateHz;
};

int run_replay(const ReplayOptions& o);

}  // namespace pheromesh::cli
