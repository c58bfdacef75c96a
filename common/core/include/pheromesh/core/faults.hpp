// A fault schedule: what `pheromesh run --faults`, `pheromesh sim --faults`
// and a scenario's `fault:` lines inject (docs/faults.md).
//
// One event per item, items separated by ';' (or given one per scenario line):
//
//   kill      TARGETS @TIME                  SIGKILL
//   stop      TARGETS @TIME for DURATION     SIGSTOP, then SIGCONT
//   restart   TARGETS @TIME [for DURATION]   SIGKILL, then start it again after DURATION (default 0)
//   standby   place:R @TIME                  start a new standby place agent for region R
//   partition TARGETS @TIME for DURATION     cut TARGETS off from every other process
//   loss      P% [TARGETS] @TIME for DURATION  drop P % of the packets TARGETS receive (default: every process)
//
// TARGETS: comma-separated uav:I, uav:I-J, place:R, place:R-S, ground.
// TIME: 5s, 2500ms (realtime runs) or 40t (ticks; lockstep runs and the
// simulator). DURATION is wall time (s or ms) in both clocks: a lockstep run
// does not advance its ticks while one of its processes is stopped or cut off.
//
// Meaning at tick k of a lockstep run and in the simulator (they must give the
// same numbers):
//   kill uav:U @kt     UAV U acts in ticks 0..k-1 only; from tick k it is gone
//                      (no state in any view, no deposits, no coverage).
//   kill place:R @kt   with a standby: nothing changes (the standby takes
//                      over). Without: region R goes dark - its tiles are in
//                      no view from the views of tick k on (UAV phase k+1),
//                      every deposit into R from tick k on is lost (counted);
//                      its neighbours' diffusion keeps its last ring, and the
//                      final field keeps its values after tick k-1. The UAVs
//                      homed on R talk to their backup gateway from tick k on
//                      (core::gateway_region: region R+1): it takes their
//                      states and deposits (forwarded to the owners as any)
//                      and composes their views from place tick k on - the
//                      place agent's death darkens exactly its region. A UAV
//                      whose home and backup are both dead gets no view and
//                      its deposits are lost (counted).
//   stop / partition / loss in lockstep: slower, same numbers.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "pheromesh/core/result.hpp"

namespace pheromesh::core {

enum class FaultAction : uint8_t { Kill, Stop, Restart, Standby, Partition, Loss };
const char* to_string(FaultAction a);

// One process: role "uav", "place" or "ground" and its index (0 for ground).
struct FaultTarget {
  std::string role;
  uint32_t index = 0;
  [[nodiscard]] std::string process_name() const;  // "uav-3", "place-0", "ground"
  friend bool operator==(const FaultTarget&, const FaultTarget&) = default;
};

struct FaultEvent {
  FaultAction action = FaultAction::Kill;
  std::vector<FaultTarget> targets;  // expanded ranges; empty for loss on every process
  // When: exactly one of the two is set.
  std::optional<double> at_s;        // [s] after the swarm started (realtime)
  std::optional<uint32_t> at_tick;   // before this tick runs (lockstep, simulator)
  double duration_s = 0;             // stop, partition, loss; restart: down time
  double loss = 0;                   // loss: share of packets dropped, 0..1
  std::string text;                  // the item as written, for messages
};

struct FaultSchedule {
  std::vector<FaultEvent> events;  // sorted by time (stable)
  [[nodiscard]] bool empty() const { return events.empty(); }
  [[nodiscard]] bool in_ticks() const;      // every event timed in ticks
  [[nodiscard]] bool has_network() const;   // a partition or loss event
  // UAVs killed (kill, not restart) and the tick they are gone from, for the
  // simulator: uav -> first tick it does not act.
  [[nodiscard]] std::vector<std::pair<uint32_t, uint32_t>> uav_kills() const;
  [[nodiscard]] std::vector<std::pair<uint32_t, uint32_t>> place_kills() const;  // region -> tick
};

// Parses "kill uav:3 @5s; stop place:1 @10s for 5s; ...". `where` names the
// source in errors ("--faults", "scenario.textproto:12"). Also accepts the
// older --kill form "uav:3@5s,place:1@2500ms" (kills only).
Result<FaultSchedule> parse_fault_schedule(const std::string& text, const std::string& where = "--faults");

// Checks every target exists (uavs, regions) and the clock fits: lockstep
// runs and the simulator need tick times, realtime runs second times.
std::optional<std::string> check_fault_schedule(const FaultSchedule& s, uint32_t uavs, uint32_t regions, bool lockstep);

// Adds b's events to a (sorted).
void merge_fault_schedules(FaultSchedule& a, const FaultSchedule& b);

}  // namespace pheromesh::core
