#include "pheromesh/runtime/lockstep_loop.hpp"

#include <spdlog/spdlog.h>

#include <chrono>

#include "pheromesh/runtime/process.hpp"

namespace pheromesh::runtime {

using Clock = std::chrono::steady_clock;

bool take_clock(bus::Bus& bus, core::LockstepFollower& follower, SampleAudit& audit,
                std::vector<core::ClockMsg>* accepted) {
  std::vector<core::ClockMsg> taken;
  bus.take_clock(taken);
  // The first clock samples name their writers (a place agent's: the
  // conductor; a UAV's: the place agents that relay it the clock): on an
  // open domain anyone can write a clock (a forged Stop would end the run),
  // but no one can write through another process's DDS writer.
  for (const auto& c : follower.offer(taken, Clock::now(), accepted)) {
    audit.refuse(core::Refusal::ForeignClock,
                 fmt::format("a clock sample of tick {} phase {} from another writer", c.tick, c.phase));
  }
  return !follower.conductor_lost(Clock::now());
}

LockstepEnd LockstepLoop::run() {
  const auto conductor_gone = [&] {
    const auto& w = follower.watch();
    const auto last = follower.last_done();
    log.error(
        "the conductor (ground station) is gone: no lockstep clock for {:.1f} s ({} leases of {} ms) after tick {}; "
        "stopping",
        std::chrono::duration<double>(w.silence(Clock::now())).count(), w.limit() / std::chrono::milliseconds(lease_ms),
        lease_ms, last ? static_cast<int64_t>(*last) : -1);
    return LockstepEnd::ConductorLost;
  };
  while (!follower.stopped()) {
    if (shutdown_requested()) {
      // Asked to stop after the conductor vanished: that is why the run
      // ends. (Once every UAV ended, the launcher stops the place agents;
      // one whose place phase still waited for samples that never came
      // heard the stop before it looked at the clock again.)
      return follower.conductor_lost(Clock::now()) ? conductor_gone() : LockstepEnd::ShutDown;
    }
    if (before_round) before_round();
    std::vector<core::ClockMsg> accepted;
    take_clock(bus, follower, audit, relay ? &accepted : nullptr);
    for (const auto& c : accepted) relay(c);
    bool ran = false;
    while (auto c = follower.next_phase()) {
      if (run_phase(*c) == PhaseOutcome::Leave) return LockstepEnd::Left;
      follower.done(c->tick);
      ran = true;
    }
    if (ran || follower.stopped()) continue;
    if (follower.conductor_lost(Clock::now())) return conductor_gone();
    if (resend.resend_if_quiet()) {
      log.debug("tick {}: nothing new for 1 s; re-sent this tick's samples", follower.last_done().value_or(0));
    }
    const auto until = Clock::now() + kShutdownSlice;
    if (wake_on_reports) {
      // A place agent: whatever it relays (before_round takes it all).
      bus.wait({bus::TopicKind::Clock, bus::TopicKind::PhaseDone, bus::TopicKind::UavHome, bus::TopicKind::Detection,
                bus::TopicKind::Broadcast, bus::TopicKind::Command},
               until);
    } else {
      // A UAV: its clock comes relayed or in its view (bus::Bus::take_clock).
      bus.wait({bus::TopicKind::Clock, bus::TopicKind::RelayedClock, bus::TopicKind::View}, until);
    }
  }
  return LockstepEnd::Stopped;
}

}  // namespace pheromesh::runtime
