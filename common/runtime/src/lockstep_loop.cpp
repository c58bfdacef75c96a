#include "pheromesh/runtime/lockstep_loop.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <optional>
#include <utility>
#include <vector>

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

// What the main thread and the receive thread share while phases may run in
// the latter (LockstepLoop::ready). `work` keeps their rounds apart: the
// receive thread only tries it (it must never wait: it delivers the samples
// the main thread may be waiting for) and, when it is taken, leaves a note
// in `missed` under `note`, so that the main thread goes round again instead
// of sleeping.
struct LockstepLoop::Receiving {
  std::mutex work;
  std::mutex note;
  std::condition_variable noted;
  bool missed = false;             // under note
  std::optional<LockstepEnd> end;  // under note: how a receive-thread round ended the run
  std::exception_ptr failed;       // under note: what a receive-thread round threw
  uint64_t phases_here = 0;        // under work: phases the receive thread ran (a pending one: finished)
  uint64_t phases_main = 0;        // under work: phases the main thread ran (a pending one: finished)
};

namespace {
// The loop whose round runs on this thread now: a write inside a round can
// deliver to one of the process's own readers, and the vendor then calls
// back on the same thread.
thread_local const void* round_here = nullptr;

// Marks this thread as running `loop`'s round while it lives, or while
// enter() .. leave() (the main thread sleeps in between).
class RoundHere {
 public:
  explicit RoundHere(const void* loop, bool now = true) : loop_(loop) {
    if (now) enter();
  }
  ~RoundHere() { leave(); }
  RoundHere(const RoundHere&) = delete;
  RoundHere& operator=(const RoundHere&) = delete;
  void enter() {
    if (!in_) before_ = std::exchange(round_here, loop_);
    in_ = true;
  }
  void leave() {
    if (in_) round_here = before_;
    in_ = false;
  }

 private:
  const void* loop_;
  const void* before_ = nullptr;
  bool in_ = false;
};
}  // namespace

LockstepEnd LockstepLoop::conductor_gone() {
  const auto& w = follower.watch();
  const auto last = follower.last_done();
  log.error(
      "the conductor (ground station) is gone: no lockstep clock for {:.1f} s ({} leases of {} ms) after tick {}; "
      "stopping",
      std::chrono::duration<double>(w.silence(Clock::now())).count(), w.limit() / std::chrono::milliseconds(lease_ms),
      lease_ms, last ? static_cast<int64_t>(*last) : -1);
  return LockstepEnd::ConductorLost;
}

LockstepEnd LockstepLoop::run() {
  if (inputs.empty()) return run_on_main(nullptr);
  Receiving receiving;
  if (!bus.on_data(inputs, [this, &receiving] { round_in_receive_thread(receiving); })) return run_on_main(nullptr);
  LockstepEnd end = LockstepEnd::Stopped;
  try {
    end = run_on_main(&receiving);
  } catch (...) {
    bus.on_data({}, {});  // returns once no receive-thread round is under way
    throw;
  }
  bus.on_data({}, {});
  log.debug("lockstep: {} phases ran in the receive thread, {} in the main thread", receiving.phases_here,
            receiving.phases_main);
  return end;
}

void LockstepLoop::round_in_receive_thread(Receiving& r) {
  const auto note = [&](auto&& set) {
    {
      std::lock_guard<std::mutex> lock(r.note);
      set();
    }
    r.noted.notify_one();
  };
  if (round_here == this || !r.work.try_lock()) {
    note([&] { r.missed = true; });
    return;
  }
  std::lock_guard<std::mutex> work(r.work, std::adopt_lock);
  const RoundHere here(this);
  {
    std::lock_guard<std::mutex> lock(r.note);
    if (r.end || r.failed) return;
  }
  try {
    if (before_round) before_round();
    std::vector<core::ClockMsg> accepted;
    take_clock(bus, follower, audit, relay ? &accepted : nullptr);
    for (const auto& c : accepted) relay(c);
    while (auto c = follower.next_phase()) {
      if (ready && !ready(*c)) {
        follower.put_back(std::move(*c));  // its main thread waits for what it lacks, or its next sample brings it
        break;
      }
      const PhaseOutcome o = run_phase(*c);
      if (o == PhaseOutcome::Leave) {
        note([&] { r.end = LockstepEnd::Left; });
        return;
      }
      if (o == PhaseOutcome::Pending) {
        follower.put_back(std::move(*c));  // the sample it lacks runs it on
        break;
      }
      ++r.phases_here;
      follower.done(c->tick);
    }
    if (follower.stopped()) note([&] { r.end = LockstepEnd::Stopped; });
  } catch (...) {
    // Not through the vendor's C frames: the main thread throws it.
    note([&] { r.failed = std::current_exception(); });
  }
}

LockstepEnd LockstepLoop::run_on_main(Receiving* receiving) {
  std::unique_lock<std::mutex> work;
  RoundHere here(this, receiving != nullptr);
  if (receiving != nullptr) work = std::unique_lock<std::mutex>(receiving->work);
  // After a round of the receive thread: how it ended the run, if it did.
  const auto ended_there = [&]() -> std::optional<LockstepEnd> {
    if (receiving == nullptr) return std::nullopt;
    std::lock_guard<std::mutex> lock(receiving->note);
    if (receiving->failed) std::rethrow_exception(receiving->failed);
    return receiving->end;
  };
  while (!follower.stopped()) {
    if (auto end = ended_there()) return *end;
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
      const PhaseOutcome o = run_phase(*c);
      if (o == PhaseOutcome::Leave) return LockstepEnd::Left;
      if (o == PhaseOutcome::Pending) {
        follower.put_back(std::move(*c));
        break;
      }
      if (receiving != nullptr) ++receiving->phases_main;
      follower.done(c->tick);
      ran = true;
    }
    if (ran || follower.stopped()) continue;
    if (follower.conductor_lost(Clock::now())) return conductor_gone();
    if (resend.resend_if_quiet()) {
      log.debug("tick {}: nothing new for 1 s; re-sent this tick's samples", follower.last_done().value_or(0));
    }
    const auto until = Clock::now() + kShutdownSlice;
    if (receiving != nullptr) {
      // The receive thread runs the phases now; this thread sleeps until it
      // could not (it found a round under way here), or it ended the run,
      // or the slice is over.
      here.leave();
      work.unlock();
      {
        std::unique_lock<std::mutex> lock(receiving->note);
        receiving->noted.wait_until(lock, until, [&] {
          return receiving->missed || receiving->end || receiving->failed || shutdown_requested();
        });
        receiving->missed = false;
      }
      work.lock();
      here.enter();
    } else if (!inputs.empty()) {
      bus.wait_any(inputs, until);  // a bus without a receive thread
    } else {
      // A UAV: its clock comes relayed or in its view (bus::Bus::take_clock).
      bus.wait({bus::TopicKind::Clock, bus::TopicKind::RelayedClock, bus::TopicKind::View}, until);
    }
  }
  if (auto end = ended_there()) return *end;
  return LockstepEnd::Stopped;
}

}  // namespace pheromesh::runtime
