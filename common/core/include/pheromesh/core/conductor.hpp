// The lockstep conductor's protocol, without DDS (docs/architecture.md,
// "Time"). The ground station feeds it what it hears (UAV states,
// broadcasts, PhaseDone reports, liveliness departures) and publishes the
// clock it returns; this class decides what each clock announces and when a
// phase is complete. Time is passed in, so tests drive it by hand.
//
// Before tick 0 the Ready phase waits (start_timeout) until every UAV and
// place agent reported Ready: it matched the readers it deposits to. A phase
// of tick k is complete when every expected process reported PhaseDone for
// exactly (k, phase); a UAV phase also needs every reporting
// UAV's state of tick k and as many broadcasts of tick k as were reported.
// The place phase of tick k announces, per region, the deposits of tick k it
// must apply and the states of tick k of its home UAVs it must hold: every
// place agent waits for those exact samples, so no UAV waits for
// acknowledgements (an acknowledgement waits for the writer's heartbeat:
// ~100 ms on Cyclone 0.10, docs/dds.md "Lockstep at network speed"). A
// UAV whose liveliness lapsed is still waited for during a grace period (a
// stalled, overloaded process is not a dead one); after it, it is not. A
// place agent is waited for unless it is absent (below): without it the tick
// cannot be exact, so the phase runs into its timeout and the run ends. Any
// sample of a UAV (its state, a PhaseDone - a waiting UAV re-sends its own
// every second - or a broadcast) counts as a sign of life: a UAV whose
// liveliness lapses under packet loss while it still talks is not dropped.
//
// Faults at a tick (core/faults.hpp): before the UAV phase of a tick with
// faults, the ground station asks the launcher which processes it killed
// (parse_gone) and tells the conductor. A gone UAV is dropped at once: it is
// not waited for from that tick on. A gone place agent without a standby
// makes its region absent: every clock from then on lists it, nobody waits
// for it, and the deposits reported for it - and every deposit of the UAVs
// homed on it, which went through it - are lost (deposits_lost).
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/result.hpp"

namespace pheromesh::core {

// The launcher's answer to "faults K" without its "ok ": "gone uav-3,place-1"
// or "gone -" (nothing gone). Names outside the swarm (uav index >= uavs,
// region >= regions) and anything else are errors.
struct GoneProcesses {
  std::vector<uint32_t> uavs;
  std::vector<RegionId> regions;   // primaries (place-R)
  std::vector<uint32_t> standbys;  // standby replicas (place-R.rN), as place_id(R, N)
};
Result<GoneProcesses> parse_gone(const std::string& answer, uint32_t uavs, uint32_t regions);

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
    std::chrono::milliseconds start_timeout{120000};  // the Ready phase (ClockPhase::Ready)
  };

  struct Status {
    bool complete = false;
    bool timed_out = false;  // the phase's timeout passed before it completed
    uint32_t waiting = 0;    // processes (or missing states/broadcasts) still awaited
    // Who has not reported the phase yet (ids; in a UAV phase also a UAV
    // whose state is still missing; a region once, however many of its
    // replicas are missing).
    std::vector<uint32_t> uavs_not_ready, regions_not_ready;
  };

  explicit LockstepConductor(Options o) : o_(o) {}

  // --- what the ground station heard
  // A valid state of `uav` over `tile` (not finished), with its pose (x, y,
  // velocity, heading, role, view cell; its uav and region are the
  // conductor's to fill): the place phase of `tick` lists it as served
  // (ClockMsg::served). Returns true if the UAV had departed and is back.
  bool on_uav_state(uint32_t uav, uint32_t tick, TileCoord tile, ServedUav pose = {});
  // A state of `uav` its gateway refused as implausible (UavStateMsg::
  // implausible): the UAV's answer for `tick`, as a state is, but over no
  // tile (no view waits for it as a neighbour), and its deposits of `tick`
  // are announced to no region (its gateway rejects them: issue 42 D4).
  // Returns true if the UAV had departed and is back.
  bool on_uav_refused(uint32_t uav, uint32_t tick);
  // A finished UAV's last state: it is back if it had departed, nothing else.
  bool on_uav_finished(uint32_t uav);
  void on_broadcast(uint32_t uav, uint32_t tick);
  // A report of an older tick than the process's latest is not news.
  void on_phase_done(const PhaseDoneMsg& m);
  // The UAV's liveliness lapsed. Returns true the first time (until it is back).
  bool on_uav_departed(uint32_t uav, Clock::time_point now);
  // A place replica's liveliness lapsed (place_id). In a run with standbys it
  // is not waited for (it may have missed ticks; it leaves when it notices).
  void on_place_departed(uint32_t place) { places_gone_.insert(place); }
  [[nodiscard]] bool place_gone(uint32_t place) const { return places_gone_.contains(place); }
  // The launcher killed the place replica: it is never waited for again.
  void on_place_killed(uint32_t place) {
    places_gone_.insert(place);
    places_killed_.insert(place);
  }
  // A departed place replica is heard again (its health). If it is still in
  // step - it reported the place phase of the tick before the current one,
  // or the current one - it is waited for again: a replica whose lease
  // lapsed only because it was not scheduled for a while (a loaded host) then
  // keeps the swarm from running ahead of it, and it counts as a live replica
  // of its region when the other one dies. One that missed a place phase
  // stays gone (it leaves when it notices). True if it is waited for again.
  bool on_place_back(uint32_t place);
  // A sample from the UAV (state, PhaseDone, broadcast) arrived at `now`: the
  // grace of a departed UAV runs from the later of its departure and this.
  void heard_from(uint32_t uav, Clock::time_point now) { heard_[uav] = now; }
  [[nodiscard]] bool departed(uint32_t uav) const { return departed_since_.contains(uav); }
  // When the UAV's latest sample arrived (heard_from), if any did.
  [[nodiscard]] std::optional<Clock::time_point> last_heard(uint32_t uav) const {
    auto it = heard_.find(uav);
    if (it == heard_.end()) return std::nullopt;
    return it->second;
  }

  // --- faults at a tick (before begin_phase of its UAV phase)
  // The UAV was killed: not waited for from now on, and a state it sent
  // before it died does not bring it back. True the first time.
  bool drop_uav(uint32_t uav);
  // The region's place agent was killed and has no standby: absent from now
  // on (listed in every clock). True the first time.
  bool drop_region(RegionId r);
  [[nodiscard]] bool dropped(uint32_t uav) const { return dropped_.contains(uav); }
  [[nodiscard]] bool absent(RegionId r) const { return absent_.contains(r); }
  // Deposits reported in completed UAV phases that no place agent applies:
  // those for absent regions and those of UAVs whose home and backup are both absent.
  [[nodiscard]] uint64_t deposits_lost() const { return deposits_lost_; }

  // --- the protocol
  // Starts phase `phase` of `tick` and returns the clock to publish.
  //
  // A place phase with `next_uav_phase` also begins the UAV phase of tick+1
  // (ClockMsg::next_uav_phase): it announces what a UAV clock of tick+1
  // would, each place agent relays that UAV clock at once, and a UAV acts on
  // it as soon as its view of place tick `tick` is here, so a UAV no longer
  // waits for the slowest place agent, nor for two more hops (the place
  // agents' reports here, the UAV clock back down). status() is complete
  // once the place phase and then that UAV phase are: the phase under way
  // (tick(), phase()) turns into the UAV phase when the place phase
  // completes. Only a swarm without standbys fuses (a standby may still be
  // taking the inputs of its place phase when the primary has served the
  // views, and a state of tick+1 must not reach it then); the caller does
  // not fuse before a tick with faults (the launcher must kill before the
  // UAV phase) nor while paused.
  ClockMsg begin_phase(uint32_t tick, ClockPhase phase, Clock::time_point now, bool next_uav_phase = false);
  // Where the phase under way stands at `now`.
  Status status(Clock::time_point now);
  // The phase under way and its tick.
  [[nodiscard]] uint32_t tick() const { return tick_; }
  [[nodiscard]] ClockPhase phase() const { return phase_; }
  // The clock that ends the run after `ticks`.
  [[nodiscard]] static ClockMsg stop(uint32_t ticks);

  // Where the conducted time went: for every UAV and place phase, the time
  // from begin_phase to the first status that found it complete [ms]. A UAV
  // phase begun with a place phase is timed from that place phase's end, so
  // that a tick's UAV and place times add up to its time.
  struct PhaseTimes {
    std::vector<double> uav_ms;
    std::vector<double> place_ms;
  };
  [[nodiscard]] const PhaseTimes& phase_times() const { return times_; }

  // A departed UAV that has not come back within the grace period.
  [[nodiscard]] bool gone_for_good(uint32_t uav, Clock::time_point now) const;

 private:
  [[nodiscard]] ClockMsg announce(uint32_t tick, ClockPhase phase) const;
  // The place phase of a fused pair is complete: the UAV phase of the next
  // tick is the phase under way from `now`.
  void turn_to_next_uav_phase(Clock::time_point now);
  void record_time(Clock::time_point now);
  void keep_recent();

  [[nodiscard]] bool waited_for_uav(uint32_t uav, Clock::time_point now) const {
    return !dropped_.contains(uav) && !gone_for_good(uav, now);
  }
  // status() by phase: the Ready phase's; how many processes of a UAV or
  // place phase have not reported it; once every UAV did, what their reports
  // announce (deposits and states per region, deposits lost) and how many
  // answers are still missing.
  [[nodiscard]] Status ready_status(Clock::time_point now) const;
  // Both count what is missing and, given `who`, name it.
  [[nodiscard]] uint32_t not_reported(Clock::time_point now, Status* who = nullptr) const;
  uint32_t tally_uav_reports(Clock::time_point now, Status* who = nullptr);
  void note(uint32_t& waiting, Status* who, uint32_t id) const;

  Options o_;
  PhaseTimes times_;
  Clock::time_point begun_at_{};
  bool timed_ = false;           // the phase under way is complete and its time recorded
  bool next_uav_phase_ = false;  // the place phase under way began the next tick's UAV phase
  uint32_t tick_ = 0;
  ClockPhase phase_ = ClockPhase::Uav;
  Clock::time_point deadline_{};
  std::map<uint32_t, PhaseDoneMsg> done_;                        // process key -> latest report
  struct Heard {
    TileCoord tile;
    ServedUav pose;
  };
  std::map<uint32_t, std::map<uint32_t, Heard>> positions_;      // tick -> uav -> its state's tile and pose
  std::map<uint32_t, std::set<uint32_t>> broadcasters_;          // tick -> UAVs that broadcast
  std::map<uint32_t, std::set<uint32_t>> refused_;               // tick -> UAVs whose state of it was refused
  std::map<RegionId, uint32_t> deposits_reported_;               // current tick's UAV phase
  std::map<RegionId, uint32_t> states_reported_;                 // current tick's UAV phase: states per home region
  std::map<uint32_t, Clock::time_point> departed_since_;         // departed UAVs
  std::set<uint32_t> places_gone_;                               // departed place replicas (place_id)
  std::set<uint32_t> places_killed_;                             // place replicas the launcher killed (place_id)
  std::map<uint32_t, Clock::time_point> heard_;                  // UAV -> its latest sample
  std::set<uint32_t> dropped_;                                   // UAVs killed at a tick
  std::set<RegionId> absent_;                                    // regions whose place agent was killed, no standby
  uint64_t lost_this_tick_ = 0;                                  // current tick's UAV phase, for absent regions
  uint64_t deposits_lost_ = 0;
};

// A UAV's or place agent's watch on the conductor in a lockstep run. The
// conductor publishes its clock at least every half lease (re-sending the
// current one), also while paused or waiting for the launcher; a process
// that takes no clock for `limit` concludes that the conductor is gone and
// ends with an error, instead of waiting for a clock that never comes.
// Before the first clock (discovery) the bound is `first_limit`.
class ConductorWatch {
 public:
  using Clock = std::chrono::steady_clock;
  // Silence that means the conductor is gone, in liveliness leases (--lease-ms):
  // long enough for a conductor stopped for 5 s at the default lease to come back.
  static constexpr int kLeases = 6;
  // Before the first clock: discovery of a big swarm on a busy host.
  static constexpr std::chrono::milliseconds kFirstClock{300000};

  ConductorWatch(std::chrono::milliseconds limit, std::chrono::milliseconds first_limit, Clock::time_point start)
      : limit_(limit), first_limit_(first_limit), last_(start) {}
  static ConductorWatch for_lease(std::chrono::milliseconds lease, Clock::time_point start) {
    return {lease * kLeases, std::max(kFirstClock, lease * kLeases), start};
  }
  // A clock sample arrived (any: a re-sent one also says the conductor lives).
  void on_clock(Clock::time_point now) {
    last_ = now;
    heard_ = true;
  }
  [[nodiscard]] bool lost(Clock::time_point now) const { return now - last_ > (heard_ ? limit_ : first_limit_); }
  [[nodiscard]] Clock::duration silence(Clock::time_point now) const { return now - last_; }
  [[nodiscard]] bool heard() const { return heard_; }
  [[nodiscard]] std::chrono::milliseconds limit() const { return heard_ ? limit_ : first_limit_; }

 private:
  std::chrono::milliseconds limit_, first_limit_;
  Clock::time_point last_;
  bool heard_ = false;
};

}  // namespace pheromesh::core
