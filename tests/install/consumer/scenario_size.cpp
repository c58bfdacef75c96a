// Loads a scenario with the installed pheromesh::core, prints its map, and
// simulates a few ticks (the core alone, no DDS); fails if no UAV deposited.
//   scenario_size FILE TICKS
#include <cstdio>
#include <cstdlib>
#include <string>

#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: scenario_size FILE TICKS\n");
    return 2;
  }
  auto s = pheromesh::core::load_scenario(argv[1]);
  if (!s) {
    std::fprintf(stderr, "%s\n", s.error().message.c_str());
    return 1;
  }
  std::printf("map %d x %d, %u regions, %u uavs\n", s->width, s->height, s->geometry().region_count(), s->uavs);
  pheromesh::core::ScenarioConfig cfg = s.value();
  cfg.ticks = static_cast<uint32_t>(std::strtoul(argv[2], nullptr, 10));
  pheromesh::core::Simulator sim(cfg);
  sim.run();
  const uint64_t sent = sim.recorder().deposits_sent();
  std::printf("simulated %u ticks, %llu deposits\n", cfg.ticks, static_cast<unsigned long long>(sent));
  return sent > 0 ? 0 : 1;  // a swarm that flew deposits
}
