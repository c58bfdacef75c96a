// `pheromesh replay FILE`: serves the web console from a recording, with a
// time slider (docs/console.md, docs/recording.md).
#pragma once

#include <cstdint>
#include <string>

namespace pheromesh::cli {

struct ReplayOptions {
  std::string file;
  uint16_t port = 8080;  // 0: any free port
  std::string bind = "127.0.0.1";
  bool check = false;    // read the file, print what it holds, do not serve
};

int run_replay(const ReplayOptions& o);

}  // namespace pheromesh::cli
