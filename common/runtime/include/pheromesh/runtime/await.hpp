// The one wait loop of the process shells: take what arrived, check whether
// the awaited samples are all here, re-send this process's own samples of the
// phase after a quiet spell (bus/resend.hpp), and sleep on the bus's wait set
// for the kinds that bring them - bounded by a deadline and ended early by a
// shutdown request. Every lockstep wait of the UAV, the place agent and the
// ground station goes through it, so each is bounded the same way.
#pragma once

#include <chrono>
#include <initializer_list>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/bus/resend.hpp"
#include "pheromesh/runtime/process.hpp"

namespace pheromesh::runtime {

enum class Awaited : uint8_t { Done, TimedOut, ShutDown };

struct AwaitBounds {
  std::chrono::milliseconds bound{30000};  // [ms] the whole wait
  std::chrono::milliseconds slice{kShutdownSlice};  // [ms] the longest single sleep on the bus
};

// Calls take() then done() until done() holds; between rounds re-sends
// through `resend` (if given) when it has been quiet, and waits on `bus` for
// samples of `kinds`. Never sleeps past the deadline.
template <typename Take, typename Done>
Awaited await_samples(bus::Bus& bus, std::initializer_list<bus::TopicKind> kinds, AwaitBounds bounds,
                      bus::LatestResender* resend, Take&& take, Done&& done) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + bounds.bound;
  for (;;) {
    take();
    if (done()) return Awaited::Done;
    if (shutdown_requested()) return Awaited::ShutDown;
    if (Clock::now() > deadline) return Awaited::TimedOut;
    if (resend != nullptr) resend->resend_if_quiet();
    bus.wait(kinds, std::min(deadline, Clock::now() + bounds.slice));
  }
}

}  // namespace pheromesh::runtime
