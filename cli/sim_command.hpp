#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "pheromesh/core/faults.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"
#include "scenario_overrides.hpp"

namespace pheromesh::cli {

struct SimOptions {
  std::string scenario;
  // --set, --seed, --ticks, --uavs, --standby (run.standby: a standby takes
  // over every killed place agent, as in `run`).
  OverrideFlags overrides;
  std::string out_dir = "out/sim";
  bool quiet = false;
  std::string faults;  // fault schedule in ticks (core::parse_fault_schedule); "" = none
  bool tracks = false;  // also OUT/tracks.csv
  std::string record;   // a console recording of the run for `pheromesh replay`; "" = none
};

// `pheromesh sim`: the whole swarm in this process (core::Simulator), same
// metrics.json and final_field.txt as a lockstep `pheromesh run`.
int run_sim(const SimOptions& o);

// The run itself, with a checked scenario and the whole fault schedule (from
// --faults and the scenario's own faults, merged by the caller).
int simulate(const core::ScenarioConfig& s, const core::FaultSchedule& faults, const SimOptions& o);

// OUT/metrics.json of a finished simulation that took `wall_seconds`, as
// `pheromesh sim` writes it (also `pheromesh sweep`'s runs).
nlohmann::json sim_metrics(const core::Simulator& sim, double wall_seconds);

// OUT/final_field.txt of a finished simulation; false if it cannot be written.
bool write_sim_field(const core::Simulator& sim, const std::string& path);

// Everything `pheromesh sim` leaves in `out_dir` after metrics.json
// (docs/outputs.md): series.csv, final_field.txt, final_field.csv, and
// tracks.csv if the simulator kept tracks. "" or the first error.
std::string write_sim_outputs(const core::Simulator& sim, const std::string& out_dir);

}  // namespace pheromesh::cli
