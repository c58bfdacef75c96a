// One run of a scenario for an experiment, in the in-process simulator and,
// with `pheromesh experiment NAME --distributed`, also as real processes
// (`pheromesh run --clock lockstep`), whose numbers must equal the
// simulator's for the same scenario text and seed.
//
// An experiment that wants a run checked on the real swarm builds its
// scenario from text (core::load_scenario / core::patch_scenario) and may
// change nothing of it in memory but the seed: the processes get the text.
// A change made in memory only makes the two runs differ, and the check
// reports it: it cannot pass silently.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"

namespace pheromesh::cli::experiments {

// What a run is judged by: the quantities of metrics.json that the ground
// station and the simulator both compute from their RunRecorder.
struct RunNumbers {
  uint32_t ticks = 0;
  double coverage = 0;
  uint64_t covered_cells = 0;
  uint32_t targets_found = 0;
  std::vector<uint32_t> acquisition_ticks;
  std::vector<uint32_t> revisit_response_ticks;
  std::optional<uint32_t> leader_arrival_tick;
  uint64_t deposits_sent = 0;
  std::map<std::string, double> field;  // metrics.json "field" (policy.hpp field_summary)
};

RunNumbers numbers_of(const core::RunRecorder& r);
// The same from a metrics.json text; false with a message if a key is missing.
bool numbers_from_metrics_json(const std::string& json, RunNumbers& out, std::string& error);
// "" when equal, else the first differences, one per line ("coverage: 0.51 vs 0.52").
std::string differences(const RunNumbers& sim, const RunNumbers& processes);

struct DistributedOptions {
  bool enabled = false;
  std::string dds = "cyclone";  // pheromesh run --dds
  uint32_t domain = 0;          // pheromesh run --domain (0: the launcher's default)
  std::string work_dir;         // scenario texts and run folders (default OUT/distributed)
  std::string program;          // the `pheromesh` binary (default /proc/self/exe)
};

// One run flown by both.
struct DistributedCheck {
  std::string label;  // "shao2020-50x50 seed 3"
  uint64_t seed = 0;
  bool equal = false;
  std::string differences;  // or why the process run failed
  double sim_seconds = 0, process_seconds = 0;
  std::string run_dir;
};

// Set by `pheromesh experiment` before an experiment runs.
void set_distributed(const DistributedOptions& o);
[[nodiscard]] const DistributedOptions& distributed_options();
// The checks made since the last set_distributed().
[[nodiscard]] const std::vector<DistributedCheck>& distributed_checks();

// Runs `s` in the simulator, calling on_tick(sim, k) after each tick k, and
// returns its numbers. With --distributed and `check` set, also runs s.
// source_text with run.seed = s.seed as real processes in lockstep and records a
// DistributedCheck. Runs that only explore (sensitivity sweeps) pass
// check = false.
RunNumbers fly(const core::ScenarioConfig& s, const std::function<void(const core::Simulator&, uint32_t)>& on_tick = {},
               bool check = true);

}  // namespace pheromesh::cli::experiments
