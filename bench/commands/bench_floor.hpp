// The network floor of the benchmarks: one pheromesh sample down and one back
// up between this process and a child process on loopback (`pheromesh bench
// lockstep-echo`), per vendor pairing. `bench lockstep` times the round trip
// of a bare clock and report (a lockstep tick is about nine such hops);
// `bench scale` sends a clock as large as a UAV's view down and has a report
// as large as its uplink come back, and counts the CPU both processes spent
// per round trip: what one UAV tick cannot cost less than over DDS.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "pheromesh/core/sample_summary.hpp"

namespace pheromesh::cli {

struct FloorOptions {
  std::string pairing = "cyclone";  // "cyclone", "fastdds", "mixed" (this process Cyclone, the child Fast DDS)
  uint32_t domain = 45;
  uint32_t pings = 500;
  std::string out_dir;         // where the child's log goes (echo-<pairing>.log)
  std::size_t down_bytes = 0;  // payload of the sample down (0: a bare clock)
  std::size_t up_bytes = 0;    // payload of the sample back up (0: a bare report)
};

struct Floor {
  std::string pairing;
  core::SampleSummary rtt_ms;
  uint32_t lost = 0;
  std::string error;
  std::size_t down_bytes = 0, up_bytes = 0;  // the payloads as sent (the IDL bounds cap them)
  // CPU of both processes per answered round trip [ms] (every thread, from
  // /proc/<pid>/task/*/schedstat), if it could be read.
  std::optional<double> cpu_ms;
};

Floor measure_floor(const FloorOptions& o);

// The other end (`pheromesh bench lockstep-echo`, hidden): answers every
// clock sample with a PhaseDone of its tick, padded to about `answer_bytes`,
// until a Stop, or until `timeout_s` passes.
struct LockstepEchoOptions {
  std::string dds = "cyclone";
  uint32_t domain = 44;
  double timeout_s = 120;
  std::size_t answer_bytes = 0;
};
int run_lockstep_echo(const LockstepEchoOptions& o);

}  // namespace pheromesh::cli
