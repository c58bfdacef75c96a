// The lockstep conductor's protocol, without DDS (docs/architecture.md,
// "Time"). The ground station feeds it what it hears (UAV states,
// broadcasts, PhaseDone reports, liveliness departures) and publishes the
// clock it returns; this class decides what each clock announces and when a
// phase is complete. Time is passed in, so tests drive it by hand.
//
// A phase of tick k is complete when every expected process reported
// PhaseDone for exactly (k, phase); a UAV phase also needs every reporting
// UAV's state of tick k and as many broadcasts of tick k as were reported. A
// UAV whose liveliness lapsed is still waited for during a grace period (a
// stalled, overloaded process is not a dead one); after it, it is not. A
// place agent is always waited for: without it the tick cannot be exact, so
// the phase runs into its timeout and the run ends.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <set>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/messages.hpp"

namespace pheromesh::core {

class LockstepConductor {
 public:
  using Clock = std::chrono::steady_clock;

  struct Options {
    uint32_t uavs = 0;
    uint32_t regions = 0;
    std::chrono::milliseconds phase_timeout{60000};
    std::chrono::milliseconds departed_grace{5000};
    // Hot standbys per region (pheromesh run --standby): each replica
    // reports PhaseDone under process_key(kRolePlace, place_id(region,
    // replica)) and is waited for while it lives, so standbys never fall
    // behind; a lost replica is not waited for while another of its region lives.
    uint32_t standbys = 0;
  };

  struct Status {
    bool complete = false;
    bool timed_out = false;   // the phase's timeout passed before it completed
    uint32_t waiting = 0;     // processes (or missing states/broadcasts) still awaited
  };

  explicit LockstepConductor(Options o) : o_(o) {}

  // --- what the ground station heard
  // A valid state of `uav` over `tile` (not finished). Returns true if the
  // UAV had departed and is back.
  bool on_uav_state(uint32_t uav, uint32_t tick, TileCoord tile);
  // A finished UAV's last state: it is back if it had departed, nothing else.
  bool on_uav_finished(uint32_t uav);
  void on_broadcast(uint32_t uav, uint32_t tick);
  void on_phase_done(const PhaseDoneMsg& m);
  // The UAV's liveliness lapsed. Returns true the first time (until it is back).
  bool on_uav_departed(uint32_t uav, Clock::time_point now);
  // A place replica's liveliness lapsed (place_id). In a run with standbys it
  // is not waited for again (it missed ticks; it leaves when it notices).
  void on_place_departed(uint32_t place) { places_gone_.insert(place); }
  [[nodiscard]] bool departed(uint32_t uav) const { return departed_since_.contains(uav); }

  // --- the protocol
  // Starts phase `phase` of `tick` and returns the clock to publish.
  ClockMsg begin_phase(uint32_t tick, ClockPhase phase, Clock::time_point now);
  // Where the phase begun last stands at `now`.
  Status status(Clock::time_point now);
  // The clock that ends the run after `ticks`.
  [[nodiscard]] static ClockMsg stop(uint32_t ticks);

  // A departed UAV that has not come back within the grace period.
  [[nodiscard]] bool gone_for_good(uint32_t uav, Clock::time_point now) const;

 private:
  [[nodiscard]] ClockMsg announce(uint32_t tick, ClockPhase phase) const;
  void keep_recent();

  Options o_;
  uint32_t tick_ = 0;
  ClockPhase phase_ = ClockPhase::Uav;
  Clock::time_point deadline_{};
  std::map<uint32_t, PhaseDoneMsg> done_;                 // process key -> latest report
  std::map<uint32_t, std::map<uint32_t, TileCoord>> positions_;  // tick -> uav -> tile
  std::map<uint32_t, std::set<uint32_t>> broadcasters_;   // tick -> UAVs that broadcast
  std::map<RegionId, uint32_t> deposits_reported_;        // current tick's UAV phase
  std::map<uint32_t, Clock::time_point> departed_since_;  // departed UAVs
  std::set<uint32_t> places_gone_;                         // departed place replicas (place_id)
};

}  // namespace pheromesh::core
