// The robustness claim of Shao 2020 Sec. 4.3.3 as a library: "the exhaustive
// search algorithm with a fixed path is not robust or flexible, facing
// unexpected faults which cause a rapid decrease in the efficiency of the
// whole system. However, our algorithm with no fixed path can adapt
// dynamically to emergencies". The paper shows no numbers for it
// (Shao 2020 Fig. 6 is fault-free); `pheromesh experiment shao2020-robustness`
// formats what this loop returns.
//
// One run = one scenario seed, one search (the pheromone search of
// Shao 2020 Algorithm 1, unchanged, or the fixed-route lawnmower with transit,
// lawnmower.hpp) and one share of UAVs killed at one tick, in the simulator
// with the fault semantics of faults.hpp (a killed UAV is gone: no state, no
// deposits, no coverage).
//
// Which UAVs die (ours): round(share · N) distinct UAVs, the first ones of a
// random permutation of 0..N-1 drawn by a partial Fisher-Yates shuffle from
// stream_seed(seed, "faults", 0) — draw j takes uniform_below(N - j) and
// swaps it into place j. The same seed kills the same UAVs in both searches,
// and the UAVs of a smaller share are among those of a larger one.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "pheromesh/core/faults.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/shao/policy.hpp"

namespace pheromesh::core {

// round(share · uavs), within [0, uavs].
uint32_t kill_count(double share, uint32_t uavs);
// The `count` UAVs (of `uavs`) that die in the run of `seed`, ascending.
std::vector<uint32_t> draw_killed_uavs(uint64_t seed, uint32_t uavs, uint32_t count);
// "kill uav:U @Tt" for each of them.
FaultSchedule uav_kill_schedule(const std::vector<uint32_t>& uavs, uint32_t tick);

struct RobustnessRun {
  ShaoRoute route = ShaoRoute::Pheromone;
  double kill_share = 0;
  uint64_t seed = 0;
  uint32_t kill_tick = 0;
  std::vector<uint32_t> killed;
  std::vector<double> coverage;     // share of reachable cells covered after tick t, t = 0..ticks
  std::optional<uint32_t> reached;  // first tick with coverage >= the goal
  uint32_t targets_found = 0;
  uint64_t deposits_sent = 0, deposits_lost = 0;
};

// One run of `base` (its map, swarm, ticks and Shao parameters as they are)
// with seed `seed`, the search `route`, and kill_count(share) UAVs drawn for
// `seed` killed at `kill_tick`. `goal`: the coverage whose first tick is `reached`.
RobustnessRun run_robustness(const ScenarioConfig& base, ShaoRoute route, double share, uint64_t seed,
                             uint32_t kill_tick, double goal);

}  // namespace pheromesh::core
