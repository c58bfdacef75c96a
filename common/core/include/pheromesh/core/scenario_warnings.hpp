// What a valid scenario file holds that its run ignores: not errors, but the
// author should know (`pheromesh validate` prints them, sim and run log them).
#pragma once

#include <string>
#include <vector>

#include "pheromesh/core/scenario.hpp"

namespace pheromesh::core {

// One "FILE:LINE:COL: ..." line per block the scenario's policy does not read
// (a `shao { }` block beside `policy { shostak {} }`), located in the file
// `s` was loaded from (its source_text when it has no file).
std::vector<std::string> scenario_warnings(const ScenarioConfig& s);

}  // namespace pheromesh::core
