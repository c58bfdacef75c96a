// `pheromesh bench lockstep`: where a lockstep tick's time goes. For each
// swarm (a scenario and a UAV count) it runs the in-process simulator and
// `pheromesh run --clock lockstep` once per DDS vendor (cyclone, fastdds,
// mixed), and measures in the same run the round trip of one pheromesh
// sample between two processes per vendor pairing (the network floor). It
// prints ticks/s, the time of each UAV and place phase (from the conductor,
// metrics.json "lockstep"), the ratio to the simulator and to the floor, and
// whether the processes gave the simulator's numbers.
#pragma once

#include <cstdint>
#include <string>

namespace pheromesh::cli {

struct BenchLockstepOptions {
  // SCENARIO[:UAVS] entries, comma-separated; a scenario by path or by the
  // name of a shipped one.
  std::string swarms = "small-test:10,scale-100x100:100";
  std::string dds = "cyclone,fastdds,mixed";
  uint32_t ticks = 300;  // lockstep ticks per run
  uint32_t pings = 500;  // round trips per vendor pairing for the floor
  uint32_t domain = 44;
  std::string out_dir = "out/bench-lockstep";
  // Another build's `pheromesh` (e.g. of the commit before a change): every
  // run is flown with it too, in the same bench, and compared by wall time.
  std::string baseline;
  // Runs per swarm, vendor and build. With a baseline the builds alternate
  // and swap which goes first every other round (this, baseline; baseline,
  // this; ...), so that a drift of the host falls on both; the report gives
  // the median and the range of each, and of the paired ratios.
  uint32_t repeat = 1;
};

extern const char* const kBenchLockstepFooter;

// 0 when every run was made and equal to the simulator, 4 if a run differed
// or failed (its row says why), 2 on bad options, 5 if the results cannot be
// written, 130 if interrupted.
int run_bench_lockstep(const BenchLockstepOptions& o);

}  // namespace pheromesh::cli
