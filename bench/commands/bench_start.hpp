// What a process of the swarm costs to start: the CPU (user + system, from
// the kernel's accounting of the child) of a UAV program started alone,
// again and again, against a process that does nothing (/bin/true) measured
// in the same run. (Not its peak memory: the kernel counts a child's from
// before its exec, when it still shares this process's pages.) A big swarm starts
// thousands of UAVs; on a busy host their start is what bounds discovery
// (docs/benchmarks.md, "A lighter process").
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "pheromesh/core/sample_summary.hpp"

namespace pheromesh::cli {

struct BenchStartOptions {
  std::string scenario;  // the UAVs' scenario (resolved path)
  std::vector<std::string> dds = {"cyclone", "fastdds"};
  uint32_t runs = 30;        // starts of each kind
  uint32_t domain = 47;      // DDS domain of the UAVs started alone
  std::string programs_dir;  // this build's bin folder (its pheromesh-uav)
  std::string baseline;      // another build's bin folder (its pheromesh-uav), or empty
  double wait_s = 4;         // a UAV waiting this long for a start that does not come (0: no such row; else >= 3)
};

// One kind of start, `runs` times.
struct StartCost {
  std::string what;     // "a process that does nothing", ...
  std::string build;    // "this", "baseline" or "" (the bare process)
  std::string command;  // as run, program by its file name
  core::SampleSummary cpu_ms;
  uint32_t failed = 0;  // runs that did not exit 0
};

// The command lines of one build's UAV program (`uav` its path): loaded and
// gone (--help), and per vendor started alone for one tick with no place
// agent and no ground station, and (with `wait_s` > 0) started with a control
// key, so that it waits `wait_s` for a ground station's start that does not
// come, with a big swarm's lease (5 s), before its tick.
struct StartCommand {
  std::string what;
  std::vector<std::string> argv;
  std::vector<std::string> env = {};  // added to this process's environment, NAME=VALUE
  std::string waits_beside = {};      // a waiting row: the `what` of the same start without the wait
};
std::vector<StartCommand> start_commands(const std::string& uav, const BenchStartOptions& o);

// Runs `argv` (its environment this process's, with `env` over it) with its
// output to /dev/null and waits: the CPU [ms] of the child, and whether it
// exited 0; with a `window` [from, to) in seconds after the spawn, also what
// the child's threads ran in it (/proc/PID/task/*/schedstat, read at both ends).
struct ChildCost {
  double cpu_ms = 0;
  bool ok = false;
  std::optional<double> window_cpu_ms;
};
struct Window {
  double from_s = 0, to_s = 0;
};
ChildCost run_child(const std::vector<std::string>& argv, const std::vector<std::string>& env = {},
                    std::optional<Window> window = std::nullopt);
// The waiting rows' window: from 1.5 s after the spawn (the UAV has started
// and waits) to 0.5 s before its wait ends; nothing if `wait_s` < 3.
std::optional<Window> waiting_window(double wait_s);

int run_bench_start(const BenchStartOptions& o);

extern const char* const kBenchStartFooter;

}  // namespace pheromesh::cli
