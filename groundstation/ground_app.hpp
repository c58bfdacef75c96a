// pheromesh-ground (headless): subscribes to everything, prints progress,
// records the run metrics (core::RunRecorder) and writes OUT/metrics.json and
// OUT/final_field.txt at the end. With the lockstep clock it is also the
// conductor that advances the numbered ticks.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "console_live.hpp"
#include "mavlink_link.hpp"
#include "pheromesh/auth/control.hpp"
#include "pheromesh/bus/bus.hpp"
#include "pheromesh/bus/resend.hpp"
#include "pheromesh/console/commands.hpp"
#include "pheromesh/console/frame_builder.hpp"
#include "pheromesh/console/ground_intake.hpp"
#include "pheromesh/console/launcher_link.hpp"
#include "pheromesh/console/mavlink_feed.hpp"
#include "pheromesh/console/recording.hpp"
#include "pheromesh/console/server.hpp"
#include "pheromesh/console/uncertainty.hpp"
#include "pheromesh/core/conductor.hpp"
#include "pheromesh/core/run_book.hpp"
#include "pheromesh/core/run_metrics.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/world.hpp"
#include "pheromesh/mavlink/command_gate.hpp"
#include "pheromesh/runtime/process.hpp"

namespace spdlog {
class logger;
}

namespace CLI {
class App;
}  // namespace CLI

namespace pheromesh::groundstation {

// Time as the flags give it (seconds) and as waits take it; shared by the
// ground station's sources.
inline std::chrono::milliseconds millis(double seconds) {
  return std::chrono::milliseconds(static_cast<int64_t>(seconds * 1000));
}
inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct GroundConfig;
// The lockstep start timeout of `cfg` for a swarm of `processes` [s].
double start_timeout(const GroundConfig& cfg, uint32_t processes);

struct GroundConfig {
  runtime::CommonOptions common;
  std::string out_dir = "out/ground";
  uint32_t expect_uavs = 0;  // 0: the scenario's swarm.uavs
  double progress_period_s = 1.0;
  double phase_timeout_s = 60.0;  // lockstep: longest wait for one phase [s]
  // Lockstep: longest wait for every process's Ready before tick 0 [s]; 0:
  // 60 s and 1 s more per process (start_timeout()).
  double start_timeout_s = 0.0;
  double departed_grace_s = 5.0;  // lockstep: a UAV silent this long after its liveliness lapsed is dropped [s]
  // Web console (docs/console.md): served when http_port is set (0: any free port).
  std::optional<uint16_t> http_port;
  std::string http_bind = "127.0.0.1";
  console::HttpLimits http_limits;  // --http-threads, --http-max-body
  double console_hz = 5.0;          // frames per second
  std::string record_path;          // record the console frames here (empty: no recording)
  bool tracks = false;              // also OUT/tracks.csv (every UAV state heard; docs/outputs.md)
  int launcher_fd = -1;             // control socket from `pheromesh run` (kill / restart)
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
  // --mavlink udp:HOST:PORT: stream the swarm to a MAVLink ground-control
  // station and take its signed commands (docs/mavlink.md); empty: none.
  std::string mavlink;
  double mavlink_rate_hz = console::kMavlinkDefaultRateHz;  // [Hz] positions per UAV
};

class GroundApp {
 public:
  GroundApp(GroundConfig cfg, core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus);
  int run();

 private:
  using Clock = std::chrono::steady_clock;
  // Takes what arrived from the bus and hands it to the intake; logs its notes.
  void poll();
  void take_samples();
  void log_notes(const console::GroundIntake::Notes& notes);
  // Logs discovery, and sends the realtime swarm its Start (RunBook).
  void note_discovery(Clock::time_point now);
  // Until data arrives on any reader poll() takes, or `until`.
  void wait_for_data(Clock::time_point until);
  void progress_if_due();
  void print_progress();
  [[nodiscard]] core::RunBook::Heard heard() const;  // by the frame builder
  // --attach: logs once when every UAV and place agent was heard and every
  // region's field arrived.
  void note_full_state();
  // Ends the run if it is over for this ground station (--attach: every
  // place agent finished; --until-done: every UAV finished, then the End
  // goes out); true if it is.
  bool end_if_over();

  // --- lockstep (ground_lockstep.cpp)
  // The conductor: returns false if a phase timed out.
  bool conduct();
  // `next_uav_phase`: a place phase that begins the UAV phase of tick+1
  // (core::LockstepConductor::begin_phase); it returns once both are complete.
  bool run_phase(uint32_t tick, core::ClockPhase phase, bool next_uav_phase = false);
  // Whether the place phase of `tick` may begin the UAV phase of tick+1.
  [[nodiscard]] bool fuses_after(uint32_t tick, uint32_t ticks) const;
  // Paused from the console: the next tick is not announced (the last clock
  // is, again, so the swarm knows the conductor lives).
  void hold_while_paused();
  // The final field is that of the last tick: waits (bounded) until every
  // present region's field of it is here. False if it did not come.
  bool await_last_fields(uint32_t ticks);
  // Asks the launcher for the faults of `tick` and drops from the protocol
  // what it killed; false if the launcher could not say.
  bool apply_faults(uint32_t tick);
  // Before the launcher kills at `tick`: waits (bounded) until every live
  // place replica's health of the tick before is here.
  void await_health_before_kills(uint32_t tick);
  // The launcher's answer; meanwhile takes samples and keeps the clock going out.
  [[nodiscard]] console::ConsoleSource::Answer ask_faults(uint32_t tick);
  // The launcher or the console killed these.
  void drop_uav(uint32_t uav, uint32_t tick);
  void drop_region(core::RegionId r, uint32_t tick);

  // --- MAVLink (ground_mavlink.cpp)
  void start_mavlink();
  void service_mavlink();                                     // the stream due now, and the commands that arrived
  uint8_t carry_out(const mavlink::CommandGate::Command& c);  // its MAV_RESULT
  void finish_mavlink();                                      // the totals: log and OUT/mavlink.json

  // --- the end
  int finish();
  // Waits (bounded) for every place agent's final health so the deposit
  // accounting is complete.
  void drain();
  // Writes metrics.json and final_field.txt; 0, or the exit code.
  int write_results();
  void end_run();

  // --- web console, recording and commands (ground_console.cpp)
  void start_console();
  [[nodiscard]] console::ConsoleInfo console_info() const;
  [[nodiscard]] ControlStatus control_status() const;
  void start_recording(const console::ConsoleInfo& info);
  void start_server();
  void close_console();  // the last frame, console_final.json, the recording
  void service();        // main thread: pending commands, frames when due
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
  console::FrameBuilder frame_builder_;  // what the console shows (also who was heard, for discovery)
  core::LockstepConductor conductor_;    // lockstep protocol (also departures, realtime)
  core::RunBook book_;                   // start gate, discovery, fields held, the end
  console::GroundIntake intake_;         // every received sample: checks, and who hears of it
  console::GroundSamples samples_;       // reusable inbox
  Clock::time_point next_progress_;

  // --- web console
  std::unique_ptr<LiveConsole> console_;
  std::unique_ptr<console::ConsoleServer> server_;
  std::unique_ptr<console::RecordingWriter> recording_;
  std::unique_ptr<console::UncertaintyTracker> uncertainty_;
  std::optional<auth::ControlKey> control_key_;
  Clock::time_point console_t0_, next_frame_, next_series_;
  std::vector<core::Rect> popup_obstacles_;
  std::vector<console::CommandLogEntry> command_log_;  // for the next frame
  uint32_t command_seq_ = 0;
  uint64_t commands_ok_ = 0, commands_refused_ = 0, frames_ = 0;
  // Refused commands and requests reach the log and the recording at most 5
  // times in 10 s; the rest are summarised ("suppressed K").
  static constexpr uint32_t kRefusalsLogged = 5;
  static constexpr double kRefusalWindowS = 10.0;
  console::RefusalLimiter refusal_log_{kRefusalsLogged, kRefusalWindowS};
  bool paused_ = false;
  bool recording_failed_ = false;
  bool ended_ = false;  // --until-done: the End went out
  bool interrupted_ = false;  // lockstep: a phase ended by a stop (SIGINT, SIGTERM), not by a timeout

  // --- MAVLink
  std::unique_ptr<MavlinkLink> mavlink_;
  std::unique_ptr<console::MavlinkFeed> mavlink_feed_;
  std::unique_ptr<mavlink::CommandGate> mavlink_gate_;
  std::optional<mavlink::SecretKey> mavlink_key_;
  uint64_t mavlink_refusals_logged_ = 0;
};

// pheromesh-ground's flags into `cfg` (ground_options.cpp); --attach-timeout
// into `attach_timeout_s`.
void add_ground_options(CLI::App& app, GroundConfig& cfg, double& attach_timeout_s);

// pheromesh-ground --attach (attach.cpp): finds the running swarm on the
// domain, takes its scenario and options, then runs a GroundApp as a monitor.
int attach(GroundConfig cfg, double timeout_s);

}  // namespace pheromesh::groundstation
