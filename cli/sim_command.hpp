#pragma once
#include <cstdint>
#include <string>

namespace pheromesh::cli {

struct SimOptions {
  std::string scenario;
  uint64_t seed = 0;    // 0: the scenario's
  uint32_t ticks = 0;   // 0: the scenario's
  uint32_t uavs = 0;    // 0: the scenario's
  std::string out_dir = "out/sim";
  bool quiet = false;
};

// `pheromesh sim`: the whole swarm in this process (core::Simulator), same
// metrics.json and final_field.txt as a lockstep `pheromesh run`.
int run_sim(const SimOptions& o);

}  // namespace pheromesh::cli
