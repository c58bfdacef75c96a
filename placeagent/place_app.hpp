// pheromesh-place: owns the pheromone tiles of one region (the software twin
// of an RFID tag / unattended ground sensor). The logic is core::PlaceCore,
// what it makes of each received sample core::PlaceIntake's and the tiles
// each view needs core::ViewServer's; this shell wires them to the bus and a
// clock. It is also the home of the
// UAVs with core::home_region(uav) == its region, and the backup gateway of
// those whose home is the previous region once that one died
// (core::gateway_region): it forwards their deposits for other regions to
// the owners, and each tick sends each of them its view (core::ViewServer).
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/bus/resend.hpp"
#include "pheromesh/core/field_to_ground.hpp"
#include "pheromesh/core/intake.hpp"
#include "pheromesh/core/lockstep_follower.hpp"
#include "pheromesh/core/place_core.hpp"
#include "pheromesh/core/place_intake.hpp"
#include "pheromesh/core/receipts.hpp"
#include "pheromesh/core/relay_batch.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/sender_judge.hpp"
#include "pheromesh/core/tick_gaps.hpp"
#include "pheromesh/core/uplink_reports.hpp"
#include "pheromesh/core/view_server.hpp"
#include "pheromesh/core/writer_latch.hpp"
#include "pheromesh/runtime/commands.hpp"
#include "pheromesh/runtime/lockstep_loop.hpp"
#include "pheromesh/runtime/process.hpp"
#include "pheromesh/runtime/sample_audit.hpp"

namespace spdlog {
class logger;
}
namespace CLI {
class App;
}

namespace pheromesh::placeagent {

struct PlaceConfig {
  runtime::CommonOptions common;
  core::RegionId region = 0;
  uint16_t replica = 0;   // 0 the primary, 1.. hot standbys (--standby swarms)
  double field_hz = 5.0;  // realtime: fields to the ground station per second (core::FieldToGround)
  uint32_t life = 1;      // 2..: started again after its death (pheromesh run's restart): no deposit history
};

// The flags of pheromesh-place (`replica`: --replica, checked 0..999).
void add_place_options(CLI::App& app, PlaceConfig& cfg, uint32_t& replica);
// The flags against the scenario: nullopt if they fit, else the exit code
// (the reason logged).
std::optional<int> check_place_config(const PlaceConfig& cfg, const core::ScenarioConfig& scenario);

class PlaceApp {
 public:
  PlaceApp(PlaceConfig cfg, core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus);
  int run();

 private:
  // Lockstep: what the place phase of a tick must hold before it applies the
  // tick, as its clock announced (core/conductor.hpp).
  struct TickDemand {
    uint32_t deposits = 0;  // of this tick, for this region
    uint32_t states = 0;    // of this tick, of the home UAVs
    // Every region's served UAVs of this tick, as the place clock lists them
    // (the clock's, alive during the step).
    const std::vector<core::ServedUav>* served = nullptr;
  };
  enum class HealthKind : uint8_t { Running, Final };

  int run_realtime();
  int run_lockstep();
  void report_ready_once();
  // Every other region's place agent reads the deposits this one forwards
  // (sticky once true; health carries it, and the realtime Start waits for it).
  bool note_linked();
  // Lockstep: runs the place phase of clock `c` as far as the samples held
  // let it (Pending until it holds what each stage needs).
  runtime::PhaseOutcome run_place_phase(const core::ClockMsg& c);
  // The stages of a tick; each ends when it holds what it needs (lockstep:
  // exactly as announced) or its bound passed (stage_end).
  enum class Stage : uint8_t {
    Inputs,  // the home UAVs' states and the deposits for this region
    Rings,   // the neighbours' rings of this tick
    Tiles,   // the tiles its served UAVs' views need from other regions
    Done,
  };
  enum class StageEnd : uint8_t { Wait, Held, Late };
  // Realtime: one tick, every stage on what arrived.
  void step(uint32_t tick);
  // Starts a tick: with a demand (lockstep) advance_step waits (bounded)
  // for exactly the deposits and home states announced, every neighbour's
  // ring of this tick and the tiles of this tick its views need; without
  // (realtime) it uses the latest received.
  void begin_step(uint32_t tick, std::optional<TickDemand> demand);
  // Takes what the bus holds and runs the stages it completes; true once
  // the tick is done (its views sent). Never waits.
  bool advance_step();
  [[nodiscard]] StageEnd stage_end(bool held) const;
  void next_stage(Stage s);
  [[nodiscard]] uint32_t deposits_of(uint32_t tick) const;  // of `tick`, taken for this region
  [[nodiscard]] bool inputs_held(uint32_t tick) const;
  void log_inputs_late(uint32_t tick) const;
  // The deposits applied, the ring sent to each neighbour.
  void apply_inputs(uint32_t tick);
  void take_rings(uint32_t tick);
  // The rings taken, the field updated; its field to the ground station and
  // its tiles to the other place agents.
  void update_field(uint32_t tick);
  // The home UAVs served this tick (served_) and their states, to the other place agents.
  void publish_served(uint32_t tick);
  // Publishes this region's field of `tick` to the ground station and sends
  // the other place agents the tiles their UAVs' views need.
  void send_field_and_tiles(uint32_t tick);
  // The served home UAVs' views.
  void send_views(uint32_t tick);
  // To each other place agent the tiles of this region its UAVs' views need.
  void send_tiles(uint32_t tick);
  // The tiles the served UAVs' views need from the other regions.
  void take_tiles(uint32_t tick);
  [[nodiscard]] std::vector<core::RegionId> owners_for_views() const;
  // Realtime: owners send the tiles within one more cell, as a UAV has moved
  // since the state they used; lockstep: exactly the view's tiles.
  [[nodiscard]] int32_t tile_margin() const { return demand_ ? 0 : 1; }
  // Takes deposits into inbox_ and forwards the others to their owner's place
  // agent (logs it if it is unreachable: forward_failed).
  void take_deposits();
  void forward(const core::DepositMsg& d);  // into to_forward_
  void flush_forwards();                    // to_forward_ out, a batch per owner
  void forward_failed(const core::DepositMsg& d, const char* why);
  // `batch` (lockstep, between phases): the relays to the ground station
  // wait for the rest of the UAV phase's reports (core::RelayBatch).
  void take_home_states(uint32_t tick, bool batch = false);
  // The departures of UAVs' state writers: told to the ground station (in relayed_).
  void take_departures();
  // A state of a UAV this place agent serves that check_home_state refused
  // (StateGate): told to the ground station, an empty view owed to the UAV.
  void answer_refused(const core::UavStateMsg& st);
  // The deposits in carried_ of a state judged as `fate` (core::
  // CarriedDeposits): on to take_deposits, kept for reject_carried, or refused.
  void route_carried(core::CarriedDeposits fate);
  // The deposits of states refused for their motion, taken since the last
  // call: through the desk, then rejected and refused (take_deposits).
  void reject_carried();
  // The served UAVs of every other present region (lockstep: of `tick`, as
  // the place clock lists them; realtime: the chunks that came).
  void take_served(uint32_t tick);
  // Home UAVs whose newest state is of `tick` or later.
  [[nodiscard]] uint32_t home_states_of(uint32_t tick) const;
  // Every deposit the home UAVs with a state of `tick` wrote was taken (applied or forwarded).
  [[nodiscard]] bool holds_home_deposits(uint32_t tick) const;
  void publish_health(uint32_t tick, HealthKind kind);
  // The final health, flushed, and the summary in the log.
  void finish(uint32_t tick);
  void log_summary(uint32_t tick);
  // The clocks' absent regions (place agents killed at a tick, without a
  // standby) join absent_; nobody waits for them any more.
  void note_absent();
  [[nodiscard]] bool is_absent(core::RegionId r) const { return absent_.contains(r); }
  // The backup gateway: UAV `uav`, whose backup this region is, talks to this
  // place agent from now on (lockstep: its home is absent; realtime: its state
  // came here). `state_before`: its last state its home served (lockstep),
  // from which this place agent counts the deposits it must hold.
  void adopt(uint32_t uav, const core::UavStateMsg* state_before);
  [[nodiscard]] uint32_t tick_ceiling() const;
  // The lockstep tree: relays every clock this place agent accepted to the
  // UAVs it serves (and, relay_uplinks, their reports to the conductor) in
  // every round of the lockstep loop, also while a place phase is pending.
  void relay_clock(const core::ClockMsg& c);
  void relay_one_clock(const core::ClockMsg& c);
  // Writes `c` on the relay writer to the UAVs `to` names.
  void send_clock(const core::ClockMsg& c, core::UavClockRelay::To to);
  void relay_uav_clock_after_views(uint32_t tick);
  // The UAV clock the views of place tick `tick` carry to the UAVs homed
  // here (nullptr: none), decided once per clock (core::UavClockRelay).
  const core::ClockMsg* clock_for_views(uint32_t tick);
  void relay_reports();
  // Relays (docs/architecture.md, "Relays"): its UAVs' reports, detections
  // and broadcasts up, the swarm's broadcasts and the ground station's
  // commands down (their states and departures go up in take_home_states).
  // Realtime: once a tick; lockstep: in every round of the lockstep loop.
  void relay_uplinks();
  // Lockstep, between phases and after the Stop: also takes (and relays) the
  // states of the UAVs it serves.
  void relay_idle();
  // Who forwarded a deposit (issue 28, core::PlaceIntake::judge_forwarded):
  // judges the forwarded deposits in taken_ from index `first`.
  void judge_forwarded(std::size_t first);

  PlaceConfig cfg_;
  core::ScenarioConfig scenario_;
  core::MapGeometry geo_;
  std::unique_ptr<bus::Bus> bus_;
  bus::LatestResender resend_;  // lockstep: this tick's fields, views, halo, PhaseDone
  std::shared_ptr<spdlog::logger> log_;
  runtime::SampleAudit audit_;       // received samples dropped and refused (deposits and rings: core_)
  core::LockstepFollower follower_;  // lockstep: the conductor's clock, the phases to run
  core::UavClockRelay uav_clocks_;   // which of them go on to the UAVs served
  // The UAV clock a place clock began, relayed after this place phase's views.
  std::optional<core::ClockMsg> uav_clock_after_views_;
  // Where it goes, once decided (clock_for_views), and the home UAVs whose
  // view carried it: the relay writes it only for the others.
  std::optional<core::UavClockRelay::To> view_clock_to_;
  std::vector<uint32_t> clocked_views_;
  core::PlaceCore core_;
  double rate_ = 0.0;
  core::TickGaps gaps_;  // realtime: gaps between tick starts (reported in the health)
  core::PolicyTraits traits_;
  core::ViewServer views_;   // home UAVs' states and every region's field, composed into views
  core::IntakeRules rules_;  // what a received sample is checked against
  core::DepositDesk desk_;   // where each taken deposit goes; what the home UAVs' views confirm
  std::unique_ptr<runtime::SwarmCommands> commands_;  // pause / resume
  std::vector<uint32_t> home_uavs_;
  std::vector<uint32_t> backed_up_;  // the UAVs homed elsewhere whose backup gateway this region is
  // The UAVs whose gateway this place agent is: its home UAVs, and those it
  // adopted as their backup (adopt); their deposits-sent count and this
  // place agent's taken count when adopted.
  std::vector<uint32_t> gateway_uavs_;
  std::map<uint32_t, std::pair<uint64_t, uint64_t>> adopted_;
  std::vector<core::RegionId> other_regions_;
  std::vector<core::RegionId> present_others_;  // other_regions_ without the absent ones
  std::set<core::RegionId> absent_;
  std::size_t absent_seen_ = 0;              // follower_.absent() entries handled
  bool replicated_ = false;                  // --standby swarm
  bool ready_ = false;                       // lockstep: Ready reported (or tick 0 began without it)
  bool linked_ = false;                      // note_linked()
  std::vector<core::PhaseDoneMsg> reports_;  // relay_reports' inbox
  uint64_t clocks_relayed_ = 0, reports_relayed_ = 0, states_relayed_ = 0;
  std::vector<core::UavDeparture> departed_;
  std::vector<core::DetectionMsg> detections_up_;
  std::vector<core::BroadcastMsg> broadcasts_;
  uint32_t current_tick_ = 0;
  std::optional<TickDemand> demand_;       // the tick under way's (lockstep)
  // Lockstep: the clock of the latest place phase (demand_.served points
  // into it), and where its step stands (Done: no phase under way).
  std::optional<core::ClockMsg> phase_clock_;
  Stage stage_ = Stage::Done;
  std::chrono::steady_clock::time_point stage_deadline_{};
  std::set<core::RegionId> fresh_rings_;     // the neighbours whose ring of the tick was taken
  std::size_t rings_awaited_ = 0;            // present neighbours
  std::vector<core::RegionId> tile_owners_;  // lockstep: the regions whose tiles the views need
  std::optional<uint32_t> served_listed_;  // lockstep: the tick whose clock's served UAVs views_ holds
  std::map<uint32_t, uint32_t> heard_at_;  // home UAV -> place tick of its newest state
  // The judgement of every received sample (core::PlaceIntake): each UAV's
  // state writer as first heard (a plausible forged state from another
  // writer would become the "last accepted" one and get the UAV's own
  // refused; issue 28), given up at its departure or after a silence of a
  // lease (realtime: a UAV writes every tick) or of 6 leases (lockstep: a
  // waiting UAV writes again every second, and under packet loss a tick
  // takes seconds); the one plausibility rule (core::StateGate): a refused
  // state of a UAV it serves is answered - relayed to the ground station as
  // such, and an empty view of its tick to the UAV (answer_refused,
  // send_views); the other place agents' processes, which forward deposits.
  core::PlaceIntake intake_;
  core::UplinkReports uplink_reports_;         // lockstep: its UAVs' reports, made from their states
  std::vector<core::PhaseDoneMsg> reports_out_;  // lockstep: those held, published after their states
  core::RelayBatch relay_batch_;                 // lockstep: when relayed_ and reports_out_ go
  std::vector<uint32_t> refused_views_;          // UAVs owed an empty view at the next send_views
  std::vector<core::IntakeVerdict> verdicts_;  // judge_forwarded's refusals
  // Reusable inboxes and outboxes.
  // uplinked_: deposits the UAVs' states carried, not yet routed (take_deposits).
  // carried_: those of the state take_home_states is judging.
  // refused_carried_: those of states refused for their motion (reject_carried).
  std::vector<core::DepositMsg> taken_, inbox_, uplinked_, carried_, refused_carried_, rejected_carried_;
  // relayed_: the states and departures take_home_states relays to the ground station.
  std::vector<core::UavStateMsg> state_inbox_, home_states_, served_states_, relayed_;
  std::vector<uint32_t> served_;  // home UAVs that get a view this tick
  std::vector<uint32_t> listed_;  // lockstep: the UAVs the place clock lists as this region's (sorted)
  std::vector<std::string> malformed_;  // lockstep: the place clock's served UAVs not taken, and why
  std::vector<core::TileMsg> tiles_for_;
  uint32_t tiles_stale_after_ = 10;  // realtime: place ticks a tile not sent again is still shown
  std::vector<core::FieldMsg> field_inbox_;
  std::vector<core::HaloMsg> halo_inbox_;
  std::vector<core::TargetEventMsg> events_;
  std::vector<core::TileMsg> tiles_out_;
  core::FieldToGround to_ground_;  // what of the field goes to the ground station, when
  std::vector<core::TileMsg> ground_tiles_;
  bool last_tick_ = false;  // realtime: the drain after the last tick (a full field goes out)
  std::vector<std::string> rejections_;
  core::ViewMsg view_;
  // Counts for the health and the summary.
  uint64_t halos_missing_ = 0;
  std::map<core::RegionId, std::vector<core::DepositMsg>> to_forward_;  // this take's, by owner (flush_forwards)
  uint64_t deposits_forwarded_ = 0;
  uint64_t deposits_lost_ = 0;    // lockstep: home UAVs' deposits for absent regions, not forwarded
  uint64_t forwards_failed_ = 0;  // deposits for other regions that could not be forwarded
};

}  // namespace pheromesh::placeagent
