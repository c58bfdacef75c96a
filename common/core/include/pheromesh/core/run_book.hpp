// The ground station's bookkeeping of a run, without DDS: when a realtime
// swarm gets its Start, how long discovery took, which tick's field each
// region delivered, when --until-done may end the run, when every place
// agent finished, when an attached monitor shows the whole swarm, and the
// highest tick a sample can carry now (plausibility.hpp). Time is passed in;
// each call returns what happened, and the ground station logs it and
// publishes what it must (the Start). Follows LockstepConductor.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <set>

#include "pheromesh/core/conductor.hpp"
#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/plausibility.hpp"
#include "pheromesh/core/run_metrics.hpp"

namespace pheromesh::core {

class RunBook {
 public:
  using Clock = std::chrono::steady_clock;

  // What this ground station does in the run.
  enum class Role : uint8_t {
    Starter,    // realtime: sends the swarm its Start once discovery is over (or its bound passed)
    Conductor,  // lockstep: the conductor's clock starts the swarm
    Monitor,    // --attach: starts, conducts and ends nothing
  };

  struct Options {
    Role role = Role::Starter;
    uint32_t uavs = 0;  // expected
    uint32_t regions = 0;
    double tick_rate_hz = 10.0;
    Clock::time_point started{};                // this process's start
    std::optional<Clock::time_point> launched;  // the run's launch ($PHEROMESH_RUN_T0_MS), if known
    TickSlack launch_slack = kLaunchSlack;      // how far ahead of `launched` a sender's clock may run
  };

  // How many UAVs and place agents (regions) were heard so far.
  struct Heard {
    std::size_t uavs = 0;
    std::size_t regions = 0;
  };

  enum class StartNow : uint8_t {
    No,                     // not a starter, already sent, or still waiting for someone
    EveryoneHeard,          // send the Start: every process was heard
    WithoutSomeAfterBound,  // send the Start: the bound passed without hearing everyone
  };
  struct Discovery {
    // The first time every process was heard: seconds since the launch (else
    // since this process started).
    std::optional<double> complete_s;
    StartNow start = StartNow::No;
    std::size_t uavs_missing = 0, regions_missing = 0;  // with WithoutSomeAfterBound
    std::size_t regions_unlinked = 0;                   // with WithoutSomeAfterBound: heard, not linked
  };

  explicit RunBook(Options o) : o_(o) {}

  // --- discovery and the realtime start gate
  // Realtime UAVs wait for the Start to fly: once every process is heard and
  // every region's place agent is linked (note_linked), or after
  // start_bound() (one process that never came up does not hold the others
  // back). A Start is returned once.
  Discovery note_discovery(Heard heard, Clock::time_point now);
  // Region r's place agent matched every other region's (HealthMsg::linked):
  // a deposit its home UAVs make elsewhere reaches the owner.
  void note_linked(RegionId r);
  [[nodiscard]] std::size_t regions_linked() const { return linked_.size(); }
  [[nodiscard]] std::optional<double> discovery_s() const { return discovery_s_; }
  [[nodiscard]] bool start_sent() const { return start_sent_; }
  // 30 s, and 0.1 s more per expected UAV.
  [[nodiscard]] std::chrono::milliseconds start_bound() const;

  // --- fields
  // A plausible chunk of region r's field of `tick`: a newer tick restarts
  // the count of its chunks.
  void on_field_chunk(RegionId r, uint32_t tick, uint16_t chunk, uint16_t chunks);
  // Every region present (not absent in the conductor) delivered every chunk
  // of its field of `tick`.
  [[nodiscard]] bool holds_last_fields(uint32_t tick, const LockstepConductor& conductor) const;

  // --- the end of the run
  // --until-done: every expected UAV was heard (or the Start went out
  // without some) and each is done: it finished; or it was killed (a fault:
  // note_uav_killed, or dropped by the conductor at a tick) and was not heard
  // since; or its liveliness lapsed and it stayed silent past the departed
  // grace (LockstepConductor::gone_for_good). A UAV whose liveliness lapsed
  // is not done before that: a stopped (SIGSTOP) or overloaded process may
  // come back and finish.
  [[nodiscard]] bool uavs_done(const RunRecorder& rec, const LockstepConductor& conductor,
                               Clock::time_point now) const;
  // The UAV was killed on purpose at `now` (the console's kill, answered by
  // the launcher): it no longer flies. A sample heard from it later (a
  // restart) makes it fly again.
  void note_uav_killed(uint32_t uav, Clock::time_point now) { killed_[uav] = now; }
  // Every replica heard of every region reported its final health or is gone
  // (a killed primary whose standby finished counts as done).
  [[nodiscard]] bool places_finished(const RunRecorder& rec) const;

  // --- --attach
  // Seconds since the launch, returned once: the first time every UAV and
  // place agent was heard and every region's field arrived.
  std::optional<double> note_full_state(Heard heard, Clock::time_point now);

  // --- plausibility
  // Lockstep: the conductor announced `tick`.
  void note_conducted(uint32_t tick) { conducted_tick_ = std::max(conducted_tick_, tick); }
  // The highest tick a sample can carry at `now`: the conductor's own clock
  // (lockstep); the launch time shared by every process of the run
  // (realtime); unlimited for a monitor, which does not know the launch.
  [[nodiscard]] uint32_t tick_ceiling(Clock::time_point now) const;
  // [s], to the millisecond.
  [[nodiscard]] double seconds_since_launch(Clock::time_point now) const;

 private:
  Options o_;
  std::optional<double> discovery_s_;
  bool start_sent_ = false;
  std::set<RegionId> linked_;
  std::map<uint32_t, Clock::time_point> killed_;  // UAV -> when it was killed
  bool full_state_noted_ = false;
  uint32_t conducted_tick_ = 0;
  std::map<RegionId, std::pair<uint32_t, std::set<uint16_t>>> field_ticks_;  // region -> newest tick, its chunks seen
  std::map<RegionId, uint16_t> field_chunks_;                                // region -> chunks per field
};

}  // namespace pheromesh::core
