#include "pheromesh/runtime/process.hpp"

#include "pheromesh/core/scenario_limits.hpp"

#include <algorithm>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/sinks/stdout_sinks.h>
#include <sys/stat.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <string_view>
#include <limits>
#include <optional>
#include <sstream>
#include <thread>

#include <poll.h>
#include <sys/eventfd.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <ctime>
#include <system_error>

#include "pheromesh/cliutil/command_line.hpp"
#include "pheromesh/cliutil/scenario_paths.hpp"
#include "pheromesh/core/plausibility.hpp"

namespace pheromesh::runtime {
namespace {

std::atomic<bool> g_shutdown{false};
static_assert(std::atomic<bool>::is_always_lock_free);

// Written (an eventfd) at every shutdown request: it wakes a WakeTimer.
std::atomic<int> g_wake_fd{-1};
void wake_sleepers() {
  const int fd = g_wake_fd.load();
  if (fd < 0) return;
  const uint64_t one = 1;
  (void)!::write(fd, &one, sizeof one);  // async-signal-safe
}
extern "C" void on_signal(int /*sig*/) {
  g_shutdown.store(true);
  wake_sleepers();
}

std::string env_or(const char* name, const std::string& fallback) {
  const char* v = std::getenv(name);
  return (v != nullptr && *v != '\0') ? std::string(v) : fallback;
}

}  // namespace

void add_common_options(CLI::App& app, CommonOptions& o) {
  o.dds = bus::default_vendor();
  o.dds_profile = env_or("PHEROMESH_DDS_PROFILE", o.dds_profile);
  o.domain = static_cast<uint32_t>(std::stoul(env_or("PHEROMESH_DOMAIN", "0")));
  app.add_option("--scenario", o.scenario, cli::kScenarioArgHelp)
      ->required()
      ->transform(CLI::Validator(cli::resolve_scenario_argument, "FILE|NAME"));
  app.add_option("--dds", o.dds, "DDS vendor of this process: cyclone or fastdds [env PHEROMESH_DDS]")
      ->capture_default_str();
  app.add_option("--dds-profile", o.dds_profile,
                 "DDS profile: onehost (loopback, multicast discovery, >=100 processes), onehost-unicast (loopback, "
                 "unicast discovery, <=120 processes), cells (loopback, the peers `pheromesh run` names in $PHEROMESH_CELL), "
                 "lan (several hosts, multicast discovery), lan-unicast (several "
                 "hosts, discovery through --dds-peers), netns (one network namespace per process on a bridge, set up "
                 "by pheromesh run for network faults), default (vendor defaults) or vendor config files, "
                 "comma-separated (this process uses the one for its vendor) [env PHEROMESH_DDS_PROFILE]")
      ->capture_default_str();
  o.dds_peers = env_or("PHEROMESH_DDS_PEERS", o.dds_peers);
  app.add_option("--dds-peers", o.dds_peers,
                 "lan profiles: the hosts to announce this process to, comma-separated IPv4 addresses or host names "
                 "(a name is resolved at start to all its addresses, e.g. a Kubernetes headless Service); every "
                 "process of the swarm gets the same list [env PHEROMESH_DDS_PEERS]");
  app.add_option("--domain", o.domain, "DDS domain id [env PHEROMESH_DOMAIN]")->check(CLI::Range(0, 232))->capture_default_str();
  app.add_option("--log-level", o.log_level, "Log level: trace, debug, info, warn, error, critical or off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}))
      ->capture_default_str();
  app.add_option("--rate", o.rate_hz,
                 "Tick rate [Hz], (0, 1000] (default: the scenario's run.tick_rate_hz; stands for --set "
                 "run.tick_rate_hz=HZ, validated like the file)")
      ->type_name("HZ");
  app.add_option("--ticks", o.ticks,
                 "Ticks to run, >= 1 (default: the scenario's run.ticks; validated like the file). A UAV flies them; "
                 "a realtime place agent runs until the ground station's End or SIGTERM")
      ->type_name("N");
  app.add_option("--seed", o.seed, "Run seed (default: the scenario's run.seed; validated like the file)")
      ->type_name("N");
  o.clock = env_or("PHEROMESH_CLOCK", o.clock);
  app.add_option("--clock", o.clock,
                 "realtime: every process ticks on its own clock; lockstep: the ground station conducts numbered "
                 "ticks (UAV phase, then place phase) [env PHEROMESH_CLOCK]")
      ->check(CLI::IsMember({"realtime", "lockstep"}))
      ->capture_default_str();
  app.add_option("--uavs", o.uavs,
                 "Number of UAVs in the swarm, 1..5000 (default: the scenario's swarm.uavs; validated like the file: "
                 "the start area must hold them)")
      ->type_name("N");
  app.add_option("--lease-ms", o.lease_ms, "Liveliness lease [ms]")->check(CLI::Range(50, 60000))->capture_default_str();
  app.add_flag("--standby", o.standby,
               "The swarm runs a hot-standby replica of every place agent (every process of it needs this flag, or "
               "the scenario's run.standby: true): exclusive ownership of place-agent output");
  o.secure = env_or("PHEROMESH_SECURE", o.secure);
  app.add_option("--secure", o.secure,
                 "DDS Security: the directory made by `pheromesh security init`; this process authenticates with "
                 "its own identity there (uav-N, place-R, ground), and its permissions, the governance's "
                 "encryption and access control apply (docs/security.md) [env PHEROMESH_SECURE]");
  app.add_flag("--shared-ownership", o.shared_ownership,
               "With standbys: readers take every replica's output (shared ownership) instead of the owner's only; "
               "pheromesh run sets it for swarms with Fast DDS processes (docs/faults.md)");
  cli::add_version_flag(app);
}

core::Result<core::ScenarioMsg> scenario_message(const CommonOptions& o, const core::ScenarioConfig& s,
                                                 uint32_t publisher) {
  std::ifstream in(o.scenario, std::ios::binary);
  if (!in) return core::Error{"cannot read " + o.scenario + " again to publish it"};
  std::ostringstream text;
  text << in.rdbuf();
  core::ScenarioMsg m;
  m.publisher = publisher;
  m.text = text.str();
  if (m.text.size() > core::kMaxScenarioBytes) {
    return core::Error{o.scenario + " has " + std::to_string(m.text.size()) +
                       " bytes; a published scenario holds at most " + std::to_string(core::kMaxScenarioBytes) +
                       " (monitors that attach later need --scenario)"};
  }
  m.uavs = s.uavs;
  m.ticks = s.ticks;
  m.seed = s.seed;
  m.tick_rate_hz = s.tick_rate_hz;
  m.clock = o.lockstep() ? 1 : 0;
  m.lease_ms = o.lease_ms;
  m.standby = o.standby || s.standby;
  m.shared_ownership = o.shared_ownership;
  return m;
}

core::Result<core::ScenarioConfig> scenario_from_message(const core::ScenarioMsg& m, CommonOptions& o) {
  auto s = core::parse_scenario(
      m.text, "the scenario published by place agent " + std::to_string(core::place_id_region(m.publisher)) +
                  (core::place_id_replica(m.publisher) > 0 ? ".r" + std::to_string(core::place_id_replica(m.publisher))
                                                           : std::string()));
  if (!s) return s;
  if (m.uavs > 0) s->uavs = m.uavs;
  if (m.ticks > 0) s->ticks = m.ticks;
  if (m.seed > 0) s->seed = m.seed;
  if (m.tick_rate_hz > 0) s->tick_rate_hz = m.tick_rate_hz;
  o.clock = m.clock == 1 ? "lockstep" : "realtime";
  if (m.lease_ms >= 50 && m.lease_ms <= 60000) o.lease_ms = m.lease_ms;
  o.standby = m.standby;
  o.shared_ownership = m.shared_ownership;
  return s;
}

bool streams_differ(int a, int b) {
  struct stat sa {};
  struct stat sb {};
  if (fstat(a, &sa) != 0 || fstat(b, &sb) != 0) return false;
  return sa.st_dev != sb.st_dev || sa.st_ino != sb.st_ino;
}

std::shared_ptr<spdlog::logger> make_logger(const std::string& name, const std::string& level) {
  std::vector<spdlog::sink_ptr> sinks{std::make_shared<spdlog::sinks::stderr_color_sink_mt>()};
  const bool both = streams_differ(STDOUT_FILENO, STDERR_FILENO);
  if (both) sinks.push_back(std::make_shared<spdlog::sinks::stdout_sink_mt>());
  auto logger = std::make_shared<spdlog::logger>(name, sinks.begin(), sinks.end());
  spdlog::register_logger(logger);
  // stdout is buffered: each line reaches the log file at once, so that a
  // process that dies leaves its last lines there.
  if (both) logger->flush_on(spdlog::level::trace);
  logger->set_level(spdlog::level::from_str(level));
  logger->set_pattern("%H:%M:%S.%e %^%-5l%$ [%n] %v");
  spdlog::set_default_logger(logger);
  return logger;
}

core::TickSlack launch_slack() {
  const char* v = std::getenv(kOneHostEnv);
  return v != nullptr && std::string_view(v) == "1" ? core::kOneHostSlack : core::kLaunchSlack;
}

uint32_t realtime_tick_ceiling(double rate_hz) {
  static const std::optional<int64_t> t0 = []() -> std::optional<int64_t> {
    const char* v = std::getenv("PHEROMESH_RUN_T0_MS");
    if (v == nullptr) return std::nullopt;
    char* end = nullptr;
    const long long ms = std::strtoll(v, &end, 10);
    if (end == v || *end != '\0' || ms <= 0) return std::nullopt;
    return ms;
  }();
  if (!t0) return std::numeric_limits<uint32_t>::max();
  static const core::TickSlack slack = launch_slack();
  const int64_t now =
      std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
  return core::realtime_tick_ceiling(static_cast<double>(now - *t0) / 1000.0, rate_hz, slack);
}

void install_shutdown_handlers() {
  if (g_wake_fd.load() < 0) g_wake_fd.store(::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC));
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

bool shutdown_requested() { return g_shutdown.load(); }
void request_shutdown() {
  g_shutdown.store(true);
  wake_sleepers();
}

// Non-blocking: another thread may move the deadline between poll and read
// (the read then finds nothing, and the caller looks again).
WakeTimer::WakeTimer() : fd_(::timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC | TFD_NONBLOCK)) {
  if (fd_ < 0) throw std::system_error(errno, std::generic_category(), "timerfd_create");
}

WakeTimer::~WakeTimer() { ::close(fd_); }

void WakeTimer::set(std::chrono::steady_clock::time_point at) {
  // steady_clock is CLOCK_MONOTONIC (libstdc++ on Linux); 0 would disarm.
  const auto ns =
      std::max<int64_t>(1, std::chrono::duration_cast<std::chrono::nanoseconds>(at.time_since_epoch()).count());
  itimerspec spec{};
  spec.it_value.tv_sec = static_cast<time_t>(ns / 1'000'000'000);
  spec.it_value.tv_nsec = static_cast<long>(ns % 1'000'000'000);
  (void)::timerfd_settime(fd_, TFD_TIMER_ABSTIME, &spec, nullptr);
}

bool WakeTimer::wait(std::chrono::milliseconds slice) {
  const int wake = g_wake_fd.load();
  std::array<pollfd, 2> fds{pollfd{fd_, POLLIN, 0}, pollfd{wake, POLLIN, 0}};
  while (!shutdown_requested()) {
    const int n = ::poll(fds.data(), wake >= 0 ? 2 : 1, wake >= 0 ? -1 : static_cast<int>(slice.count()));
    if (n > 0 && (fds[0].revents & POLLIN) != 0) {
      uint64_t expirations = 0;
      (void)!::read(fd_, &expirations, sizeof expirations);
      return !shutdown_requested();
    }
    if (n == 0) return !shutdown_requested();  // the slice, without a wake-up descriptor
  }
  return false;
}

core::ScenarioOverrides overrides_of(const CommonOptions& o) {
  core::ScenarioOverrides out;
  const std::pair<const std::optional<std::string>*, std::pair<const char*, const char*>> flags[] = {
      {&o.rate_hz, {"run.tick_rate_hz", "--rate"}},
      {&o.ticks, {"run.ticks", "--ticks"}},
      {&o.seed, {"run.seed", "--seed"}},
      {&o.uavs, {"swarm.uavs", "--uavs"}},
  };
  for (const auto& [value, field] : flags) {
    if (*value) out.push_back({field.first, **value, std::string(field.second) + " " + **value});
  }
  if (o.standby) out.push_back({"run.standby", "true", "--standby"});
  return out;
}

core::Result<core::ScenarioConfig> load_scenario(const CommonOptions& o) {
  // The same checks as the file's, limits included: a value the file may not
  // hold is refused on the command line too.
  return core::load_scenario(o.scenario, overrides_of(o));
}

core::Result<bus::BusOptions> bus_options(const CommonOptions& o, const std::string& process_name, bool standby,
                                          spdlog::logger* log) {
  bus::BusOptions b;
  if (!o.dds_peers.empty()) {
    auto peers = bus::resolve_peers(o.dds_peers);
    if (!peers) return peers.error();
    if (log != nullptr && !peers->unresolved.empty()) {
      std::string names;
      for (const auto& n : peers->unresolved) names += (names.empty() ? "" : ", ") + n;
      log->warn("DDS peers {} do not resolve (yet): left out; processes there find this one when they start", names);
    }
    if (log != nullptr) {
      std::string list;
      for (const auto& a : peers->addresses) list += (list.empty() ? "" : ", ") + a;
      log->debug("DDS peers: {}", list.empty() ? "none resolved" : list);
    }
    b.peers = std::move(peers->addresses);
  }
  b.replication.exclusive = (standby || o.standby) && !o.shared_ownership;
  if (b.replication.exclusive && o.place_replica >= 0) {
    b.replication.strength = std::max(1, kPrimaryStrength - o.place_replica);
  }
  b.pacing = o.lockstep() ? bus::Pacing::Lockstep : bus::Pacing::Realtime;
  b.process_name = process_name;
  b.domain = o.domain;
  b.profile = o.dds_profile;
  b.liveliness_lease = std::chrono::milliseconds(o.lease_ms);
  b.secure_dir = o.secure;
  // Given by `pheromesh run` to each process it spawns (Fast DDS ports).
  if (const char* id = std::getenv("PHEROMESH_PARTICIPANT_ID"); id != nullptr && *id != '\0') {
    char* end = nullptr;
    const long v = std::strtol(id, &end, 10);
    if (end != id && *end == '\0' && v >= 0 && v < 30000) b.participant_id = static_cast<int32_t>(v);
  }
  // Given by `pheromesh run` too: how many processes its host starts.
  if (const char* n = std::getenv(bus::kSwarmProcessesEnv); n != nullptr && *n != '\0') {
    char* end = nullptr;
    const unsigned long v = std::strtoul(n, &end, 10);
    if (end != n && *end == '\0' && v <= 1000000) b.swarm_processes = static_cast<uint32_t>(v);
  }
  // Cell discovery (docs/dds.md, "Cell discovery"): `pheromesh run
  // --dds-profile cells` names each process's peers.
  const char* cell = std::getenv(bus::kCellEnv);
  if (cell != nullptr && *cell != '\0') {
    auto parsed = bus::parse_cell(cell, o.domain);
    if (!parsed) return parsed.error();
    b.cell = std::move(parsed).value();
    // A Fast DDS member takes the first free index otherwise, and can bind
    // a hub's port beside it: it would then hear what is meant for the hub.
    if (!b.cell->index && b.participant_id < 0 && o.dds == "fastdds") {
      return core::Error{std::string("$") + bus::kCellEnv +
                         ": a Fast DDS process in a cell needs its own participant id past the hubs' "
                         "($PHEROMESH_PARTICIPANT_ID; `pheromesh run --dds-profile cells` gives every process one)"};
    }
  } else if (o.dds_profile == "cells") {
    return core::Error{std::string("--dds-profile cells: this process has no cell ($") + bus::kCellEnv +
                       "); `pheromesh run --dds-profile cells` gives every process it starts one"};
  }
  return b;
}

int run_process(const std::string& name, const CommonOptions& o, const AppBody& app) {
  auto log = make_logger(name, o.log_level);
  auto scenario = load_scenario(o);
  if (!scenario) {
    log->error("invalid scenario:\n{}", scenario.error().message);
    return 2;
  }
  install_shutdown_handlers();
  auto options = bus_options(o, name, scenario->standby, log.get());
  if (!options) {
    log->error("{}", options.error().message);
    return 3;
  }
  auto bus = bus::make_bus(o.dds, options.value());
  if (!bus) {
    log->error("{}", bus.error().message);
    return 3;
  }
  try {
    return app(std::move(scenario).value(), std::move(bus).value());
  } catch (const std::exception& e) {
    log->critical("fatal: {}", e.what());
    return 4;
  }
}

int bound_teardown(int code, std::chrono::milliseconds grace) {
  // Written with write(2), not the logger: when it fires, exit() may be
  // destroying the logger (static destructors can hang the same way).
  const auto logger = spdlog::default_logger();
  const std::string name = logger ? logger->name() : std::string("pheromesh");
  std::thread([code, name, grace] {
    std::this_thread::sleep_for(grace);
    const std::time_t now = std::time(nullptr);
    std::tm local{};
    localtime_r(&now, &local);
    char line[256];
    const int n = std::snprintf(line, sizeof line,
                                "%02d:%02d:%02d warn  [%s] the DDS teardown has not ended %.1f s after the work was "
                                "done and sent: exiting without it\n",
                                local.tm_hour, local.tm_min, local.tm_sec, name.c_str(),
                                std::chrono::duration<double>(grace).count());
    if (n > 0) (void)!::write(STDERR_FILENO, line, std::min<std::size_t>(static_cast<std::size_t>(n), sizeof line - 1));
    _exit(code);  // no atexit handlers: they may wait for the same teardown
  }).detach();
  return code;
}

namespace {
// One nanosleep, not retried when a signal interrupts it (std::this_thread::
// sleep_for sleeps on after the handler): the caller looks at the shutdown
// flag the handler set.
void sleep_slice(std::chrono::nanoseconds d) {
  timespec ts{static_cast<time_t>(d.count() / 1'000'000'000), static_cast<long>(d.count() % 1'000'000'000)};
  (void)nanosleep(&ts, nullptr);
}
}  // namespace

TickClock::TickClock(double rate_hz)
    : period_(std::chrono::nanoseconds(static_cast<int64_t>(1e9 / rate_hz))),
      next_(std::chrono::steady_clock::now()),
      window_start_(next_) {}

bool TickClock::wait_next() {
  next_ += period_;
  auto now = std::chrono::steady_clock::now();
  if (next_ < now - period_) {
    // More than a period behind this tick's boundary: late. Do not burst to
    // catch up; the schedule restarts from now.
    ++late_ticks_;
    next_ = now;
  }
  // Sleep in slices so a shutdown request is seen within kShutdownSlice (a signal
  // to this thread ends the slice at once). At 5 Hz that is one sleep per
  // tick: 50 ms slices were four, and each wake-up a context switch of
  // every UAV (measured: 4.0 voluntary switches per UAV tick, 1.0 after;
  // docs/benchmarks.md, "Where a UAV tick goes").
  while (!shutdown_requested() && now < next_) {
    sleep_slice(std::min<std::chrono::nanoseconds>(next_ - now, kShutdownSlice));
    now = std::chrono::steady_clock::now();
  }
  ++window_ticks_;
  if (now - window_start_ >= std::chrono::seconds(1)) {
    measured_rate_ = window_ticks_ / std::chrono::duration<double>(now - window_start_).count();
    window_start_ = now;
    window_ticks_ = 0;
  }
  return !shutdown_requested();
}

void note_tick_start(core::TickGaps& gaps, spdlog::logger& log, uint32_t tick) {
  const auto gap = gaps.on_tick_start(std::chrono::steady_clock::now());
  if (!gap || gaps.gaps_over_2() > 10) return;
  log.warn("tick {} started {} ms after the one before ({:.1f} tick periods)", tick,
           std::chrono::duration_cast<std::chrono::milliseconds>(*gap).count(),
           static_cast<double>(gap->count()) / static_cast<double>(gaps.period().count()));
}

void log_clock_kept(const core::TickGaps& gaps, spdlog::logger& log, const std::string& who, const std::string& extra) {
  log.info("{} kept its clock: longest gap between tick starts {} ms ({:.2f} periods), {} gaps over 2 periods{}", who,
           gaps.max_gap_ms(), gaps.max_gap_periods(), gaps.gaps_over_2(), extra);
}

}  // namespace pheromesh::runtime
