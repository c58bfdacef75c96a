#pragma once
#include <cstdint>
#include <string>

#include "cli/scenario_overrides.hpp"

namespace pheromesh::cli {

struct ExperimentOptions {
  std::string name;
  uint32_t runs = 0;  // 0: the paper's run count
  std::string out_dir;  // default out/experiments/NAME
  bool list = false;
  bool all = false;  // --all: every experiment, and OUT/summary.md (OUT default out/experiments)
  // --distributed: each checked run is also flown by real processes in
  // lockstep (experiments/flight.hpp) and must give the simulator's numbers.
  bool distributed = false;
  std::string dds = "cyclone";
  uint32_t domain = 0;
  // --set: applied to every scenario file the experiment reads (not run.seed,
  // which the experiment sets per run).
  OverrideFlags overrides;
};

// `pheromesh experiment`: list, or run one experiment and write its report.
int run_experiment_command(const ExperimentOptions& o);

}  // namespace pheromesh::cli
