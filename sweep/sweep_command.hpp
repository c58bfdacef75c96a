// `pheromesh sweep`: a scenario run on the in-process simulator for every
// combination of the values of its `--set PATH=V1,V2,...` flags, times every
// seed of `--seeds`, in parallel (--jobs); resumable (each run's folder gets
// its metrics.json last and atomically, and a re-run in the same OUT keeps
// the runs that have one); then runs.csv, summary.csv, SVG plots and
// sweep.md (sweep_report.hpp). With --distributed a sample of the runs is
// also flown as `pheromesh run --clock lockstep` and checked against the
// simulator. docs/sweeps.md.
#pragma once

#include <cstdint>
#include <string>

#include "cli/scenario_overrides.hpp"

namespace pheromesh::cli {

struct SweepOptions {
  std::string scenario;  // a path (resolved by the CLI)
  // --set PATH=V1,V2,... (lists, see sweep_grid.hpp), --ticks, --uavs (fixed).
  OverrideFlags overrides;
  std::string seeds = "1-10";
  unsigned jobs = 0;    // 0: the host's hardware threads
  std::string out_dir;  // default out/sweeps/<scenario name>
  bool distributed = false;
  unsigned distributed_sample = 1;  // runs flown as processes
  std::string dds = "cyclone";      // their vendor(s), as `pheromesh run --dds`
  uint32_t domain = 0;              // their DDS domain (0: the launcher's)
  bool quiet = false;               // no progress bar
  std::string command;              // the command line as typed, for sweep.md
  // The `pheromesh` that flies --distributed runs (default: this executable).
  std::string program;
};

// Exit codes: 0 done; 2 bad flags, a refused combination, or an OUT that
// holds another sweep; 1 a run failed; 4 a --distributed run differs from
// the simulator; 5 an output file could not be written.
int run_sweep(const SweepOptions& o);

// argv as one shell line, each argument quoted when the shell would split or
// expand it ('--set a="x, y"'), for sweep.md.
std::string command_line(int argc, const char* const* argv);

// The footer of `pheromesh sweep --help`.
extern const char* const kSweepFooter;

}  // namespace pheromesh::cli
