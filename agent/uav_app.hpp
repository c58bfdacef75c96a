// pheromesh-uav: one UAV. The logic is core::UavCore (the scenario's
// policy); this shell wires it to the bus and a clock. It reads one view per
// tick - the tiles around it and the UAVs over them - and writes its state
// and deposits, all through its home place agent (core::home_region), with
// DDS endpoints created once at start-up.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/bus/resend.hpp"
#include "pheromesh/core/conductor.hpp"
#include "pheromesh/core/home_watch.hpp"
#include "pheromesh/core/lockstep_follower.hpp"
#include "pheromesh/core/plausibility.hpp"
#include "pheromesh/core/receipts.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/tick_gaps.hpp"
#include "pheromesh/core/uav_core.hpp"
#include "pheromesh/core/view_pacing.hpp"
#include "pheromesh/core/world.hpp"
#include "pheromesh/runtime/commands.hpp"
#include "pheromesh/runtime/process.hpp"
#include "pheromesh/runtime/sample_audit.hpp"

namespace spdlog {
class logger;
}

namespace pheromesh::agent {

struct UavConfig {
  runtime::CommonOptions common;
  uint32_t id = 0;
  double wait_for_places_s = 15.0;  // [s] wait at start until the home place agent is matched
  double wait_for_start_s = 300.0;  // [s] realtime: wait at most this long for the ground station's start
  uint32_t seq_base = 0;  // first deposit sequence number - 1 (a restarted UAV continues above its old life's)
};

class UavApp {
 public:
  UavApp(UavConfig cfg, core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus);
  int run();

 private:
  void wait_for_home();
  void wait_for_start();
  void receive();
  // Lockstep: wait (bounded) until the view of place tick `tick` (the tiles
  // around this UAV and the states of the UAVs over them) and the broadcasts
  // the clock announced of UAV tick `tick` have arrived.
  void wait_for_tick(uint32_t tick, const core::ClockMsg& announced);
  // Whether the UAV phase of clock `c` can run now without waiting: what
  // wait_for_tick waits for is here (it takes what the bus holds), and the
  // gateway stays (a new one is opened and waited for). The lockstep loop
  // runs such a phase in the bus's receive thread (runtime::LockstepLoop::ready).
  bool ready_for(const core::ClockMsg& c);
  // Fly: decide, move, deposit and publish the state of `tick`. Finish: only
  // the last state, marked finished.
  enum class StepKind : uint8_t { Fly, Finish };
  void step(uint32_t tick, StepKind kind);
  void report_ready_once();
  void run_uav_phase(const core::ClockMsg& c, uint32_t ticks);
  // Ground-station commands: pop-ups change this UAV's world; pause is kept by commands_.
  void handle_commands();
  int run_realtime(uint32_t ticks);
  // Realtime: run the next tick now, started by a view (receive thread) or
  // by the timer (core::ViewPacing); the caller holds the loop's mutex.
  void run_paced_tick(uint32_t& tick, core::ViewPacing& pacing, std::chrono::steady_clock::time_point now,
                      bool by_view);
  // Realtime, the main thread's timer: the tick no view ran (with, after
  // the home's silence, the move to the backup gateway), or the pause.
  void timer_came(uint32_t& tick, core::ViewPacing& pacing, std::chrono::steady_clock::time_point now);
  int run_lockstep(uint32_t ticks);

  UavConfig cfg_;
  core::ScenarioConfig scenario_;
  core::MapGeometry geo_;
  core::World world_;
  std::unique_ptr<bus::Bus> bus_;
  bus::LatestResender resend_;       // lockstep: this tick's PhaseDone
  core::LockstepFollower follower_;  // lockstep: the conductor's clock, the phases to run
  bool ready_ = false;               // lockstep: Ready reported (or tick 0 began without it)
  std::shared_ptr<spdlog::logger> log_;
  runtime::SampleAudit audit_;  // received samples dropped and refused (the refusals go out in the state)
  core::UavCore core_;
  core::UavCore::Output out_;
  std::vector<core::DepositMsg> uplink_;  // this tick's deposits, to go up in its state
  uint64_t deposits_sent_ = 0;
  uint64_t deposits_undeliverable_ = 0;
  core::DepositReceipts receipts_;  // deposits its home place agent has not confirmed yet
  // Before the last state: wait (bounded) until the home confirmed every deposit.
  void wait_for_receipts(std::chrono::milliseconds bound);
  uint64_t tile_samples_received_ = 0;
  uint64_t samples_received_ = 0;  // views + broadcasts + commands taken
  uint32_t ticks_late_ = 0;        // realtime: ticks that started more than one period late
  core::TickGaps gaps_;            // realtime: gaps between tick starts (reported in the state)
  std::vector<core::ViewMsg> view_inbox_;
  std::optional<uint32_t> view_tick_;  // tick of the newest view received
  std::vector<core::BroadcastMsg> broadcast_inbox_;
  int layers_ = 0;
  core::RegionId home_ = 0;  // the place agent this UAV talks to while it lives
  // Its gateway: home_, else its backup (core::gateway_region); none when both
  // are dead. Lockstep: from the clock's absent regions at `tick`.
  std::optional<core::RegionId> gateway_;
  [[nodiscard]] std::optional<core::RegionId> gateway_at(uint32_t tick) const;
  // Moves the state and deposit writers to `gateway` (bounded wait for its
  // readers in lockstep).
  void switch_gateway(core::RegionId gateway, uint32_t tick);
  // Realtime: whether the home is gone (its views silent), after which the
  // backup serves this UAV.
  core::HomeWatch home_watch_;
  // What the last step wrote (lockstep reports it with PhaseDone).
  std::map<core::RegionId, uint32_t> written_;
  bool broadcast_written_ = false;
  bool conductor_lost_ = false;  // lockstep: no clock for ConductorWatch's limit
  std::unique_ptr<runtime::SwarmCommands> commands_;
  std::vector<core::ValueRange> layer_ranges_;  // physical range per layer (core/intake.hpp)
  [[nodiscard]] uint32_t tick_ceiling() const;
};

}  // namespace pheromesh::agent
