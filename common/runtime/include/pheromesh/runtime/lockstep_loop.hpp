// The run loop of a lockstep UAV or place agent, written once: take the
// conductor's clock (core::LockstepFollower latches the conductor and watches
// it), run each new phase of this process's kind, and between clocks re-send
// this tick's samples after a quiet spell (bus/resend.hpp) and sleep on the
// clock reader - until the conductor's Stop, its death, a shutdown request,
// or a phase that asks to leave.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/bus/resend.hpp"
#include "pheromesh/core/lockstep_follower.hpp"
#include "pheromesh/runtime/sample_audit.hpp"

namespace spdlog {
class logger;
}

namespace pheromesh::runtime {

// Takes the clock samples the bus holds and hands them to `follower`; a
// sample of another writer is refused (counted in `audit`); copies of the
// accepted ones go to `accepted` if given. False once the conductor is gone.
bool take_clock(bus::Bus& bus, core::LockstepFollower& follower, SampleAudit& audit,
                std::vector<core::ClockMsg>* accepted = nullptr);

enum class LockstepEnd : uint8_t { Stopped, ConductorLost, ShutDown, Left };
// The exit code of a UAV or place agent whose conductor vanished
// (runtime::run_process uses 2-4; the launcher names it).
inline constexpr int kExitConductorLost = 7;
// Continue: the phase is done. Leave: the process leaves the run. Pending:
// the phase waits for samples that are not here yet; the loop runs it again
// (the same clock) when one of `inputs` arrives, or at the latest after a
// slice, so that the phase can give up at its own deadline.
enum class PhaseOutcome : uint8_t { Continue, Leave, Pending };

struct LockstepLoop {
  bus::Bus& bus;
  core::LockstepFollower& follower;
  bus::LatestResender& resend;
  SampleAudit& audit;
  spdlog::logger& log;
  uint32_t lease_ms = 1000;
  // Called before every round, e.g. to report Ready once the process matched
  // its peers, or (a place agent) to relay the clock and its UAVs' reports.
  std::function<void()> before_round;
  // Runs one phase; the loop marks it done unless it returns Leave or Pending.
  std::function<PhaseOutcome(const core::ClockMsg&)> run_phase;
  // A place agent relays every clock it accepts to the UAVs it serves.
  std::function<void(const core::ClockMsg&)> relay{};
  // A process whose phase answers samples (a UAV: its view in, its state
  // out; a place agent: its inputs, rings and tiles in, its views out) runs
  // it in the thread that received them, a wake-up and a context switch
  // less per sample (docs/architecture.md, "Answering in the receive
  // thread"). `inputs` are the topics whose samples the rounds and phases
  // take (a place agent's: also whatever before_round relays). Where the
  // bus has a receive thread (bus::Bus::on_data), each of their samples
  // runs a round there; elsewhere the main thread sleeps on them. A round
  // never waits: a phase either runs whole if `ready(c)` (unset: always)
  // says it can without waiting, or it runs as far as the samples held let
  // it and says Pending. The main thread keeps watch between rounds (the
  // conductor's death, a shutdown, re-sends after a quiet spell) and runs
  // whatever the receive thread left, a phase that is not ready whole.
  std::function<bool(const core::ClockMsg&)> ready{};
  std::vector<bus::TopicKind> inputs{};

  // Logs the conductor's death ("the conductor (ground station) is gone: ...").
  LockstepEnd run();

 private:
  struct Receiving;
  LockstepEnd run_on_main(Receiving* receiving);
  void round_in_receive_thread(Receiving& r);
  LockstepEnd conductor_gone();
};

}  // namespace pheromesh::runtime
