// What `pheromesh sweep` runs: a grid of scenario overrides (every
// combination of the values given to each `--set PATH=V1,V2,...`) times a
// list of seeds (`--seeds 1-20`). Pure: no files, no simulator; the command
// (sweep_command.cpp) loads and runs what this describes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pheromesh/core/result.hpp"
#include "cli/scenario_overrides.hpp"

namespace pheromesh::cli::sweep {

// One parameter of the sweep: a field path and the values it takes. A
// parameter with one value is a fixed override, recorded like the others.
struct Parameter {
  std::string path;                 // "shao.aco.alpha"
  std::vector<std::string> values;  // as typed: "1", "2.5", "frontier"
  // The flag that gave it: "--set", or a flag that stands for a field
  // ("--ticks", "--uavs", "--rate"), which takes one value.
  std::string flag = "--set";

  [[nodiscard]] bool swept() const { return values.size() > 1; }
  // How the user gave it: "--set shao.aco.alpha=1,2", "--ticks 30".
  [[nodiscard]] std::string source() const;
};

// The most runs one sweep may hold (a typo such as --seeds 1-1000000000
// is refused instead of filling the disk).
inline constexpr uint64_t kMaxRuns = 1'000'000;

// `--seeds`: comma-separated items, each a seed ("7") or an inclusive range
// ("1-20"); "1-3,9" is 1 2 3 9. Refused, naming the item: an empty item, a
// non-number, a range whose end is below its start, a seed given twice, more
// than kMaxRuns seeds. The order given is kept.
core::Result<std::vector<uint64_t>> parse_seeds(const std::string& text);

// The values of one `--set PATH=V1,V2,...`: split at commas outside double
// quotes ("kill uav:1,2 @4t" in quotes is one value; the override machinery
// removes the quotes). Refused, naming the argument: no '=', an empty path,
// an empty value, a value given twice.
core::Result<Parameter> parse_set_list(const std::string& arg);

// Every parameter of the sweep's flags, in the order given: the field flags
// of `flags` (--uavs, --ticks, --rate) first, then each --set. Refused: a
// path given twice (by two --set, or by --set and the flag that stands for
// it), run.seed (the sweep's seeds come from --seeds), --seed, --duration.
core::Result<std::vector<Parameter>> parameters_of(const OverrideFlags& flags);

// One combination of the parameters' values: index i into each parameter's
// values.
struct Cell {
  std::size_t index = 0;            // position in the grid (first parameter slowest)
  std::vector<std::size_t> choice;  // per parameter, the index of its value
};

// The Cartesian product of the parameters' values, first parameter slowest
// (as nested loops in the order the flags were given). One cell, with no
// choice, when there are no parameters.
std::vector<Cell> grid(const std::vector<Parameter>& params);

// The overrides of one cell (and seed), as flags for load_overridden: each
// --set a single PATH=VALUE, the field flags their one value, --seed `seed`.
// Errors about a field then name "--set PATH=VALUE" or "--ticks N".
OverrideFlags cell_flags(const std::vector<Parameter>& params, const Cell& cell, uint64_t seed);

// "shao.aco.alpha=2, swarm.uavs=4": a cell's values, for messages and tables.
std::string describe_cell(const std::vector<Parameter>& params, const Cell& cell);

// One run: a cell and a seed.
struct Run {
  std::size_t cell = 0;
  uint64_t seed = 0;
  std::string id;  // "c003-s7": the run's folder under OUT/runs
};

// Every run, cell by cell, each cell's seeds in the order given. Empty
// (with an error) when cells x seeds exceeds kMaxRuns.
core::Result<std::vector<Run>> runs_of(const std::vector<Cell>& cells, const std::vector<uint64_t>& seeds);

// `k` runs spread evenly over `runs` (the first, then every n/k-th), for
// --distributed: all of them when k >= runs.size().
std::vector<std::size_t> sample_runs(std::size_t run_count, std::size_t k);

// The sweep's definition, stored as OUT/sweep.json: what a re-run in the same
// OUT must equal to reuse the runs found there.
nlohmann::json definition_json(const std::string& scenario_name, const std::vector<Parameter>& params,
                               const std::vector<uint64_t>& seeds);
// "" when `stored` equals `wanted`, else what differs, one clause per
// difference ("seeds: 1-10 before, 1-20 now").
std::string definition_change(const nlohmann::json& stored, const nlohmann::json& wanted);

// "1-10", "1-3, 7, 9": seeds in short form, for reports.
std::string describe_seeds(const std::vector<uint64_t>& seeds);

}  // namespace pheromesh::cli::sweep
