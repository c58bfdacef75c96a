// What the ground station does with every sample it receives, without DDS:
// the checks on each state, broadcast, detection, target event, health,
// field, tile, departure and PhaseDone (messages.hpp, plausibility.hpp), and
// who is told of it - the run recorder, the lockstep conductor, the run book
// (fields), the frame builder and the uncertainty plot. The ground station
// takes the samples from its bus, hands them over with the time, and logs
// the notes returned. Follows LockstepConductor and FrameBuilder.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "pheromesh/console/frame_builder.hpp"
#include "pheromesh/console/uncertainty.hpp"
#include "pheromesh/core/conductor.hpp"
#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/place_vouch.hpp"
#include "pheromesh/core/plausibility.hpp"
#include "pheromesh/core/run_book.hpp"
#include "pheromesh/core/run_metrics.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/sender_judge.hpp"
#include "pheromesh/core/world.hpp"

namespace pheromesh::console {

// What the ground station received since it last looked, by kind.
struct GroundSamples {
  std::vector<core::UavStateMsg> states;
  std::vector<core::BroadcastMsg> broadcasts;
  std::vector<core::UavDeparture> departed_uavs;
  std::vector<core::DetectionMsg> detections;
  std::vector<core::TargetEventMsg> target_events;
  std::vector<core::HealthMsg> healths;
  std::vector<core::FieldMsg> fields;
  std::vector<core::TileMsg> tiles;
  std::vector<uint32_t> departed_places;  // core::place_id
  std::vector<core::PhaseDoneMsg> phase_dones;
  void clear();
};

// One thing worth a log line; `text` is the line.
struct IntakeNote {
  enum class Kind : uint8_t {
    StateDropped,    // malformed (the first 3 samples rejected)
    StateRefused,    // implausible (the first 5 refusals)
    SampleRefused,   // a broadcast, field or tile refused (the first 5 refusals)
    TileDropped,     // malformed (the first 3 samples rejected)
    UavBack,         // a UAV reported lost is heard again
    UavLost,         // a UAV's liveliness lapsed before it finished, and it was not heard around the lapse
    TargetAcquired,  // a target detected for the first time
    PlaceBack,       // a place replica reported lost is heard again
    OwnerRegained,   // a region's output is owned by a lower replica again
    PlaceLost,       // a place replica's liveliness lapsed before it finished, and it was not heard around the lapse
    LivenessLapsed,  // a process's liveliness lapsed while it was heard (the first time per process; the run's count at
                     // the end)
  };
  enum class Level : uint8_t { Info, Warn };
  Kind kind;
  Level level;
  std::string text;
};

class GroundIntake {
 public:
  using Clock = std::chrono::steady_clock;
  using Notes = std::vector<IntakeNote>;
  // Place agents with hot standby replicas: a lost replica is not waited for
  // again by the conductor.
  enum class Standby : uint8_t { None, Hot };

  // What the intake feeds; all outlive it.
  struct Parts {
    core::RunRecorder& rec;
    core::LockstepConductor& conductor;
    core::RunBook& book;
    FrameBuilder& frames;
    const core::World& world;  // targets, with those added during the run
  };

  // How the swarm's ticks are paced: a lockstep process is heard once a
  // tick, however long the tick takes (see Liveness below).
  enum class Pace : uint8_t { Realtime, Lockstep };

  // `lease`: the swarm's liveliness lease (--lease-ms), against which a
  // departure is judged (see Liveness below).
  GroundIntake(const core::ScenarioConfig& scenario, Parts parts, Standby standby,
               std::chrono::milliseconds lease = std::chrono::milliseconds(1000), Pace pace = Pace::Realtime);
  // The console's uncertainty plot, once it exists (null: none).
  void set_uncertainty(UncertaintyTracker* u) { uncertainty_ = u; }

  // Hands every sample of `in` to whom it concerns, in the order of the
  // members of GroundSamples; samples of a tick above `tick_ceiling`
  // (RunBook::tick_ceiling) are refused. Moves the tiles out of the fields.
  Notes take(GroundSamples& in, uint32_t tick_ceiling, Clock::time_point now);
  // End of a run: judges the detections still waiting (RunRecorder) and
  // reports the targets they acquired; a departure not judged yet is a loss.
  Notes judge_pending();
  // Departures judged lapses of live processes so far (see Liveness).
  [[nodiscard]] uint64_t liveliness_lapses() const { return lapses_; }
  // Samples waiting for their process to be heard as a place agent (vouch).
  [[nodiscard]] std::size_t parked() const;

  // Lockstep, before the launcher kills at a tick: the live place replicas
  // (core::place_id) whose health of `tick` or later has not arrived. A
  // region the conductor dropped and a replica it holds gone are not waited
  // for; replica 1 only with hot standbys.
  [[nodiscard]] std::vector<uint32_t> places_without_health_of(uint32_t tick) const;
  // A monitor (--attach) that came late can miss a place agent that ended
  // before it was discovered (no health, no departure). The run is over for
  // it once every place agent it heard has finished or departed, and
  // nothing changed that for `quiet`: then the regions never heard (maybe
  // none), else nullopt. Called with the time as it goes on.
  [[nodiscard]] std::optional<std::vector<core::RegionId>> heard_places_over(
      Clock::time_point now, Clock::duration quiet = std::chrono::seconds(5));

  // The newest plausible tile of each (layer, tile).
  [[nodiscard]] const std::map<FrameBuilder::TileKey, core::TileMsg>& tiles() const { return tiles_; }
  // The value of the newest tile at cell c of `layer`; NaN where no tile arrived.
  [[nodiscard]] float field_value(int layer, core::Cell c) const;

 private:
  void on_states(const std::vector<core::UavStateMsg>& states, Clock::time_point now);
  void on_broadcasts(const std::vector<core::BroadcastMsg>& broadcasts, Clock::time_point now);
  void note_refused_state(const core::UavStateMsg& s);
  uint64_t states_refused_noted_ = 0;
  void on_departed_uavs(const std::vector<core::UavDeparture>& gone, Clock::time_point now);
  void on_target_events(const std::vector<core::TargetEventMsg>& events);
  void on_healths(const std::vector<core::HealthMsg>& healths, Clock::time_point now);
  void on_fields(std::vector<core::FieldMsg>& fields, std::vector<core::TileMsg>& tiles, uint32_t ceiling);
  void on_tiles(std::vector<core::TileMsg>& tiles, uint32_t ceiling);
  void on_departed_places(const std::vector<uint32_t>& gone, Clock::time_point now);
  void on_phase_dones(const std::vector<core::PhaseDoneMsg>& dones, Clock::time_point now);
  void note_acquisitions();
  // Who may write what only a place agent writes or relays (place_vouch.hpp):
  // a health latches its place id to its process (one from another process
  // is refused, foreign_writer; a lockstep place agent writes one with its
  // Ready, before it relays anything); states, relayed departures,
  // broadcasts, detections, target events, fields and tiles are taken from
  // a process that holds a place id, parked while it holds none, and
  // refused when they waited PlaceVouch::park_for(). Removes from `in` what
  // it parks or refuses, and puts what is vouched for now in front.
  void vouch(GroundSamples& in, Clock::time_point now);
  template <typename T>
  void gate(core::Parked<T>& parked, std::vector<T>& in, Clock::time_point now);
  // The end of a run: every sample still parked is refused.
  template <typename T>
  void refuse_parked(core::Parked<T>& parked);
  template <typename T>
  static const char* relay_name();  // "a relayed uav state", ... (notes)
  void refuse_unvouched(const char* what, uint64_t participant);
  static Clock::duration place_takeover(std::chrono::milliseconds lease, Pace pace);
  // `participant` holds a replica of region `r`, or none is held.
  [[nodiscard]] bool speaks_for_region(core::RegionId r, uint64_t participant) const;

  // A departure is the lapse of a writer's liveliness (docs/dds.md): a
  // process that died or hangs, or one whose assertions were all lost for a
  // lease (packet loss; they are not sent again) while its samples, which
  // are, still arrive. It is judged by what comes after it only (a process
  // cut off by a partition, or killed, was heard until just before): one
  // heard again within the wait is a lapse, noted once per process and
  // counted, never reported lost; one not heard is reported lost when the
  // wait ends. The wait is half a lease in realtime, where a live process is
  // heard every tick period. In lockstep a live process is heard once a
  // tick, and a tick under packet loss takes seconds (each lost sample waits
  // for a quiet second before it is sent again): there it is twice the
  // longest silence of that process so far, at least the lockstep takeover
  // time (place_takeover: 10 s, or six leases) and at most three times
  // that. 10-tick runs under 30 % loss reported a live process lost when
  // the wait was half a lease (ticks of up to 3.6 s), and again when it was
  // twice the longest silence from half a lease up: a place agent silent
  // for 0.9 s until then was next heard 7 s after its departure, in tick 0.
  // A process that died stalls the lockstep tick anyway; a later "lost"
  // costs nothing, a false one misleads.
  // The conductor and the recorder are told of every departure at once.
  struct Liveness {
    Clock::time_point heard{};                  // its newest sample
    Clock::duration longest_silence{};          // between two of its samples
    std::optional<Clock::time_point> departed;  // a departure not judged yet
    bool reported_lost = false;                 // "lost" was logged, "back" not yet
    bool lapse_noted = false;
  };
  enum class Who : uint8_t { Uav, Place };
  // A sample of `id` at `now`. True if it had been reported lost (it is back).
  // `new_life`: the sample is of a process started again (a restart), so a
  // departure not judged yet was a death, not a lapse.
  bool heard(Who who, uint32_t id, Clock::time_point now, bool new_life = false);
  void departed(Who who, uint32_t id, Clock::time_point now);
  void note_lapse(Who who, uint32_t id);
  // How long after its departure `l` is judged (see Liveness).
  [[nodiscard]] Clock::duration wait(const Liveness& l) const;
  // Reports the departures not heard again within their wait (all: every one).
  void judge_departures(Clock::time_point now, bool all);
  void note_lost(Who who, uint32_t id);
  [[nodiscard]] std::string who_text(Who who, uint32_t id) const;
  void refuse(core::Refusal r, const std::string& what);
  void note(IntakeNote::Kind kind, IntakeNote::Level level, std::string line);

  Parts p_;
  Standby standby_;
  core::MapGeometry geo_;
  uint32_t swarm_;  // the scenario's UAVs: ids 0..swarm_-1
  int layers_;
  std::vector<core::ValueRange> layer_ranges_;  // physical range per layer (tiles out of it are refused)
  UncertaintyTracker* uncertainty_ = nullptr;
  std::map<FrameBuilder::TileKey, core::TileMsg> tiles_;
  Clock::duration lease_;
  Pace pace_;
  std::map<uint32_t, Liveness> uav_live_, place_live_;  // by UAV id, by place_id
  std::vector<std::pair<Who, uint32_t>> pending_;       // departures not judged yet, in their order
  uint64_t lapses_ = 0;
  Notes notes_;  // of the call under way
  std::optional<Clock::time_point> heard_places_finished_;  // heard_places_over: since when
  core::PlaceVouch places_;
  core::SwarmNames names_;  // the UAV ids and place agents (region, replica) the run has
  core::Parked<core::UavStateMsg> parked_states_;
  core::Parked<core::UavDeparture> parked_departures_;
  core::Parked<core::BroadcastMsg> parked_broadcasts_;
  core::Parked<core::DetectionMsg> parked_detections_;
  core::Parked<core::TargetEventMsg> parked_events_;
  core::Parked<core::FieldMsg> parked_fields_;
  core::Parked<core::TileMsg> parked_tiles_;
};

}  // namespace pheromesh::console
