// `pheromesh bench scale`: runs `pheromesh run` with swarms of increasing
// size, per DDS vendor, and tabulates what each size costs (timeliness, CPU,
// memory, threads, UDP traffic) from each run's metrics.json.
#pragma once

#include <cstdint>
#include <string>

namespace pheromesh::cli {

struct BenchScaleOptions {
  std::string scenario;
  std::string sizes = "25,50,100,200,400,700,1000";  // UAV counts
  uint32_t max_uavs = 0;                             // 0: no cap; else sizes above it are left out
  std::string dds = "cyclone";                       // comma-separated: cyclone, fastdds, mixed
  double rate_hz = 5;                                // [Hz]
  uint32_t ticks = 100;
  uint32_t lease_ms = 5000;  // [ms]
  std::string out_dir = "out/bench-scale";
  double stop_late_share = 0.10;  // a vendor's larger sizes are skipped once a size has more late ticks than this
  uint32_t domain = 40;
  std::string extra;  // more arguments for `pheromesh run`, split at blanks
};

// What --help says after the options: what is measured and how.
extern const char* const kBenchScaleFooter;

// Returns 0 if every run was made (a run that failed is a row, not an
// error), 2 on bad options, 5 if the results cannot be written, 130 if
// interrupted.
int run_bench_scale(const BenchScaleOptions& o);

}  // namespace pheromesh::cli
