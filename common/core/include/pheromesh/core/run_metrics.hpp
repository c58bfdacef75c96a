// Everything a run is judged by, recorded from the messages the swarm
// produces. The ground station and the in-process simulator both feed one of
// these, so `pheromesh run` and `pheromesh sim` report the same quantities
// computed the same way.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "pheromesh/core/marks.hpp"
#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/metrics.hpp"
#include "pheromesh/core/plausibility.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/world.hpp"

namespace pheromesh::core {

// Every UAV's start cell (coverage counts the cells reachable from them).
std::vector<Cell> all_starts(const ScenarioConfig& s);

// The swarm at the end of one tick (series.csv; docs/outputs.md): what the
// states, detections and health records stamped with that tick or an earlier
// one say, whatever order they arrived in. A lockstep run's ground station
// hears every one of them, so its rows equal the simulator's; a realtime
// ground station has what reached it.
struct TickRow {
  uint32_t tick = 0;
  int64_t covered_cells = 0;
  double coverage = 0;             // covered_cells / reachable cells, 0..1
  uint32_t targets_found = 0;      // targets first detected at this tick or before
  uint32_t uavs_reporting = 0;     // UAVs with a state of this very tick
  uint64_t deposits_sent = 0;      // by the UAVs, by their latest state of this tick or before
  uint64_t deposits_applied = 0;   // by the place agents, by their latest health of this tick or before
  uint64_t deposits_rejected = 0;  // likewise
};

// The first tick whose row has coverage >= `share` (0..1), if one has: the
// time to coverage of metrics.json (ticks_to_coverage_50, _90). A run that
// never got there is censored at its last tick: no value, not that tick.
std::optional<uint32_t> first_tick_at_coverage(const std::vector<TickRow>& rows, double share);

// The tick every target had been found by (the last first acquisition), if
// there is a target and every one was found: ticks_to_all_targets.
std::optional<uint32_t> all_targets_found_tick(const AcquisitionTracker& a);

// One UAV at one tick (tracks.csv).
struct TrackRow {
  uint32_t tick = 0;
  uint32_t uav = 0;
  double x = 0, y = 0;  // [cell]
  uint8_t role = 0;     // core::Role
};

// "searcher", "leader", "follower"; "role-N" for a code outside Role.
std::string role_name(uint8_t role);

struct UavStatus {
  UavStateMsg last{};
  bool heard = false;  // `last` holds a state of this UAV
  // The latest tick heard of it: an accepted state's, or its gateway's
  // answer for a refused one (`last` keeps the accepted state's tick).
  uint32_t heard_tick = 0;
  bool alive = true;
  bool finished = false;
  uint64_t earlier_lives_deposits = 0;  // deposits sent by earlier processes of this UAV (restarts)
  // Where it was at its last kRecentFixes accepted states, oldest first: a
  // detection is judged against the one nearest its tick (16 bytes each, 2 KiB
  // per UAV: 2 MiB for a swarm of 1000).
  struct Fix {
    uint32_t tick = 0;
    float x = 0, y = 0;  // [cell]
  };
  std::deque<Fix> recent;
  static constexpr std::size_t kRecentFixes = 128;
  // An older fix was dropped from `recent`: a detection of a tick before
  // its first is older than what is kept, and refused (StaleDetection).
  bool forgot = false;
};

class RunRecorder {
 public:
  RunRecorder(const ScenarioConfig& scenario, const World& world);

  // Each returns false if the sample was malformed (counted in
  // samples_rejected) or implausible (counted in refused(), plausibility.hpp)
  // and ignored. A state its gateway refused (UavStateMsg::implausible) is
  // the UAV's answer for its tick: its counters (deposits sent, samples,
  // finished) are taken and its tick counts as reported in the series, but
  // not its position (coverage, tracks, detections); the gateway counted the
  // refusal, this recorder only notes it (refused_states). Returns true.
  bool on_uav_state(const UavStateMsg& s);
  // A detection is judged against the reporting UAV's state of its tick, or
  // the nearest later one it holds (of its last 128); until one arrives it
  // waits (true). One of a tick before the oldest of the 128 kept (once
  // older ones were dropped) is refused (Refusal::StaleDetection,
  // check_detection_kept): the nearest later one is then further in time
  // than the window, and its reach - max_step for every tick between -
  // could cover the map. Judged against the UAV's latest state instead, a detection
  // of a tick long past had the reach of every tick flown since (issue 28:
  // forged detections a few ticks old were accepted). Detections of targets found
  // for the first time collect in take_first_acquisitions().
  bool on_detection(const DetectionMsg& d);
  // Judges the detections still waiting against the last states (end of a run).
  void judge_pending_detections();
  // The first acquisitions of targets since the last call.
  std::vector<DetectionMsg> take_first_acquisitions();
  // Realtime or lockstep: states of a tick above this are refused
  // (plausibility.hpp, realtime_tick_ceiling); unlimited by default.
  void set_tick_ceiling(uint32_t ceiling) { tick_ceiling_ = ceiling; }
  // A sample refused by the process that feeds this recorder (tiles, fields).
  void count_refused(Refusal r) { refused_.add(r); }
  [[nodiscard]] const RefusalCounts& refused() const { return refused_; }
  // The states each UAV's gateway refused as implausible (the ground station
  // hears them as UavStateMsg::implausible), the first one with the state it
  // was judged against: what `sim` and `run` say about them.
  struct RefusedStates {
    uint64_t count = 0;      // one per tick (copies relayed again count once)
    uint32_t last_tick = 0;  // of the latest refused state
    UavStateMsg first{};     // the first refused state
    UavStateMsg accepted{};  // the last accepted state before it ...
    bool from_start = true;  // ... or none: it was judged from the start cell
    Cell start{};
  };
  [[nodiscard]] const std::map<uint32_t, RefusedStates>& refused_states() const { return refused_states_; }
  [[nodiscard]] uint64_t states_refused() const;
  [[nodiscard]] double max_step() const { return max_step_; }
  // What the place agents (every replica's latest health) and the UAVs (their
  // latest states) report they refused.
  [[nodiscard]] RefusalCounts refused_by_places() const;
  [[nodiscard]] RefusalCounts refused_by_uavs() const;
  void on_target_event(const TargetEventMsg& e);
  // One replica's health. Returns true if that replica had been lost and is
  // heard again (a stopped process that resumed).
  bool on_health(const HealthMsg& h);
  // Returns false, and changes nothing, for a relayed departure older than
  // the UAV's last state (UavDeparture): the relay lost a UAV that another
  // gateway still relays. Taken for a death, it had the next stale copy from
  // that relay start a "new life" and counted the UAV's deposits twice
  // (deposits sent 3330, received 3005: Faults.AStoppedPlaceAgent...).
  bool on_uav_departed(const UavDeparture& d);
  // A place replica's health writer vanished (core::place_id).
  void on_place_departed(uint32_t place);
  // Faults injected on purpose (docs/faults.md): UAVs and place agents
  // killed, and of those place agents the ones no standby took over (their
  // regions froze).
  void on_uav_killed() { ++uavs_killed_; }
  void on_place_killed(bool region_frozen) {
    ++places_killed_;
    regions_frozen_ += region_frozen ? 1 : 0;
  }
  void count_rejected_sample() { ++samples_rejected_; }
  // A target added during the run (the world gained it first).
  void add_target() { acquisitions_.add_target(); }
  // Policy-specific quantities of the final field (policy.hpp field_summary).
  void set_field_summary(std::map<std::string, double> summary) { field_summary_ = std::move(summary); }
  [[nodiscard]] const std::map<std::string, double>& field_summary() const { return field_summary_; }
  // Keep every accepted state's position for tracks() (off by default: a
  // long run of a large swarm has millions).
  void keep_tracks() { keep_tracks_ = true; }

  [[nodiscard]] const ScenarioConfig& scenario() const { return *scenario_; }
  [[nodiscard]] uint32_t max_tick() const { return max_tick_; }
  [[nodiscard]] const std::map<uint32_t, UavStatus>& uavs() const { return uavs_; }
  // Per region, the health of the replica that received the most deposits
  // (the counters of a replica's earlier lives included: a place agent
  // started again counts from 0)
  // (the one that has served it longest: a standby that took over counts
  // every deposit of the run, its dead primary only those until its death).
  [[nodiscard]] const std::map<RegionId, HealthMsg>& health() const { return health_; }
  // Every replica's latest health, by core::place_id.
  [[nodiscard]] const std::map<uint32_t, HealthMsg>& replica_health() const { return replica_health_; }
  [[nodiscard]] bool place_departed(uint32_t place) const { return departed_places_.contains(place); }
  // Every replica heard of region r is lost.
  [[nodiscard]] bool region_departed(RegionId r) const;
  // The live replica of r with the lowest number (the owner of its output), if any.
  [[nodiscard]] std::optional<uint16_t> region_owner(RegionId r) const;
  [[nodiscard]] uint32_t replicas_alive(RegionId r) const;
  // Regions with at least one live replica.
  [[nodiscard]] uint32_t regions_alive() const;
  // What the UAVs themselves count as not confirmed by their home place agent.
  [[nodiscard]] uint64_t deposits_unconfirmed_by_uavs() const;
  [[nodiscard]] const CoverageTracker& coverage() const { return coverage_; }
  [[nodiscard]] const AcquisitionTracker& acquisitions() const { return acquisitions_; }
  // Revisit response times ordered by (tick, region, y, x): independent of
  // the order events arrived in.
  [[nodiscard]] std::vector<uint32_t> revisit_response_ticks() const;
  // The revisit events themselves, in the same order.
  [[nodiscard]] std::vector<TargetEventMsg> revisit_events() const;
  // One row per tick 0..max_tick() (TickRow).
  [[nodiscard]] std::vector<TickRow> tick_series() const;
  // Every UAV's position at every tick it was heard, by (tick, uav); empty
  // unless keep_tracks() was called before the run.
  [[nodiscard]] std::vector<TrackRow> tracks() const;
  [[nodiscard]] uint64_t samples_rejected() const { return samples_rejected_; }
  // UAV states older than one already held (a second gateway's relay, a late
  // re-send): their positions count, the newer state stays the UAV's last.
  [[nodiscard]] uint64_t states_stale() const { return states_stale_; }
  // Relayed departures older than the UAV's last state (on_uav_departed).
  [[nodiscard]] uint64_t departures_stale() const { return departures_stale_; }
  // `s` is the first state of a restarted UAV process: one lost before
  // (not finished) whose deposit count starts again.
  [[nodiscard]] bool starts_new_life(const UavStateMsg& s) const;
  [[nodiscard]] uint64_t deposits_sent() const;
  // Deposits sent by the UAVs that no place agent counted (received,
  // applied or rejected): lost to a dead place agent, whether their region's
  // or their UAV's home. sent == applied + rejected + lost.
  [[nodiscard]] uint64_t deposits_lost() const;
  [[nodiscard]] uint32_t uavs_killed() const { return uavs_killed_; }
  [[nodiscard]] uint32_t places_killed() const { return places_killed_; }
  [[nodiscard]] uint32_t regions_frozen() const { return regions_frozen_; }
  // Tick at which a leader became a searcher (Shao 2020 Sec. 5: it reached the
  // centre of the target region), if one did.
  [[nodiscard]] std::optional<uint32_t> leader_arrival_tick() const { return leader_arrival_; }

 private:
  [[nodiscard]] static bool stale_copy(const UavStateMsg& s, const UavStatus& u);

  const ScenarioConfig* scenario_;
  const World* world_;
  MapGeometry geo_;
  CoverageTracker coverage_;
  AcquisitionTracker acquisitions_;
  std::vector<TargetEventMsg> revisits_;
  std::map<uint32_t, UavStatus> uavs_;
  std::map<RegionId, HealthMsg> health_;
  std::map<uint32_t, HealthMsg> replica_health_;  // by place_id
  std::map<uint32_t, bool> departed_places_;      // by place_id
  // Per place replica, what its earlier lives counted (a place agent started
  // again counts from 0; on_health adds these, so the dead life's deposits
  // stay counted), and its current life's latest record as it sent it.
  std::map<uint32_t, HealthMsg> banked_lives_, life_latest_;
  // The series' deposits sent and UAVs reporting, summed per tick as the
  // states arrive (tick_series): a change of a UAV's count (earlier lives
  // included) at the tick of the state that carried it, and one UAV more at
  // each tick it first reported. Per UAV only its latest tick and count: a
  // history of every state grew by 16 bytes a UAV tick (+79 MiB/h of the
  // ground station's soak with 183 UAVs at 5 Hz, issue 28).
  struct SeriesMark {
    uint32_t tick = 0;
    uint64_t sent = 0;
  };
  void count_in_series(uint32_t uav, uint32_t tick, uint64_t sent);
  std::map<uint32_t, SeriesMark> series_mark_;
  std::vector<int64_t> sent_delta_;
  std::vector<uint32_t> reporting_;
  // Per place replica (place_id), its health records.

  struct LedgerPoint {
    uint32_t tick = 0;
    uint64_t received = 0, applied = 0, rejected = 0;
  };
  std::map<uint32_t, std::vector<LedgerPoint>> ledger_by_tick_;
  bool keep_tracks_ = false;
  std::vector<TrackRow> tracks_;
  std::map<std::string, double> field_summary_;
  std::optional<uint32_t> leader_arrival_;
  uint32_t max_tick_ = 0;
  uint64_t samples_rejected_ = 0;
  uint64_t states_stale_ = 0;
  uint64_t departures_stale_ = 0;
  uint32_t uavs_killed_ = 0, places_killed_ = 0, regions_frozen_ = 0;
  // Plausibility (plausibility.hpp).
  PolicyTraits traits_;
  double max_step_;       // [cell/tick]
  double sensor_radius_;  // [cell]
  uint32_t tick_ceiling_;
  RefusalCounts refused_;
  std::map<uint32_t, RefusedStates> refused_states_;
  void on_refused_state(const UavStateMsg& s);
  void release_pending(const UavStatus& u, uint32_t uav, uint32_t tick);
  std::vector<DetectionMsg> pending_;  // detections waiting for their UAV's state of their tick
  std::vector<DetectionMsg> first_acquisitions_;
  void judge(const DetectionMsg& d, const UavStateMsg* seen);
  // Judges `d` against the nearest of `u`'s kept positions, or refuses it as
  // older than they are (check_detection_kept).
  void judge_kept(const UavStatus& u, const DetectionMsg& d);
  // The UAV's position at the kept state nearest `tick` (the first of that
  // tick or later; none kept that late: its last state).
  static UavStateMsg nearest_state(const UavStatus& u, uint32_t tick);
};

// How far a UAV's first refused state lay from the state it was judged
// against (its last accepted one, else its start cell), and in how many ticks.
struct RefusedMove {
  double cells = 0;  // [cell]
  uint32_t ticks = 1;
};
RefusedMove first_refused_move(const RunRecorder::RefusedStates& r);
// "uav 0's state of tick 3 refused: it moved 5 cells in one tick from its last
// accepted state (max_step 1.5 allows 3 with the slack)".
std::string describe_first_refusal(const RunRecorder::RefusedStates& r, uint32_t uav, double max_step);
// The same from its parts (metrics.json "states_refused").
std::string describe_refusal(uint32_t uav, uint32_t tick, RefusedMove m, bool from_start, double max_step);

}  // namespace pheromesh::core
