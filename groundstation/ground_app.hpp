// pheromesh-ground (headless): subscribes to everything, prints progress,
// records the run metrics (core::RunRecorder) and writes OUT/metrics.json and
// OUT/final_field.txt at the end. With the lockstep clock it is also the
// conductor that advances the numbered ticks.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "console_live.hpp"
#include "pheromesh/bus/bus.hpp"
#include "pheromesh/auth/control.hpp"
#include "pheromesh/console/commands.hpp"
#include "pheromesh/console/frame_builder.hpp"
#include "pheromesh/console/launcher_link.hpp"
#include "pheromesh/console/recording.hpp"
#include "pheromesh/console/server.hpp"
#include "pheromesh/console/uncertainty.hpp"
#include "pheromesh/core/conductor.hpp"
#include "pheromesh/core/run_metrics.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/world.hpp"
#include "pheromesh/runtime/process.hpp"
#include "pheromesh/bus/resend.hpp"

namespace spdlog {
class logger;
}

namespace pheromesh::groundstation {

struct GroundConfig {
  runtime::CommonOptions common;
  std::string out_dir = ".";
  uint32_t expect_uavs = 0;  // 0: the scenario's swarm.uavs
  double progress_period_s = 1.0;
  double phase_timeout_s = 60.0;  // lockstep: longest wait for one phase [s]
  double start_timeout_s = 120.0; // lockstep: longest wait for every process's Ready before tick 0 [s]
  double departed_grace_s = 5.0;  // lockstep: a UAV silent this long after its liveliness lapsed is dropped [s]
  // Web console (docs/console.md): served when http_port is set (0: any free port).
  std::optional<uint16_t> http_port;
  std::string http_bind = "127.0.0.1";
  console::HttpLimits http_limits;  // --http-threads, --http-max-body
  double console_hz = 5.0;   // frames per second
  std::string record_path;   // record the console frames here (empty: no recording)
  int launcher_fd = -1;      // control socket from `pheromesh run` (kill / restart)
  std::string scenario_path;
  // Lockstep: ticks before whose UAV phase the launcher injects faults
  // (core/faults.hpp); the conductor asks it "faults K" and drops what it killed.
  std::vector<uint32_t> fault_ticks;
  double faults_timeout_s = 60.0;  // [s] longest wait for the launcher's answer
  bool standby = false;            // place agents have standby replicas: a killed one is replaced, its region stays
  // The ground station ends the run (no launcher to do it: a swarm over
  // several hosts, containers): once every expected UAV finished or was
  // lost, it publishes a signed End (place agents finish on it) and exits
  // after writing metrics.json.
  bool until_done = false;
  // A monitor that attached to a running swarm (pheromesh attach): it took
  // the scenario from the place agents, conducts nothing, starts and ends
  // nothing, sends no commands; it stops when every place agent finished.
  bool attach = false;
};

class GroundApp {
 public:
  GroundApp(GroundConfig cfg, core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus);
  int run();

 private:
  void poll();
  // Plausibility (core/plausibility.hpp): the highest tick a sample can carry
  // now, and a refusal counted for metrics.json.
  [[nodiscard]] uint32_t tick_ceiling() const;
  void note_refused(core::Refusal r, const std::string& what);
  // Logs and shows targets acquired for the first time.
  void note_acquisitions();
  // Until data arrives on any reader poll() takes, or `until`.
  void wait_for_data(std::chrono::steady_clock::time_point until);
  void progress_if_due();
  void print_progress();
  // Lockstep conductor: returns false if a phase timed out.
  bool conduct();
  bool run_phase(uint32_t tick, core::ClockPhase phase);
  // Lockstep: asks the launcher for the faults of `tick` and drops from the
  // protocol what it killed; false if the launcher could not say.
  bool apply_faults(uint32_t tick);
  // Lockstep: every present region's field of `tick` (all chunks) arrived.
  [[nodiscard]] bool holds_last_fields(uint32_t tick) const;
  // Lockstep: the launcher or the console killed these.
  void drop_uav(uint32_t uav, uint32_t tick);
  void drop_region(core::RegionId r, uint32_t tick);
  int finish();
  // --until-done: every expected UAV was heard (or the swarm started
  // without some) and each finished or was lost.
  [[nodiscard]] bool uavs_done() const;
  // Every region's place agent reported its final health (or is gone).
  [[nodiscard]] bool places_finished() const;
  // --attach: logs once when every UAV and place agent was heard and every
  // region's field arrived.
  void note_full_state();
  bool full_state_logged_ = false;
  void end_run();

  // --- web console, recording and commands
  void start_console();
  void service();  // main thread: pending commands, frames when due
  void build_frame();
  [[nodiscard]] std::string metrics_text() const;
  console::ConsoleSource::Answer execute(const nlohmann::json& body, const std::string& who);
  console::ConsoleSource::Answer apply(const console::ConsoleCommand& c);
  console::ConsoleSource::Answer publish_swarm_command(core::CommandMsg c);
  void log_command(const std::string& who, const std::string& what, const console::ConsoleSource::Answer& a);
  void log_refusals();  // the server's, rate-limited
  GroundConfig cfg_;
  console::LauncherLink launcher_;  // kill / restart, and pause so the launcher extends its deadline
  core::ScenarioConfig scenario_;
  core::MapGeometry geo_;
  core::World world_;
  std::unique_ptr<bus::Bus> bus_;
  bus::LatestResender resend_;  // lockstep: the clock of the phase under way
  std::shared_ptr<spdlog::logger> log_;
  core::RunRecorder rec_;
  std::map<console::FrameBuilder::TileKey, core::TileMsg> tiles_latest_;  // (layer, tile)
  console::FrameBuilder frame_builder_;  // what the console shows (also who was heard, for discovery)
  core::LockstepConductor conductor_;  // lockstep protocol (also departures, realtime)
  std::chrono::steady_clock::time_point next_progress_;
  // reusable inboxes
  std::vector<core::UavStateMsg> states_;
  std::vector<core::DetectionMsg> detections_;
  std::vector<core::TargetEventMsg> events_;
  std::vector<core::HealthMsg> healths_;
  std::vector<core::TileMsg> tiles_;
  std::vector<core::FieldMsg> fields_;
  std::map<core::RegionId, std::pair<uint32_t, std::set<uint16_t>>> field_ticks_;  // region -> newest tick, its chunks seen
  std::map<core::RegionId, uint16_t> field_chunks_;                               // region -> chunks per field
  std::vector<core::PhaseDoneMsg> dones_;
  std::vector<core::BroadcastMsg> broadcasts_;
  int layers_ = 0;
  std::vector<core::ValueRange> layer_ranges_;  // physical range per layer (tiles out of it are refused)
  uint32_t conducted_tick_ = 0;                 // lockstep: the tick the conductor announced last

  // --- web console
  std::unique_ptr<LiveConsole> console_;
  std::unique_ptr<console::ConsoleServer> server_;
  std::unique_ptr<console::RecordingWriter> recording_;
  std::unique_ptr<console::UncertaintyTracker> uncertainty_;
  std::optional<auth::ControlKey> control_key_;
  std::chrono::steady_clock::time_point console_t0_, next_frame_, next_series_;
  std::vector<core::Rect> popup_obstacles_;
  std::vector<console::CommandLogEntry> command_log_;           // for the next frame
  uint32_t command_seq_ = 0;
  uint64_t commands_ok_ = 0, commands_refused_ = 0, frames_ = 0;
  // Refused commands and requests reach the log and the recording at most 5
  // times in 10 s; the rest are summarised ("suppressed K").
  static constexpr uint32_t kRefusalsLogged = 5;
  static constexpr double kRefusalWindowS = 10.0;
  console::RefusalLimiter refusal_log_{kRefusalsLogged, kRefusalWindowS};
  bool paused_ = false;
  bool recording_failed_ = false;
  // Discovery: the launch time ($PHEROMESH_RUN_T0_MS, else this process's
  // start) and how long until every expected process was heard.
  int64_t run_t0_unix_ms_ = 0;
  bool launch_known_ = false;  // run_t0_unix_ms_ came from the launcher
  std::optional<double> discovery_s_;
  bool start_sent_ = false;
  bool ended_ = false;  // --until-done: the End went out
  std::chrono::steady_clock::time_point started_at_ = std::chrono::steady_clock::now();
  void note_discovery();
};

// pheromesh-ground --attach (attach.cpp): finds the running swarm on the
// domain, takes its scenario and options, then runs a GroundApp as a monitor.
int attach(GroundConfig cfg, double timeout_s);

}  // namespace pheromesh::groundstation
