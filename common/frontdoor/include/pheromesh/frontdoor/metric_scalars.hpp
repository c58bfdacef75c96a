// The scalar metrics of one metrics.json, as `pheromesh sweep`'s runs.csv
// and the Python package's sweep() tabulate them.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>

namespace pheromesh::frontdoor {

// The scalars of one metrics.json, nested objects flattened with dotted
// names ("coverage", "field.found_all_tick", "uav_status.0.x"): numbers, and
// booleans as 0 / 1; null becomes NaN (a quantity the run did not reach,
// such as leader_arrival_tick). Strings and arrays (series) are left out, and
// so is "seed", which runs.csv has as a column of its own.
using Scalars = std::map<std::string, double>;
Scalars flatten_scalars(const nlohmann::json& metrics);

// Metrics that measure this host's speed, not the swarm: they differ from
// one run of the same seed to the next, so they are in runs.csv and
// summary.csv but never plotted, and a comparison of two sweeps leaves them
// out.
bool is_timing_metric(const std::string& name);

}  // namespace pheromesh::frontdoor
