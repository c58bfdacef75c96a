// pheromesh-place: owns the pheromone tiles of one region (the software twin
// of an RFID tag / unattended ground sensor). The logic is core::PlaceCore;
// this shell wires it to the bus and a clock. It is also the home of the
// UAVs with core::home_region(uav) == its region: it forwards their deposits
// for other regions to the owners, and each tick sends each of them its view
// (core::ViewServer), composed from the fields every place agent publishes.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <vector>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/core/place_core.hpp"
#include "pheromesh/core/conductor.hpp"
#include "pheromesh/core/plausibility.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/tick_gaps.hpp"
#include "pheromesh/core/view_server.hpp"
#include "pheromesh/runtime/commands.hpp"
#include "pheromesh/runtime/process.hpp"
#include "pheromesh/bus/resend.hpp"

namespace spdlog {
class logger;
}

namespace pheromesh::placeagent {

struct PlaceConfig {
  runtime::CommonOptions common;
  core::RegionId region = 0;
  uint32_t max_ticks = 0;  // 0: run until SIGINT/SIGTERM (realtime clock)
  uint16_t replica = 0;    // 0 the primary, 1.. hot standbys (--standby swarms)
};

class PlaceApp {
 public:
  PlaceApp(PlaceConfig cfg, core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus);
  int run();

 private:
  int run_realtime();
  int run_lockstep();
  // One tick. `exact` (lockstep): wait (bounded) for every neighbour's ring
  // of this tick and every region's field of this tick; otherwise use the
  // latest received. `expected_deposits` (lockstep): wait (bounded) until
  // this many deposits of `tick` for this region have arrived.
  void step(uint32_t tick, bool exact, std::optional<uint32_t> expected_deposits = {});
  // Takes deposits into inbox_ (this region's) and forwards the others to
  // their owner's place agent (or counts them rejected if it is unreachable).
  void take_deposits();
  void take_home_states(uint32_t tick);
  // Publishes this region's field of `tick` and sends the home UAVs their views.
  void serve_views(uint32_t tick, bool exact);
  void publish_health(uint32_t tick, bool finished);
  // A replicated swarm: the same deposit can come twice (forwarded by both
  // replicas of its UAV's home). True if this one was seen before.
  bool duplicate(const core::DepositMsg& d);
  void log_summary(uint32_t tick);
  // Lockstep: the clock's absent regions (place agents killed at a tick,
  // without a standby) join absent_; nobody waits for them any more.
  void note_absent(const core::ClockMsg& c);
  [[nodiscard]] bool is_absent(core::RegionId r) const { return absent_.contains(r); }

  PlaceConfig cfg_;
  core::ScenarioConfig scenario_;
  core::MapGeometry geo_;
  std::unique_ptr<bus::Bus> bus_;
  bus::LatestResender resend_;  // lockstep: this tick's fields, views, halo, PhaseDone
  std::shared_ptr<spdlog::logger> log_;
  core::PlaceCore core_;
  uint64_t halos_missing_ = 0;
  double rate_ = 0.0;
  core::TickGaps gaps_;  // realtime: gaps between tick starts (reported in the health)
  std::vector<core::DepositMsg> inbox_;
  std::vector<core::HaloMsg> halo_inbox_;
  std::vector<core::TargetEventMsg> events_;
  std::vector<core::TileMsg> tiles_out_;
  std::vector<std::string> rejections_;
  std::unique_ptr<runtime::SwarmCommands> commands_;  // pause / resume
  // Home UAVs and views.
  core::ViewServer views_;
  core::PolicyTraits traits_;
  std::vector<core::ValueRange> layer_ranges_;  // physical range per layer (plausibility.hpp)
  double max_step_;                             // [cell/tick] the farthest a UAV flies in one tick
  std::vector<uint32_t> home_uavs_;
  std::vector<core::RegionId> other_regions_;
  std::map<uint32_t, uint32_t> heard_at_;  // home UAV -> place tick of its newest state
  std::vector<core::DepositMsg> taken_;
  std::vector<core::UavStateMsg> state_inbox_;
  std::vector<core::FieldMsg> field_inbox_;
  std::vector<core::UavStateMsg> home_states_;
  core::ViewMsg view_;
  uint64_t deposits_forwarded_ = 0;
  bool replicated_ = false;                          // --standby swarm
  std::map<uint32_t, std::set<uint32_t>> seen_seq_;  // replicated: per UAV, the newest deposit seqs received
  uint64_t duplicates_ = 0;
  // home UAV -> highest deposit seq received from it (its views carry it), and
  // the place tick it came at (a seq far ahead of it is not acknowledged).
  std::map<uint32_t, std::pair<uint32_t, uint32_t>> acked_;
  uint64_t deposits_lost_ = 0;  // lockstep: home UAVs' deposits for absent regions, not forwarded
  std::set<core::RegionId> absent_;
  std::vector<core::RegionId> present_others_;  // other_regions_ without the absent ones
  uint64_t samples_rejected_ = 0;  // malformed home states and field chunks, dropped
  // Plausibility (core/plausibility.hpp): samples refused here (deposits and
  // halo rings are counted by core_), the tick the place agent is at, and
  // the conductor's clock writer, latched from its first sample.
  core::RefusalCounts refused_;
  uint32_t current_tick_ = 0;
  bool exact_ = false;  // lockstep
  std::optional<uint64_t> conductor_;
  [[nodiscard]] uint32_t tick_ceiling() const;
  void refuse(core::Refusal r, const std::string& what);
  // Lockstep: drops clock samples of writers other than the conductor's.
  void keep_conductor_clock(std::vector<core::ClockMsg>& cmds);
};

}  // namespace pheromesh::placeagent
