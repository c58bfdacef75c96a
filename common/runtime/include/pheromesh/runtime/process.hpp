// What every pheromesh process shares: logging setup, async-signal-safe
// shutdown, the common DDS flags and a fixed-rate tick clock.
#pragma once

#include <CLI/CLI.hpp>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/core/plausibility.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/tick_gaps.hpp"

namespace spdlog {
class logger;
}

namespace pheromesh::runtime {

// Flags common to the agent processes.
struct CommonOptions {
  std::string scenario;        // path of the scenario file
  std::string dds;             // vendor
  std::string dds_profile = "onehost";
  std::string dds_peers;  // lan profiles: discovery peers, comma-separated addresses or host names
  uint32_t domain = 0;
  std::string log_level = "info";
  // --rate, --ticks, --seed, --uavs as typed: overrides of run.tick_rate_hz,
  // run.ticks, run.seed and swarm.uavs, validated with the file exactly as
  // `pheromesh --set` is (load_scenario); unset: the scenario's.
  std::optional<std::string> rate_hz, ticks, seed, uavs;
  uint32_t lease_ms = 1000;    // liveliness lease
  std::string clock = "realtime";  // realtime | lockstep
  [[nodiscard]] bool lockstep() const { return clock == "lockstep"; }
  // The swarm runs hot-standby place agents (--standby, or the scenario's
  // run.standby): every process then uses exclusive ownership (bus/qos.hpp).
  bool standby = false;
  // With standbys: the replicas' output is shared (every reader takes every
  // replica's samples; identical in lockstep) instead of exclusively owned.
  // `pheromesh run` sets it when a Fast DDS process is in the swarm: Fast DDS
  // 2.9 does not hand an instance to the next writer when its owner's
  // liveliness is lost (measured; docs/faults.md).
  bool shared_ownership = false;
  // A place agent's replica number (0 the primary, 1.. standbys); -1 for
  // every other process. Its ownership strength is kMaxStrength - replica.
  int32_t place_replica = -1;
  // DDS Security: the directory of `pheromesh security init` (empty: none).
  // The process uses the identity named after it (uav-3, place-0, ground;
  // the monitor: "monitor").
  std::string secure;
};

// Loads the scenario with the overrides of the common flags (--rate, --ticks,
// --seed, --uavs; overrides_of) and validates the result as a file, so every
// process of a run agrees on them and a value the file may not hold is
// refused naming the flag ("--uavs 0: field 'swarm.uavs': ...").
core::Result<core::ScenarioConfig> load_scenario(const CommonOptions& o);
// The overrides the common flags ask for, in the order --rate, --ticks,
// --seed, --uavs (--standby adds run.standby=true).
core::ScenarioOverrides overrides_of(const CommonOptions& o);

// Registers the common flags on `app`, with defaults from the environment
// (PHEROMESH_DDS, PHEROMESH_DDS_PROFILE, PHEROMESH_DOMAIN) so launchers can
// set them once.
void add_common_options(CLI::App& app, CommonOptions& o);

// The run as this process runs it (core::ScenarioMsg): the scenario file's
// text and the overrides of `o` applied to `s`; an error if the file cannot be
// read again or is larger than a RunScenario sample holds.
core::Result<core::ScenarioMsg> scenario_message(const CommonOptions& o, const core::ScenarioConfig& s,
                                                 uint32_t publisher);
// The other way round, for a monitor that attached with only the domain id:
// the scenario (its overrides applied) and the options of the run into `o`
// (clock, lease, standby, shared ownership, uavs, ticks, seed, rate).
core::Result<core::ScenarioConfig> scenario_from_message(const core::ScenarioMsg& m, CommonOptions& o);

// The highest tick a sample of a realtime run can carry now
// (core::realtime_tick_ceiling), from the launch time `pheromesh run` gives
// every process ($PHEROMESH_RUN_T0_MS) and its slack (launch_slack);
// unlimited for a process started without it.
uint32_t realtime_tick_ceiling(double rate_hz);
// "1": every process of the run was launched by one `pheromesh run` on this
// host (no --hosts), so they share one launch instant of one clock
// (core::kOneHostSlack); else the launch slack of a LAN run.
inline constexpr const char* kOneHostEnv = "PHEROMESH_RUN_ONE_HOST";
core::TickSlack launch_slack();

// One named logger per component, level from the flag. It writes to
// stderr, and also to stdout when the two are different files
// (streams_differ): `pheromesh run` gives the ground station its log file
// as stdout and the launcher's terminal as stderr, and its log was empty
// (issue 42). Every other process has both on its log file: one copy.
std::shared_ptr<spdlog::logger> make_logger(const std::string& name, const std::string& level);
// Whether the open descriptors `a` and `b` are different files (not the same
// device and inode); false when either cannot be inspected.
bool streams_differ(int a, int b);

// SIGINT/SIGTERM set a flag (the handler does nothing else).
void install_shutdown_handlers();
// The longest a process sleeps without looking at that flag (TickClock, the
// lockstep waits): a shutdown request is seen within it. Every wake-up of an
// idle process is a context switch; a 1000-UAV lockstep swarm waits about
// 250 ms a tick, so 100 ms slices woke each UAV two or three times a tick
// for nothing (docs/benchmarks.md, "Views without neighbours").
inline constexpr std::chrono::milliseconds kShutdownSlice{250};
[[nodiscard]] bool shutdown_requested();
void request_shutdown();  // for tests and internal stops

// `standby`: the swarm runs hot-standby place agents (the flag or the scenario).
// The peers (--dds-peers) are resolved here: names that do not resolve are
// logged on `log` and left out; a malformed list is an error.
core::Result<bus::BusOptions> bus_options(const CommonOptions& o, const std::string& process_name, bool standby = false,
                                          spdlog::logger* log = nullptr);
// Ownership strength of place replica 0 (the primary); replica N has this - N.
inline constexpr int32_t kPrimaryStrength = 1000;

// The common body of every process's main() after flag parsing: logger named
// `name`, scenario (exit 2 if invalid), shutdown handlers, bus (exit 3 if it
// cannot be created), then `app(scenario, bus)`; an exception escaping the
// app is logged and gives exit 4.
using AppBody = std::function<int(core::ScenarioConfig, std::unique_ptr<bus::Bus>)>;
int run_process(const std::string& name, const CommonOptions& o, const AppBody& app);

// A deadline that any thread may move without waking the thread that sleeps
// on it (a Linux timerfd): a realtime UAV's receive thread runs its ticks as
// the views arrive and moves the timer of its main thread, which wakes only
// when no view came (core::ViewPacing), or at a shutdown request (SIGINT,
// SIGTERM, request_shutdown: install_shutdown_handlers' wake-up descriptor).
class WakeTimer {
 public:
  WakeTimer();  // throws std::system_error if the kernel gives no timer
  ~WakeTimer();
  WakeTimer(const WakeTimer&) = delete;
  WakeTimer& operator=(const WakeTimer&) = delete;
  void set(std::chrono::steady_clock::time_point at);
  // Sleeps until the last deadline set has passed (at once if it has), or at
  // most `slice` without a shutdown handler's descriptor to wake it. False
  // once a shutdown is requested.
  bool wait(std::chrono::milliseconds slice = kShutdownSlice);

 private:
  int fd_ = -1;
};

// Called with an app's exit code once its work is done and sent, before its
// bus is torn down (`return bound_teardown(app.run());`): if the process has
// not ended kTeardownGrace later, it logs so and exits with `code` without
// waiting further. A Fast DDS 2.9 participant's deletion has hung for a
// minute after a UAV finished (a killed peer's reader it waited for), past
// the launcher's SIGTERM, which only asks the app to stop. Returns `code`.
inline constexpr std::chrono::seconds kTeardownGrace{10};
int bound_teardown(int code, std::chrono::milliseconds grace = kTeardownGrace);

// Fixed-rate clock: wait_next() sleeps until the next tick boundary (never
// longer than one period) and returns false as soon as shutdown is requested.
class TickClock {
 public:
  explicit TickClock(double rate_hz);
  bool wait_next();
  [[nodiscard]] std::chrono::nanoseconds period() const { return period_; }
  // Ticks per second measured over the last second.
  [[nodiscard]] double measured_rate() const { return measured_rate_; }
  // Ticks whose wake-up came more than one period after their boundary: the
  // process could not keep the rate (an overloaded host).
  [[nodiscard]] uint32_t late_ticks() const { return late_ticks_; }

 private:
  std::chrono::nanoseconds period_;
  std::chrono::steady_clock::time_point next_;
  std::chrono::steady_clock::time_point window_start_;
  uint32_t window_ticks_ = 0;
  double measured_rate_ = 0.0;
  uint32_t late_ticks_ = 0;
};

// A realtime loop's tick `tick` starts now: feeds `gaps` and logs a gap over
// two periods (the first ten of them).
void note_tick_start(core::TickGaps& gaps, spdlog::logger& log, uint32_t tick);
// The loop's summary line: "<who> kept its clock: longest gap ...".
void log_clock_kept(const core::TickGaps& gaps, spdlog::logger& log, const std::string& who,
                    const std::string& extra = "");

}  // namespace pheromesh::runtime
