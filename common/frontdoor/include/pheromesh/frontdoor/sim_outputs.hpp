// What a finished in-process simulation leaves in OUT (docs/outputs.md), as
// `pheromesh sim`, `pheromesh sweep` and the Python package's sim() compute
// it: the same metrics.json object, the same files.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "pheromesh/core/simulator.hpp"

namespace pheromesh::frontdoor {

// OUT/metrics.json of a finished simulation that took `wall_seconds`, as
// `pheromesh sim` writes it (also `pheromesh sweep`'s runs).
nlohmann::json sim_metrics(const core::Simulator& sim, double wall_seconds);

// OUT/final_field.txt of a finished simulation; false if it cannot be written.
bool write_sim_field(const core::Simulator& sim, const std::string& path);

// Everything `pheromesh sim` leaves in `out_dir` after metrics.json
// (docs/outputs.md): series.csv, final_field.txt, final_field.csv, and
// tracks.csv if the simulator kept tracks. "" or the first error.
std::string write_sim_outputs(const core::Simulator& sim, const std::string& out_dir);

}  // namespace pheromesh::frontdoor
