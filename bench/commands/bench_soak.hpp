// `pheromesh bench soak`: runs one swarm for a long time with a fault every
// so often, and samples the resident memory, open file descriptors and
// threads of every process, by role (uav, place, ground, launcher), to show
// whether anything grows over time (leaks of memory, descriptors, threads).
#pragma once

#include <cstdint>
#include <string>

namespace pheromesh::cli {

struct BenchSoakOptions {
  std::string scenario;
  uint32_t processes = 200;            // UAVs + place agents + ground station (the launcher not counted)
  std::string duration = "1h";         // e.g. 1h, 10m, 90s
  std::string fault_every = "60s";     // one fault per period, rotating through kinds and targets; "0" for none
  std::string sample_every = "10s";
  std::string warmup = "60s";          // left out of the growth fits (discovery, first allocations)
  double rate_hz = 5;                  // [Hz]
  uint32_t lease_ms = 5000;            // [ms], generous: a loaded host stalls
  std::string dds = "cyclone";
  uint32_t domain = 41;  // cells' ports stay below the ephemeral range (bench scale: 40)
  std::string out_dir = "out/bench-soak";
  std::string extra;  // more arguments for `pheromesh run`, split at blanks
};

extern const char* const kBenchSoakFooter;

// 0 if the swarm ran to its end and the results were written; 1 if the
// swarm's launcher failed (the results are still written); 2 on bad
// options; 5 if the results cannot be written; 130 if interrupted.
int run_bench_soak(const BenchSoakOptions& o);

// --- pure parts -------------------------------------------------------------------

// "1h", "10m", "90s", "1500ms", "45" (seconds) -> seconds; < 0 if malformed.
double parse_duration_s(const std::string& text);

// Least-squares slope of y over x (per unit of x); 0 with fewer than two
// distinct x.
double linear_slope(const double* x, const double* y, std::size_t n);

// The fault schedule: one event every `every_s` from `every_s` until
// `duration_s` minus one period, rotating through restart uav, stop place,
// restart place, stop uav and stop ground, over distinct targets.
std::string soak_fault_schedule(double duration_s, double every_s, uint32_t uavs, uint32_t regions);

}  // namespace pheromesh::cli
