#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "pheromesh/core/faults.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"
#include "pheromesh/frontdoor/sim_outputs.hpp"
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
  bool strict = false;  // a state refused as implausible fails the run (kExitRefusedStates)
};

// The exit code of `sim` and `run` with --strict when a state was refused
// as implausible (docs/exit-codes.md).
inline constexpr int kExitRefusedStates = 9;
// After a run: says what metrics.json "states_refused" holds (a warning per
// line) and, with `strict` and a refusal, fails with the first one.
// Returns the exit code (0 or kExitRefusedStates).
int refused_states_verdict(const nlohmann::json& metrics, bool strict);

// `pheromesh sim`: the whole swarm in this process (core::Simulator), same
// metrics.json and final_field.txt as a lockstep `pheromesh run`.
int run_sim(const SimOptions& o);

// The run itself, with a checked scenario and the whole fault schedule (from
// --faults and the scenario's own faults, merged by the caller).
int simulate(const core::ScenarioConfig& s, const core::FaultSchedule& faults, const SimOptions& o);

// sim_metrics, write_sim_field and write_sim_outputs are the front door's
// (pheromesh/frontdoor/sim_outputs.hpp), shared with the Python package.
using frontdoor::sim_metrics;
using frontdoor::write_sim_field;
using frontdoor::write_sim_outputs;

}  // namespace pheromesh::cli
