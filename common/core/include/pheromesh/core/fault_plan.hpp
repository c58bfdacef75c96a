// When each event of a fault schedule (faults.hpp) is due, and when the ones
// that last (stop, partition, loss, restart) end: the bookkeeping of
// `pheromesh run`, without processes, signals or namespaces, so that it can be
// tested alone (tests/unit/test_fault_plan.cpp).
//
// A realtime run asks `take_due_at(now)` with its wall clock [s since the
// swarm was started]; a lockstep run asks `take_due_before_tick(k)` when the
// conductor announces that tick k is next (the `faults K` line). Either way an
// event is handed out once. The caller executes it, then calls `begin`; an
// event with an end (stop -> SIGCONT, partition and loss -> rules removed,
// restart -> the process started again) is then handed out once more by
// `take_ends_at` when its duration has passed in wall time, and the caller
// calls `end`. `records()` is what happened, for metrics.json.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "pheromesh/core/faults.hpp"

namespace pheromesh::core {

// One executed event, as metrics.json "faults" lists it.
struct FaultRecord {
  std::size_t event = 0;  // index into the schedule
  FaultAction action = FaultAction::Kill;
  std::vector<std::string> targets;  // process names as executed (e.g. "uav-3", "place-1.r1"); empty: every process
  double at_s = 0;                   // [s] when it was executed, after the swarm started
  std::optional<uint32_t> tick;      // lockstep: executed before this tick
  double duration_s = 0;             // [s] as scheduled (restart: down time)
  std::optional<double> done_at_s;   // [s] when it ended (kill, standby: at_s); none if the run ended first
  std::string note;                  // e.g. "uav-3 was not running"
};

class FaultPlan {
 public:
  explicit FaultPlan(FaultSchedule schedule);

  [[nodiscard]] const FaultSchedule& schedule() const { return schedule_; }
  [[nodiscard]] const FaultEvent& event(std::size_t i) const { return schedule_.events.at(i); }

  // Events timed in seconds whose time is <= now_s and that were not handed
  // out yet, in schedule order.
  std::vector<std::size_t> take_due_at(double now_s);
  // Events timed in ticks whose tick is <= tick and that were not handed out
  // yet: everything that must have happened before `tick` runs.
  std::vector<std::size_t> take_due_before_tick(uint32_t tick);

  // The caller executed event i at now_s (tick: the lockstep tick it ran
  // before). Events without an end are done at once.
  void begin(std::size_t i, double now_s, std::vector<std::string> targets, std::optional<uint32_t> tick = std::nullopt,
             std::string note = "");
  // Begun events whose end is due at now_s, each handed out once.
  std::vector<std::size_t> take_ends_at(double now_s);
  // Every begun event that has not ended, each handed out once (the run is
  // over: resume, remove, give up).
  std::vector<std::size_t> take_all_ends();
  void end(std::size_t i, double now_s, const std::string& note = "");

  // The distinct ticks with events, ascending (the ground station's
  // --fault-ticks).
  [[nodiscard]] std::vector<uint32_t> fault_ticks() const;
  [[nodiscard]] bool all_taken() const;
  [[nodiscard]] const std::vector<FaultRecord>& records() const { return records_; }

  // Whether an action has a second step after its duration.
  static bool has_end(FaultAction a);

 private:
  struct State {
    bool taken = false;
    std::optional<std::size_t> record;  // into records_, once begun
    std::optional<double> end_at_s;     // begun, with an end not yet handed out
  };
  FaultSchedule schedule_;
  std::vector<State> state_;
  std::vector<FaultRecord> records_;
};

}  // namespace pheromesh::core
