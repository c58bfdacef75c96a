// metrics.json and the final-field dump, written the same way by the ground
// station and the simulator.
#pragma once

#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "pheromesh/core/run_metrics.hpp"

namespace pheromesh::report {

// Who ran the swarm. The simulator's metrics.json leaves out what only
// processes have: DDS traffic, discovery, liveliness, duplicates
// (docs/outputs.md, docs/schema/metrics.schema.json).
enum class Runner : uint8_t { Processes, Simulator };

struct RunInfo {
  std::string transport;  // "cyclone", "fastdds", ... (processes only)
  std::string clock;      // "realtime" or "lockstep" (the simulator's schedule is lockstep's)
  Runner runner = Runner::Processes;
  uint32_t uavs_expected = 0;
  // Seconds from the launch ($PHEROMESH_RUN_T0_MS) until the ground station
  // had heard every expected UAV and place agent; unset if it never did.
  std::optional<double> discovery_s;
  // Lockstep: how long each conducted UAV and place phase took [ms]
  // (core::LockstepConductor::phase_times); metrics.json "lockstep".
  std::vector<double> uav_phase_ms;
  std::vector<double> place_phase_ms;
  // Payload bytes of every sample the ground station took (core::payload_bytes).
  std::optional<uint64_t> ground_bytes_received;
};

// {"n", "mean", "p50", "p90", "p99", "max"} of durations [ms] (nearest-rank
// percentiles); {"n": 0} when there are none.
nlohmann::json duration_summary(std::vector<double> ms);

// OUT/metrics.json. Keys that do not apply to a run are left out rather than
// written as null or 0: those of processes in the simulator's, those of
// realtime timekeeping in lockstep runs, leader_arrival_tick without one.
nlohmann::json metrics_json(const core::RunRecorder& r, const RunInfo& info);

// What `sim` and `run` say when states were refused as implausible: one
// line per UAV (the first few) and the total, from metrics.json
// "states_refused"; none when nothing was refused.
std::vector<std::string> refused_state_lines(const nlohmann::json& metrics);
// The earliest refusal of metrics.json "states_refused" in plain words
// (core::describe_refusal; the lowest UAV id of the earliest tick), if any:
// what `--strict` fails the run with.
std::optional<std::string> first_refusal_line(const nlohmann::json& metrics);

// The ticks of metrics.json "coverage_series": every kCoverageSeriesEvery-th
// tick and the last one (series.csv has every tick).
inline constexpr uint32_t kCoverageSeriesEvery = 10;

// The final pheromone field, every layer, in a text form that round-trips
// floats exactly ("%.9g"): `layer NAME` then one line per row. `value` may
// return NaN for cells it does not know. Written atomically.
using FieldReader = std::function<float(int layer, core::Cell c)>;
bool write_field(const std::string& path, const core::MapGeometry& geo, const std::vector<std::string>& layers,
                 const FieldReader& value);

// The JSON text of `j`; invalid UTF-8 in its strings becomes U+FFFD instead
// of an exception. Every JSON file and answer pheromesh writes goes through it.
std::string json_text(const nlohmann::json& j, int indent = 2);

// Writes `j` to DIR/FILE atomically (core/atomic_file.hpp), creating DIR;
// false (and a message in `error`) on failure.
bool write_json(const std::string& dir, const std::string& file, const nlohmann::json& j, std::string& error);

}  // namespace pheromesh::report
