// The end of `pheromesh run`: the ground station's metrics.json merged with
// what the launcher saw (every process and how it ended, the faults, the
// resources), and the run's verdict. Pure: the launcher reads and writes the
// files (tests/unit/test_metrics_merge.cpp).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "proc_stats.hpp"
#include "run_plan.hpp"

namespace pheromesh::cli {

// The steady window of a realtime flight: two looks at every process
// (ChildProcess::window_cpu), from a fifth to four fifths of the flight.
struct SteadyWindow {
  double seconds = 0;
  double rate_hz = 0;
  std::optional<UdpCounters> udp_start, udp_end;
};

// What the launcher knows at the end of the run.
struct RunRecord {
  std::span<const ChildProcess> processes;  // every process started, restarts included
  nlohmann::json faults;                    // "faults", "faults_failed", "netns" (Supervisor::fault_metrics)
  uint32_t fault_failures = 0;              // fault events that could not be injected
  std::string dds;                          // DdsPlan::describe()
  HostShare share;
  std::optional<double> resources_sampled_at_s;  // [s] after the first spawn
  std::optional<double> wall_s;                  // [s] first spawn -> every process ended
  int64_t run_t0_unix_ms = 0;                    // the first spawn, Unix time [ms]
  std::optional<UdpCounters> udp_start, udp_end;
  uint32_t ticks_asked = 0;  // each UAV's ticks (RunPlan::ticks); 0: not known, the flight is not judged
  std::optional<SteadyWindow> steady;
};
// metrics.json "steady": what one UAV tick costs the swarm while it flies
// (the window), per role and per thread group; null without a window.
nlohmann::json steady_json(std::span<const ChildProcess> processes, const std::optional<SteadyWindow>& w);

struct MergedMetrics {
  nlohmann::json metrics;
  uint32_t killed = 0;              // on purpose (faults, the console)
  uint32_t crashed = 0;             // ChildProcess::crashed
  uint32_t killed_at_stop = 0;      // ChildProcess::killed_at_stop: hung or slow at the stop, not a crash
  std::vector<std::string> errors;  // each fails the run; to be logged in this order
  // The swarm did not fly what was asked (flight_shortfall): why.
  std::optional<std::string> shortfall;
  // 1 if there is an error or a crashed process, else kExitShortfall if the
  // swarm did not fly what was asked, else 0.
  [[nodiscard]] int exit_code() const {
    if (!errors.empty() || crashed != 0) return 1;
    return shortfall ? kExitShortfall : 0;
  }
  static constexpr int kExitShortfall = 8;  // docs/exit-codes.md
};

// The least share of the UAV ticks asked for that the UAVs nobody killed
// must fly, or the run did not fly the swarm asked for (docs/exit-codes.md).
inline constexpr double kFlownShareRequired = 0.9;
// Whether the swarm of `metrics` (the ground station's) flew what was asked:
// every UAV nobody killed on purpose (`processes`) finished, and together
// they flew at least kFlownShareRequired of `ticks_asked` each (uav_status
// heard_tick; metrics.json "ticks" is the last tick reached, not the ticks
// asked). Nothing when it did; else why, in plain words.
std::optional<std::string> flight_shortfall(const nlohmann::json& metrics, std::span<const ChildProcess> processes,
                                            uint32_t ticks_asked);

// Over several hosts the swarm's metrics.json is the ground station's host's;
// every other host writes what it ran to OUT/host-I.json.
std::string metrics_path(const std::string& out_dir, const HostShare& share);

// `ground`: the ground station's metrics.json, null if it left none (or
// runs on another host); `path`: where the merge goes (for messages).
MergedMetrics merge_metrics(nlohmann::json ground, const RunRecord& run, const std::string& path);

}  // namespace pheromesh::cli
