// A UAV's or place agent's side of the lockstep protocol, without DDS
// (docs/architecture.md, "Time"): the conductor's LockstepConductor has its
// counterpart here. The shell hands it every clock sample it takes from the
// bus, whenever it takes them (also while it waits inside a phase), and asks
// it which phase to run next. Time is passed in, so tests drive it by hand.
//
// * The first clock sample names the conductor (the DDS writer the bus
//   identifies, ClockMsg::writer): a clock written by anyone else is refused
//   and counted, whatever it carries (a forged Stop would end the run;
//   core/plausibility.hpp). A UAV hears the clock as the place agents that
//   may serve it relay it (the lockstep tree): its home's and its backup's,
//   each with its standbys - `sources` writers, each relaying every clock
//   from before tick 0, so the first `sources` writers heard are they and a
//   writer heard after them is refused. (With DDS Security only a place
//   agent may write a relayed clock at all: bus/security.cpp.)
// * Every accepted sample, a re-sent one too, tells the ConductorWatch that
//   the conductor lives; a silence past its limit means it is gone.
// * Each phase of this process's kind runs once, in tick order: a clock of a
//   tick already done (a re-send) is not a new phase.
// * Regions a clock lists as absent (a place agent killed at a tick without
//   a standby, core/faults.hpp) are remembered with the first tick listing them.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "pheromesh/core/conductor.hpp"
#include "pheromesh/core/messages.hpp"

namespace pheromesh::core {

class LockstepFollower {
 public:
  using Clock = std::chrono::steady_clock;

  // `mine`: ClockPhase::Uav for a UAV, ClockPhase::Place for a place agent;
  // `sources`: the writers whose clock it accepts (1: the conductor).
  LockstepFollower(ClockPhase mine, ConductorWatch watch, uint32_t sources = 1)
      : mine_(mine), watch_(watch), sources_(sources == 0 ? 1 : sources) {}

  // Clock samples as taken from the bus (moved out of `taken`, which is left
  // empty). Returns those refused as another writer's; copies of the
  // accepted ones go to `accepted` if given (a place agent relays them).
  std::vector<ClockMsg> offer(std::vector<ClockMsg>& taken, Clock::time_point now,
                              std::vector<ClockMsg>* accepted = nullptr);

  // The next phase of this process's kind to run, oldest first, or nothing.
  // A Stop among the samples before it ends the run (stopped()).
  std::optional<ClockMsg> next_phase();
  // Gives back the phase next_phase() just returned, not run yet: it comes
  // first again (a process that may not run it now without waiting).
  void put_back(ClockMsg c) { pending_.push_front(std::move(c)); }
  // Marks the phase of `tick` done: later clocks of it or of older ticks are re-sends.
  void done(uint32_t tick) { done_ = tick; }
  [[nodiscard]] std::optional<uint32_t> last_done() const { return done_; }
  // The clock the phase of `tick` came with skips ticks after the last one
  // this process ran (a replica that was stopped while the swarm went on).
  [[nodiscard]] bool skips(uint32_t tick) const { return done_ && tick > *done_ + 1; }

  [[nodiscard]] bool stopped() const { return stopped_; }
  [[nodiscard]] bool conductor_lost(Clock::time_point now) const { return watch_.lost(now); }
  [[nodiscard]] const ConductorWatch& watch() const { return watch_; }
  // The highest tick the conductor announced (the plausibility ceiling of received samples).
  [[nodiscard]] uint32_t newest_tick() const { return newest_tick_; }
  // The tick of the first clock that listed region `r` as absent.
  [[nodiscard]] std::optional<uint32_t> absent_since(RegionId r) const;
  [[nodiscard]] const std::map<RegionId, uint32_t>& absent() const { return absent_; }

 private:
  ClockPhase mine_;
  ConductorWatch watch_;
  uint32_t sources_;
  std::vector<uint64_t> latched_;  // the accepted writers, in the order first heard
  std::deque<ClockMsg> pending_;
  std::optional<uint32_t> done_;
  bool stopped_ = false;
  uint32_t newest_tick_ = 0;
  std::map<RegionId, uint32_t> absent_;
};

// The UAV clock of tick k+1 that a place clock of tick k begins
// (ClockMsg::next_uav_phase; LockstepConductor::begin_phase), as the
// conductor would have sent it: its broadcasts, occupancy and absent
// regions, from the same writer. Nothing for any other clock. A place agent
// relays it to the UAVs it serves as it accepts the place clock.
std::optional<ClockMsg> uav_clock_begun_by(const ClockMsg& c);

// Which clocks a place agent relays to the UAVs it serves (the lockstep
// tree), so that a UAV hears one clock a tick, not four:
//  * to the UAVs homed on it: Ready, UAV and Stop clocks; a Place-phase
//    clock (a UAV runs UAV phases only) only when it is a re-send (the
//    conductor re-sends its clock after a quiet second while it waits: it
//    keeps the UAVs' ConductorWatch fed through a long phase) or lists an
//    absent region no clock before did (a UAV remembers the first tick that
//    listed it);
//  * to the UAVs it is the backup of, whose home relays them the clock:
//    Ready and Stop clocks (a UAV latches its relays at Ready), re-sends
//    (their home may be dead but not yet listed absent) and clocks newly
//    listing an absent region; and every UAV clock once any region is
//    absent (it may be their home: this place agent is their gateway now).
class UavClockRelay {
 public:
  struct To {
    bool home = false;     // to the UAVs homed on this place agent
    bool backups = false;  // to the UAVs this place agent backs up
  };
  // Where `c`, accepted from the conductor, goes on to.
  To relays(const ClockMsg& c);

 private:
  std::map<uint8_t, uint32_t> newest_;  // the newest tick seen, per phase
  std::vector<RegionId> absent_;        // the absent regions seen so far
};

}  // namespace pheromesh::core
