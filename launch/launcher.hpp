// `pheromesh run`: spawns every place agent, UAV and the ground station of a
// swarm as separate processes on this host, injects faults on a schedule
// (docs/faults.md), stops everything in order and leaves OUT/metrics.json.
//
// Three parts: the RunPlan (launch/run_plan.hpp) decides from the options and
// the scenario what runs, with which arguments and deadlines; the Supervisor
// (launch/supervisor.hpp) starts, watches, faults and stops the processes; the
// metrics merge (launch/metrics_merge.hpp) turns what happened into
// metrics.json and the exit code. The Launcher checks and wires them.
#pragma once

#include <string>

#include "run_plan.hpp"

namespace pheromesh::cli {

class Launcher {
 public:
  explicit Launcher(RunOptions o) : o_(std::move(o)) {}
  // Returns the process exit code: 0 if the run completed and no process died
  // that was not killed on purpose; 1 if one did (or metrics.json is
  // missing); 2 for a scenario, options or fault schedule that cannot run;
  // 3 if a program is missing; 5 if the overridden scenario cannot be written
  // for the processes; 130 if interrupted.
  int run();

 private:
  RunOptions o_;
};

// Folder of the running executable (its siblings are the other binaries).
std::string executable_dir();

}  // namespace pheromesh::cli
