// What the host's hardware threads give when they are all busy at once: a
// CPU-bound loop on one thread alone, then on every hardware thread at the
// same time, and the work they did together as a multiple of the one's. On
// two cores of their own the figure is near 2; on two hyper-threads of one
// core, or on virtual CPUs that a busy hypervisor shares out, it is less:
// a CPU-second does less work while all are busy, and a benchmark that
// keeps them busy counts more CPU for the same work. `bench scale` and `bench lockstep` print it beside their
// results, so that runs made on different days can be read side by side.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace pheromesh::cli {

struct HostCapacity {
  unsigned threads = 0;  // hardware threads busy at once
  double one_rate = 0;   // loop rounds a second, one thread alone
  double all_rate = 0;   // loop rounds a second, summed over `threads` threads at once
  // The work of `threads` threads at once as a multiple of one's (0: not measured).
  [[nodiscard]] double ratio() const { return one_rate > 0 ? all_rate / one_rate : 0.0; }
  // "2 hardware threads busy at once did 1.25 times the work of one"
  [[nodiscard]] std::string describe() const;
};

// One thread's loop: the rounds it ran and the seconds they took.
struct LoopRun {
  uint64_t rounds = 0;
  double seconds = 0;
};

// From the runs measured: `alone` on one thread, `together` one per thread
// at once. Runs of no time count as nothing.
[[nodiscard]] HostCapacity host_capacity_from(const LoopRun& alone, const std::vector<LoopRun>& together);

// Runs the loop for `each` on one thread, then on `threads` threads at once
// (std::thread::hardware_concurrency() when 0).
[[nodiscard]] HostCapacity measure_host_capacity(std::chrono::milliseconds each, unsigned threads = 0);

}  // namespace pheromesh::cli
