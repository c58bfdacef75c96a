// What the host's hardware threads give when they are all busy at once: a
// CPU-bound loop on one thread alone, then on every hardware thread at the
// same time, and the work they did together as a multiple of the one's. On
// two cores of their own the figure is near 2; on two hyper-threads of one
// core, or on virtual CPUs that a busy hypervisor shares out, it is less:
// a CPU-second does less work while all are busy, and a benchmark that
// keeps them busy counts more CPU for the same work. Beside it, what a
// wake-up costs: one thread waking another over a pipe and being woken
// back, which a swarm of processes does at every sample; a virtual machine
// can pay several times a bare host's there while its loop runs as fast.
// `bench scale` and `bench lockstep` print both beside their results, so
// that runs made on different days can be read side by side.
#pragma once

#include <chrono>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace pheromesh::cli {

struct HostCapacity {
  unsigned threads = 0;  // hardware threads busy at once
  double one_rate = 0;   // loop rounds a second, one thread alone
  double all_rate = 0;   // loop rounds a second, summed over `threads` threads at once
  // The work of `threads` threads at once as a multiple of one's (0: not measured).
  [[nodiscard]] double ratio() const { return one_rate > 0 ? all_rate / one_rate : 0.0; }
  // A wake-up of another thread over a pipe, the mean of a ping-pong [µs].
  std::optional<double> wake_us;
  // "2 hardware threads busy at once did 1.25 times the work of one (a
  // CPU-bound loop; ...); a wake-up of another thread over a pipe took 6.2 µs"
  [[nodiscard]] std::string describe() const;
  // As scale.json and lockstep.json carry it: threads, ratio, wake_us (null
  // when not measured).
  [[nodiscard]] nlohmann::json to_json() const;
};

// One thread's loop: the rounds it ran and the seconds they took.
struct LoopRun {
  uint64_t rounds = 0;
  double seconds = 0;
};

// From the runs measured: `alone` on one thread, `together` one per thread
// at once. Runs of no time count as nothing.
[[nodiscard]] HostCapacity host_capacity_from(const LoopRun& alone, const std::vector<LoopRun>& together);

// The mean time of one wake-up [µs] over `round_trips` ping-pongs between
// this thread and another over two pipes (two wake-ups each), or over those
// done within `bound`; nothing if the pipes or the thread could not be made.
[[nodiscard]] std::optional<double> measure_wake_us(uint32_t round_trips, std::chrono::milliseconds bound);

// Runs the loop for `each` on one thread, then on `threads` threads at once
// (std::thread::hardware_concurrency() when 0), then the ping-pong.
[[nodiscard]] HostCapacity measure_host_capacity(std::chrono::milliseconds each, unsigned threads = 0);

}  // namespace pheromesh::cli
