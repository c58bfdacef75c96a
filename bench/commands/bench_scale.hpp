// `pheromesh bench scale`: runs `pheromesh run` with swarms of increasing
// size, per DDS vendor, and tabulates what each size costs (timeliness, CPU,
// memory, threads, UDP traffic) from each run's metrics.json.
#pragma once

#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

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
  std::string extra;    // more arguments for `pheromesh run`, split at blanks
  uint32_t repeat = 1;  // runs of each size and vendor; a size holds only if every run held it
  // The floor, per vendor before the runs (bench_floor.hpp): round trips of
  // a view-sized sample down and an uplink-sized one up between two
  // processes (0: none). The default sizes are the mean DATA payloads of
  // pheromesh_view and pheromesh_uav_state that bench/tick_traffic.sh counted
  // at 500 UAVs on scale-100x100 (docs/benchmarks.md).
  uint32_t floor_pings = 300;
  uint32_t floor_view_bytes = 10700;
  uint32_t floor_uplink_bytes = 280;
};

// One run of the benchmark as its summary judges it.
struct ScaleRun {
  uint32_t uavs = 0;
  int exit_code = 0;
  std::optional<double> late_pct;     // share of late UAV ticks [%], if the ground station reported it
  std::optional<double> ticks_flown;  // UAV ticks flown, summed over the UAVs
};

// Why a run did not hold its size, or nullopt when it did: it exited 0,
// every UAV flew (at least 99 % of uavs x ticks UAV ticks; a UAV started late
// may miss a tick or two) and at most 1 % of the ticks started late. A run
// that flew nothing is never "on time".
inline std::optional<std::string> why_not_held(const ScaleRun& r, uint32_t ticks) {
  if (r.exit_code != 0) return "exited " + std::to_string(r.exit_code);
  const double expected = static_cast<double>(r.uavs) * ticks;
  if (!r.ticks_flown || *r.ticks_flown < 0.99 * expected) {
    return "flew " + (r.ticks_flown ? std::to_string(static_cast<uint64_t>(*r.ticks_flown)) : std::string("no")) +
           " of " + std::to_string(static_cast<uint64_t>(expected)) + " UAV ticks";
  }
  if (!r.late_pct) return std::string("no late share reported");
  if (*r.late_pct > 1.0) {
    char b[64];
    std::snprintf(b, sizeof b, "%.2f %% of its ticks late", *r.late_pct);
    return std::string(b);
  }
  return std::nullopt;
}

// Over the runs of one vendor (ascending size, each size run --repeat
// times): the largest size every run of which held, and the first size with
// a run that did not, with the first such run's reason. One bad run of a
// size is enough: "held" means held in every run.
struct HeldVerdict {
  std::optional<uint32_t> largest_held;
  std::optional<uint32_t> first_not_held;
  std::string why;
};
inline HeldVerdict held_verdict(const std::vector<ScaleRun>& runs, uint32_t ticks) {
  HeldVerdict v;
  for (std::size_t i = 0; i < runs.size() && !v.first_not_held; ++i) {
    const uint32_t n = runs[i].uavs;
    std::optional<std::string> worst;
    std::size_t j = i;
    for (; j < runs.size() && runs[j].uavs == n; ++j) {
      if (!worst) worst = why_not_held(runs[j], ticks);
    }
    if (worst) {
      v.first_not_held = n;
      v.why = *worst;
    } else {
      v.largest_held = n;
    }
    i = j - 1;
  }
  return v;
}

// What --help says after the options: what is measured and how.
extern const char* const kBenchScaleFooter;

// Returns 0 if every run was made (a run that failed is a row, not an
// error), 2 on bad options, 5 if the results cannot be written, 130 if
// interrupted.
int run_bench_scale(const BenchScaleOptions& o);

}  // namespace pheromesh::cli
