#include "supervisor.hpp"

#include <fcntl.h>
#include <sched.h>
#include <spdlog/spdlog.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <stdexcept>
#include <thread>

#include "child_spawn.hpp"
#include "hub_gate.hpp"
#include "pheromesh/auth/control.hpp"
#include "pheromesh/console/server.hpp"
#include "pheromesh/runtime/process.hpp"

namespace pheromesh::cli {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// --discovery-server listens on this port + the domain id.
constexpr int kDiscoveryServerPort = 11811;

double seconds(const timeval& tv) { return static_cast<double>(tv.tv_sec) + static_cast<double>(tv.tv_usec) / 1e6; }

// The last line of a process's log at level critical (spdlog's pattern of
// runtime::make_logger: "HH:MM:SS.mmm critical [name] ..."), without its
// time stamp; nothing when there is none.
std::optional<std::string> last_critical_line(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) return std::nullopt;
  std::optional<std::string> last;
  std::string line;
  int ch = 0;
  while ((ch = std::fgetc(f)) != EOF) {
    if (ch != '\n') {
      line.push_back(static_cast<char>(ch));
      continue;
    }
    if (const auto at = line.find("critical"); at != std::string::npos) {
      // Colour codes around the level are in the file too; keep what
      // follows the logger's name.
      const auto name = line.find("] ", at);
      last = line.substr(name == std::string::npos ? at : name + 2);
    }
    line.clear();
  }
  std::fclose(f);
  return last;
}

int64_t unix_ms_now() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// EAGAIN: the process or thread limit is reached for now (a big swarm's
// start); give exiting processes a moment.
pid_t fork_patiently() {
  pid_t pid = fork();
  for (int attempt = 0; pid < 0 && errno == EAGAIN && attempt < 5; ++attempt) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    pid = fork();
  }
  if (pid < 0) throw std::runtime_error(std::string("fork failed: ") + std::strerror(errno));
  return pid;
}

// In the forked child: own process group (the launcher orders the shutdown;
// a hub in a realtime swarm also leads a session of its own: Scheduling),
// die with the launcher, output to its log file (the ground station's errors
// also to ours), then the planned program.
[[noreturn]] void exec_child(PlannedProcess& p, pid_t parent, int netns_fd, int ctl_fd) {
  enter_process_group(p.scheduling);
  prctl(PR_SET_PDEATHSIG, SIGTERM);
  for (auto& e : p.env) putenv(e.data());  // single-threaded launcher: safe after fork
  if (getppid() != parent) _exit(127);
  if (netns_fd >= 0 && setns(netns_fd, CLONE_NEWNET) != 0) {
    dprintf(STDERR_FILENO, "cannot enter the network namespace of %s: %s\n", p.name.c_str(), std::strerror(errno));
    _exit(126);
  }
  if (p.control == ControlLine::Fd3 && ctl_fd >= 0) {
    // The console's control socket, as fd 3 (dup2 clears close-on-exec).
    if (ctl_fd == 3) {
      fcntl(3, F_SETFD, 0);
    } else {
      dup2(ctl_fd, 3);
    }
  }
  // A process started again (restart) appends to its earlier lives' log:
  // what the killed life wrote is kept, after a line that marks the new one.
  const bool again = p.life > 0;
  const int fd = open(p.log_path.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC | (again ? O_APPEND : O_TRUNC), 0644);
  if (fd >= 0) {
    if (again) dprintf(fd, "=== pheromesh run: %s started again (life %u, pid %d) ===\n", p.name.c_str(), p.life + 1, getpid());
    dup2(fd, STDOUT_FILENO);
    if (p.stderr_to == StderrTo::Log) dup2(fd, STDERR_FILENO);
  }
  // Nothing else of the launcher's: fd 3 is the control socket when planned.
  close_descriptors_from(p.control == ControlLine::Fd3 && ctl_fd >= 0 ? 4 : 3);
  std::vector<char*> argv;
  for (auto& a : p.argv) argv.push_back(a.data());
  argv.push_back(nullptr);
  execv(p.executable().c_str(), argv.data());
  dprintf(STDERR_FILENO, "cannot execute %s: %s\n", p.executable().c_str(), std::strerror(errno));
  _exit(127);
}

// The UAVs the resource sample looks at, and whose threads the steady
// window reads, at most: spread evenly over the running ones.
constexpr std::size_t kSampledUavs = 200;

// Per child, whether a pass looks at it closely: every running place agent
// and ground station, and at most kSampledUavs of the running UAVs.
std::vector<bool> looked_at_closely(const std::vector<ChildProcess>& children) {
  const auto uavs = static_cast<std::size_t>(
      std::count_if(children.begin(), children.end(), [](const auto& c) { return c.role == "uav" && c.running; }));
  std::vector<bool> closely(children.size(), false);
  std::size_t uav_index = 0;
  for (std::size_t i = 0; i < children.size(); ++i) {
    const auto& c = children[i];
    if (c.running) closely[i] = c.role != "uav" || evenly_taken(uav_index++, uavs, kSampledUavs);
  }
  return closely;
}

}  // namespace

Supervisor::Supervisor(RunPlan plan) : plan_(std::move(plan)) {
  if (plan_.faults) faults_.emplace(*plan_.faults);
}

// Out of line: the namespaces go (NetnsSwarm's destructor) whenever the
// supervisor does, also when the run ends by an exception.
Supervisor::~Supervisor() = default;

// --- starting -----------------------------------------------------------------

bool Supervisor::start() {
  // Every process of this swarm shares a fresh control key: only this
  // ground station can sign commands they act on (docs/console.md). Over
  // several hosts every host has the same one, from the environment
  // (check_multi_host).
  if (!plan_.multi_host()) setenv(auth::kControlKeyEnv, auth::random_control_key_hex().c_str(), 1);
  // The launch instant: wall_s and the ground station's discovery_s count from
  // here (children inherit PHEROMESH_RUN_T0_MS).
  // With network faults every process counts its own datagrams in its own
  // namespace: exactly this swarm's.
  udp_start_ = netns_ ? netns_->udp_counters() : read_udp_counters();
  spawn_t0_ = Clock::now();
  run_t0_unix_ms_ = unix_ms_now();
  setenv("PHEROMESH_RUN_T0_MS", std::to_string(run_t0_unix_ms_).c_str(), 1);
  // One host: every process's launch is this instant of this clock, so a
  // sample's tick is bounded within seconds, not the half minute of a LAN
  // run's launchers (core::kOneHostSlack).
  if (plan_.multi_host()) {
    unsetenv(runtime::kOneHostEnv);
  } else {
    setenv(runtime::kOneHostEnv, "1", 1);
  }
  if (ground_here() && plan_.processes.front().control == ControlLine::Fd3) open_control_line();
  std::string token;
  if (plan_.options.http_port) token = console::random_token();
  if (plan_.options.discovery_server && !start_discovery_server()) return false;
  if (ground_here()) {
    PlannedProcess ground = plan_.processes.front();
    if (!token.empty()) ground.env.push_back("PHEROMESH_CONSOLE_TOKEN=" + token);
    spawn(std::move(ground));
  }
  if (child_ctl_fd_ >= 0) {
    close(child_ctl_fd_);
    child_ctl_fd_ = -1;
  }
  log_console_url(token);
  spawn_swarm();  // if interrupted, fly() stops what was started
  t0_ = Clock::now();
  return true;
}

void Supervisor::open_control_line() {
  int sv[2];
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0) {
    throw std::runtime_error(std::string("socketpair: ") + std::strerror(errno));
  }
  ctl_fd_ = sv[0];
  child_ctl_fd_ = sv[1];
}

void Supervisor::log_console_url(const std::string& token) const {
  const RunOptions& o = plan_.options;
  if (o.http_port && *o.http_port != 0) {
    const std::string host = o.http_bind == "0.0.0.0" ? "127.0.0.1" : o.http_bind;
    spdlog::info("web console: http://{}:{}/?token={}", host, *o.http_port, token);
  } else if (o.http_port) {
    spdlog::info("web console: the ground station prints its URL (port chosen by the system)");
  }
}

void Supervisor::wait_spawn_gap() {
  if (plan_.spawn_gap.count() == 0) return;
  const auto until = last_spawn_ + plan_.spawn_gap;
  while (Clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    reap();
  }
  last_spawn_ = Clock::now();
}

uint32_t Supervisor::participant_for(const std::string& name) const {
  // A restarted process gets its old id (its ports are free).
  const auto known = participant_of_.find(name);
  return known != participant_of_.end() ? known->second : static_cast<uint32_t>(participant_of_.size());
}

void Supervisor::spawn(PlannedProcess p) {
  wait_spawn_gap();
  participant_of_[p.name] = p.participant_id;
  // Network faults: the process runs in its own network namespace.
  int netns_fd = -1;
  if (netns_) {
    if (auto err = netns_->add(p.name))
      throw std::runtime_error("cannot give " + p.name + " a network namespace: " + *err);
    netns_fd = netns_->fd_of(p.name);
  }
  p.life = static_cast<uint32_t>(
      std::count_if(children_.begin(), children_.end(), [&](const ChildProcess& c) { return c.name == p.name; }));
  if (p.life > 0 && p.role == "place") {
    p.argv.push_back("--life");
    p.argv.push_back(std::to_string(p.life + 1));
  }
  const pid_t parent = getpid();
  const StopSignalsHeld held;  // a stop sent while it forks is never lost in the child
  const pid_t pid = fork_patiently();
  if (pid == 0) {
    held.release_in_child();
    exec_child(p, parent, netns_fd, child_ctl_fd_);
  }
  ChildProcess c;
  c.name = p.name;
  c.role = p.role;
  c.dds = p.dds;
  c.index = p.index;
  c.replica = p.replica;
  c.pid = pid;
  c.running = true;
  unreaped_[pid] = children_.size();
  children_.push_back(std::move(c));
  if (p.role == "place") top_replica_[p.index] = std::max(top_replica_[p.index], p.replica);
}

void Supervisor::spawn_place(uint32_t region, uint32_t replica) {
  spawn(plan_.place(region, replica, participant_for(process_name("place", region, replica))));
}

bool Supervisor::spawn_swarm() {
  for (const auto& p : plan_.processes) {
    if (p.role == "place") spawn(p);
  }
  if (!await_hubs()) return false;
  if (plan_.stagger) {
    spdlog::info("{} processes: starting the uavs {} at a time, {} ms apart ({:.0f} per second, --start-rate)",
                 1 + plan_.regions + plan_.uavs, plan_.stagger->batch, plan_.stagger->pause.count(),
                 plan_.options.start_rate);
  }
  auto next =
      std::find_if(plan_.processes.begin(), plan_.processes.end(), [](const auto& p) { return p.role == "uav"; });
  // Every UAV index counts for the batches, also those of other hosts.
  for (uint32_t u = 0; u < plan_.uavs; ++u) {
    if (plan_.stagger && u % plan_.stagger->batch == 0 && !pause_before_batch(u)) return false;
    if (next != plan_.processes.end() && next->index == u) spawn(*next++);
  }
  return true;
}

bool Supervisor::await_hubs() {
  const bool uavs_here =
      std::any_of(plan_.processes.begin(), plan_.processes.end(), [](const auto& p) { return p.role == "uav"; });
  if (!plan_.cells || !uavs_here) return true;
  std::vector<AwaitedHub> hubs;
  for (const auto& c : children_) {
    if (!c.running || (c.role != "ground" && c.role != "place")) continue;
    const uint32_t index = plan_.cells->hub(c.role, c.index, c.replica).index;
    hubs.push_back(
        {c.name, c.pid, static_cast<uint16_t>(bus::unicast_discovery_port(plan_.cells->shape().domain, index))});
  }
  // Generous: a hub of a big swarm on a loaded host may take seconds, and a
  // member that goes before it is only heard at its next announcement (5 s).
  constexpr auto kBound = std::chrono::seconds(20);
  const auto t0 = Clock::now();
  HubGate gate(std::move(hubs), t0, kBound);
  for (;;) {
    const auto verdict = gate.look(Clock::now(), HubGate::ports_once_per_namespace());
    const double waited = std::chrono::duration<double>(Clock::now() - t0).count();
    if (verdict == HubGate::Verdict::Open) {
      spdlog::info("{} hubs listening after {:.2f} s: starting the uavs", gate.hubs() - gate.gone().size(), waited);
      return true;
    }
    if (verdict == HubGate::Verdict::GaveUp) {
      std::string names;
      for (const auto& h : gate.waiting()) names += (names.empty() ? "" : ", ") + h.name;
      spdlog::warn(
          "{} of {} hubs not listening after {:.0f} s ({}): starting the uavs anyway; they are heard at "
          "their next announcement",
          gate.waiting().size(), gate.hubs(), waited, names);
      return true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    reap();
    if (runtime::shutdown_requested()) {
      spdlog::warn("interrupted while the hubs start, before any uav");
      return false;
    }
  }
}

bool Supervisor::pause_before_batch(uint32_t uav) {
  // The pause before the first batch gives the place agents a head start.
  const auto until = Clock::now() + plan_.stagger->pause;
  while (Clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    reap();
  }
  if (runtime::shutdown_requested()) {
    spdlog::warn("interrupted after starting {} of {} uavs", uav, plan_.uavs);
    return false;
  }
  return true;
}

core::Result<pid_t> Supervisor::respawn(const std::string& name) {
  const ChildProcess* c = find(name);
  if (c == nullptr) return core::Error{"there is no " + name};
  if (c->running) return core::Error{name + " is running; kill it first"};
  const std::string role = c->role;
  const uint32_t index = c->index, replica = c->replica;
  if (role == "uav") {
    const int64_t remaining = uav_ticks_left();
    if (remaining < 1) return core::Error{"the run is over for " + name};
    const uint32_t life = ++lives_[index];
    // Deposits of each life are numbered above the earlier lives' (place
    // agents drop sequence numbers they have seen).
    spawn(plan_.restarted_uav(index, static_cast<uint32_t>(remaining), life << 24U, participant_for(name)));
    spdlog::info("{} started again for its remaining {} ticks", name, remaining);
  } else if (role == "place") {
    spawn_place(index, replica);
  } else {
    return core::Error{"cannot restart the " + name};
  }
  return find(name)->pid;
}

int64_t Supervisor::uav_ticks_left() const {
  // A lockstep run knows its tick from the conductor's last `faults K`;
  // a realtime one counts the ticks flown by the wall clock.
  if (plan_.lockstep() && last_fault_tick_) {
    return static_cast<int64_t>(plan_.ticks) - static_cast<int64_t>(*last_fault_tick_);
  }
  const auto flown = std::chrono::duration<double>(Clock::now() - t0_ - paused_total_).count();
  return static_cast<int64_t>(plan_.ticks) - static_cast<int64_t>(flown * plan_.rate_hz);
}

bool Supervisor::start_discovery_server() {
  // Fast DDS's discovery server: every Fast DDS process discovers through it
  // instead of with every other process (its clients take the server's
  // address from ROS_DISCOVERY_SERVER). Cyclone processes cannot use it.
  for (const char* role : {"ground", "place", "uav"}) {
    if (plan_.dds.vendor_of(role, 0) != "fastdds" || plan_.dds.vendor_of(role, 1) != "fastdds") {
      spdlog::error("--discovery-server needs every process on Fast DDS (--dds fastdds); {} processes are not", role);
      return false;
    }
  }
  const std::string port = std::to_string(kDiscoveryServerPort + static_cast<int>(plan_.options.domain));
  const std::string log_path = (fs::path(plan_.options.out_dir) / "logs" / "discovery-server.log").string();
  const StopSignalsHeld held;  // a stop sent while it forks reaches the server, not a copy of the launcher
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(std::string("fork failed: ") + std::strerror(errno));
  if (pid == 0) {
    held.release_in_child();
    setpgid(0, 0);
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    const int fd = open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd >= 0) {
      dup2(fd, STDOUT_FILENO);
      dup2(fd, STDERR_FILENO);
    }
    close_descriptors_from(3);
    execlp("fast-discovery-server", "fast-discovery-server", "-i", "0", "-l", "127.0.0.1", "-p", port.c_str(),
           static_cast<char*>(nullptr));
    dprintf(STDERR_FILENO, "cannot execute fast-discovery-server: %s\n", std::strerror(errno));
    _exit(127);
  }
  discovery_server_pid_ = pid;
  setenv("ROS_DISCOVERY_SERVER", ("127.0.0.1:" + port).c_str(), 1);
  spdlog::info("Fast DDS discovery server on 127.0.0.1:{} (pid {}); its log: {}", port, pid, log_path);
  return true;
}

void Supervisor::stop_discovery_server() {
  if (discovery_server_pid_ <= 0) return;
  kill(discovery_server_pid_, SIGTERM);
  // reap() may already have collected it (wait4(-1)); then this fails at once.
  for (int i = 0; i < 100 && waitpid(discovery_server_pid_, nullptr, WNOHANG) == 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  kill(discovery_server_pid_, SIGKILL);
  waitpid(discovery_server_pid_, nullptr, WNOHANG);
  discovery_server_pid_ = -1;
}

// --- reaping and stopping -----------------------------------------------------

void Supervisor::reap() {
  // One wait4(-1) per child that has ended rather than one per running child:
  // polled every 10 ms, a thousand children would otherwise cost 100 000
  // system calls a second. Every child of the launcher is in children_ (the
  // only other fork, std::system in clean_fastdds_shm, comes after the last
  // reap and waits for its own child).
  for (;;) {
    int status = 0;
    rusage ru{};
    const pid_t r = wait4(-1, &status, WNOHANG, &ru);
    if (r <= 0) break;  // 0: none has ended; -1 (ECHILD): no children left
    record_exit(r, status, ru);
  }
}

void Supervisor::record_exit(pid_t pid, int status, const rusage& ru) {
  const auto it = unreaped_.find(pid);
  if (it == unreaped_.end()) return;
  ChildProcess& c = children_[it->second];
  unreaped_.erase(it);
  c.running = false;
  c.stopped = false;
  c.reaped = true;
  c.cpu_user_s = seconds(ru.ru_utime);
  c.cpu_sys_s = seconds(ru.ru_stime);
  c.max_rss_mib = static_cast<double>(ru.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
  if (WIFEXITED(status)) c.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) c.term_signal = WTERMSIG(status);
  if (faults_ && faults_->schedule().in_ticks()) gone_since_answer_.push_back(c.name);
  if (c.crashed()) {
    const std::string log = (fs::path(plan_.options.out_dir) / "logs" / (c.name + ".log")).string();
    spdlog::error("{} (pid {}) {} — see {}", c.name, c.pid, c.describe(), log);
    // What it said last as it stopped (run_process logs an escaped exception
    // as critical: "fatal: ..."), so that the run's output carries the reason.
    if (const auto last = last_critical_line(log)) spdlog::error("{}: {}", c.name, *last);
    if (!first_failure_) first_failure_ = failure_line(c, log);
  } else if (c.killed_on_purpose || c.killed_at_stop()) {
    spdlog::info("{} (pid {}) {}", c.name, c.pid, c.describe());
  }
}

void Supervisor::kill_and_reap(ChildProcess& c) {
  c.killed_on_purpose = true;
  kill(c.pid, SIGKILL);
  const pid_t pid = c.pid;
  int status = 0;
  rusage ru{};
  pid_t r = -1;
  while ((r = wait4(pid, &status, 0, &ru)) < 0 && errno == EINTR) {
  }
  if (r == pid) record_exit(pid, status, ru);
}

void Supervisor::stop_role(const StopStep& step) {
  for (auto& c : children_) {
    if (c.role == step.role && c.running) {
      c.asked_to_stop = true;
      kill(c.pid, SIGTERM);
    }
  }
  const auto deadline = Clock::now() + step.grace;
  while (any_running(step.role) && Clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    reap();
  }
  for (auto& c : children_) {
    if (c.role == step.role && c.running) {
      spdlog::error("{} did not stop within {} s of SIGTERM; sending SIGKILL", c.name, step.grace.count());
      c.killed_after_sigterm_s = static_cast<int>(std::max<int64_t>(1, step.grace.count()));
      kill(c.pid, SIGKILL);
    }
  }
  while (any_running(step.role)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    reap();
  }
}

void Supervisor::stop_early() {
  for (const auto& step : plan_.stop_early) stop_role(step);
}

bool Supervisor::any_running(const std::string& role) const {
  return std::any_of(children_.begin(), children_.end(), [&](const auto& c) { return c.role == role && c.running; });
}

bool Supervisor::ended_by_itself(const std::string& role) const {
  return std::any_of(children_.begin(), children_.end(), [&](const auto& c) {
    return c.role == role && !c.running && !c.killed_on_purpose && !c.asked_to_stop;
  });
}

bool Supervisor::flying() const {
  // Over several hosts this host's place agents and ground station end by
  // themselves, on the ground station's End, after every UAV of the swarm.
  return any_running("uav") || (plan_.multi_host() && (any_running("place") || any_running("ground")));
}

ChildProcess* Supervisor::find(const std::string& name) {
  // A restarted UAV has several entries: the running one, else the latest.
  ChildProcess* latest = nullptr;
  for (auto& c : children_) {
    if (c.name != name) continue;
    if (c.running) return &c;
    latest = &c;
  }
  return latest;
}

void Supervisor::sample_resources() {
  // Once per run, mid-flight: smaps_rollup (Rss and Pss: shared pages such as
  // the DDS libraries counted once per sharer) and the thread count of every
  // place agent and ground station still running, and of at most
  // kSampledUavs UAVs spread evenly over them (metrics.json gives means per
  // role and how many were sampled). A process that ended meanwhile is
  // simply left out. On a host a swarm keeps busy, smaps_rollup took ~10 ms
  // a process: all of 1517 took 16 s, longer than the flight of a 100-tick
  // bench, and the window's closing pass came after the UAVs had ended.
  const auto start = Clock::now();
  const auto closely = looked_at_closely(children_);
  std::size_t sampled = 0, running = 0;
  for (std::size_t i = 0; i < children_.size(); ++i) {
    auto& c = children_[i];
    running += c.running ? 1 : 0;
    if (!closely[i]) continue;
    c.sample = sample_process(c.pid);
    sampled += c.sample ? 1 : 0;
  }
  sampled_at_s_ = std::chrono::duration<double>(start - spawn_t0_).count();
  sampled_ = true;
  passes_ += Clock::now() - start;
  spdlog::debug("resources: sampled {} of {} running processes in {:.0f} ms, {:.1f} s after the first spawn", sampled,
                running, std::chrono::duration<double, std::milli>(Clock::now() - start).count(), *sampled_at_s_);
}

// --- the flight ---------------------------------------------------------------

FlightEnd Supervisor::fly() {
  while (flying()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    // A lockstep flight goes as fast as the slowest process and its length is
    // unknown: the sample is also taken when the first UAV ends by itself.
    if (!sampled_ && plan_.lockstep() && ended_by_itself("uav")) sample_resources();
    reap();
    serve_control();
    const auto now = Clock::now();
    const auto paused = paused_total_ + (paused_since_ ? now - *paused_since_ : Clock::duration{});
    watch_resources(now, paused);
    // Realtime faults by the wall clock since the swarm was started
    // (lockstep ones come with the conductor's `faults K`, in
    // serve_control); the ends of lasting ones in both clocks.
    if (faults_ && !faults_->schedule().in_ticks() && flight_end_ != FlightEnd::Interrupted) {
      for (const auto i : faults_->take_due_at(fault_clock_s())) execute_fault(i, std::nullopt);
    }
    end_due_faults();
    watch_conductor(now);
    if (runtime::shutdown_requested() && flight_end_ != FlightEnd::Interrupted) {
      spdlog::warn("interrupted: stopping the swarm");
      interrupt();
    }
    watch_deadline(now, paused);
  }
  return flight_end_;
}

void Supervisor::watch_resources(Clock::time_point now, Clock::duration paused) {
  // The resource sample. A realtime flight whose ground station runs here:
  // right after the steady window opened, a fifth into the flight after the
  // ground station's start (a big swarm's discovery outlasts 60 % of a short
  // flight counted from the launch: at 2000 UAVs it held no UAV). Lockstep,
  // or the ground station on another host (no "started" comes): 60 % of the
  // flight after every process of this host started.
  if (!sampled_) {
    const bool after_start = ground_here() && !plan_.lockstep();
    if (after_start ? windows_taken_ >= 1 : now >= t0_ + plan_.deadlines.resource_sample + paused) sample_resources();
  }
  // The steady window: discovery and the start are over, the end not near.
  // Its closing pass starts early by as long as the passes so far took, so
  // that it ends at four fifths of the flight, before the UAVs do.
  if (!started_at_ || plan_.lockstep() || windows_taken_ >= 2) return;
  const auto flight = std::chrono::duration<double>(plan_.ticks / plan_.rate_hz);
  const auto at = [&](double share) {
    return *started_at_ + paused + std::chrono::duration_cast<Clock::duration>(flight * share);
  };
  if (windows_taken_ == 0 ? now >= at(0.2) : now + passes_ >= at(0.8)) sample_window(windows_taken_);
}

void Supervisor::sample_window(int end) {
  // Every running process's CPU, context switches and threads' CPU; a
  // process that ended or restarted between the two ends is left out. On a
  // host the swarm keeps busy one pass over a thousand processes takes
  // seconds (measured: 6.6 s at 1000 UAVs): the window's ends are the
  // middles of the passes. Each thread (its time, exact, and its group) of
  // every place agent and ground station and of at most kSampledUavs UAVs
  // spread evenly over them, chosen at the opening pass; of the other UAVs
  // the process's time only, two files each rather than two per thread
  // (metrics_merge scales the sampled UAVs' threads to all of them).
  const auto t = Clock::now();
  if (end == 0) {
    const auto closely = looked_at_closely(children_);
    for (std::size_t i = 0; i < children_.size(); ++i) children_[i].window_threads = closely[i];
  }
  for (auto& c : children_) {
    if (c.running) c.window_cpu[end] = sample_cpu(c.pid, c.window_threads ? CpuDetail::Threads : CpuDetail::Process);
  }
  const auto done = Clock::now();
  if (end == 0) passes_ += done - t;
  window_at_[end] = t + (done - t) / 2;
  window_udp_[end] = netns_ ? netns_->udp_counters() : read_udp_counters();
  windows_taken_ = end + 1;
  spdlog::debug(
      "steady window {}: {} processes sampled in {:.0f} ms", end == 0 ? "opens" : "closes",
      std::count_if(children_.begin(), children_.end(), [&](const auto& c) { return c.window_cpu[end].has_value(); }),
      std::chrono::duration<double, std::milli>(done - t).count());
}

void Supervisor::watch_conductor(Clock::time_point now) {
  // A lockstep swarm whose conductor crashed: every UAV and place agent
  // that has had a clock ends by itself, with an error naming the
  // conductor, once the clock has been silent for its ConductorWatch limit
  // (kLeases leases). One still waiting for its first clock would wait
  // kFirstClock (minutes): past the limit and some slack, stop the rest.
  if (!plan_.lockstep()) return;
  const auto grace = plan_.deadlines.conductor_grace;
  if (!conductor_gone_at_ && ended_by_itself("ground")) {
    spdlog::error("the ground station (the lockstep conductor) ended: the swarm's processes end within {} ms",
                  grace.count());
    conductor_gone_at_ = now;
  }
  if (conductor_gone_at_ && flight_end_ != FlightEnd::Interrupted && now - *conductor_gone_at_ > grace) {
    spdlog::error("processes still running {} ms after the conductor ended: stopping them", grace.count());
    interrupt();
  }
}

void Supervisor::watch_deadline(Clock::time_point now, Clock::duration paused) {
  if (now <= t0_ + plan_.deadlines.uavs_end + paused + plan_.deadlines.other_hosts) return;
  spdlog::error(plan_.multi_host() ? "this host's processes still running long after the expected end; stopping them"
                                   : "uavs still flying long after the expected end; stopping them");
  end_open_faults();
  stop_early();
}

void Supervisor::interrupt() {
  flight_end_ = FlightEnd::Interrupted;
  end_open_faults();  // a stopped process would not hear SIGTERM
  stop_early();
}

void Supervisor::land() {
  // Stopped processes continue, cut-off ones are reconnected, restarts due
  // later do not happen: the place agents and the ground station must be
  // able to hear SIGTERM and finish.
  end_open_faults();
  spdlog::info(plan_.multi_host() ? "this host's processes ended" : "all uavs ended; stopping place agents");
  for (const auto& step : plan_.stop_final) stop_role(step);
  wall_s_ = std::chrono::duration<double>(Clock::now() - spawn_t0_).count();
  udp_end_ = netns_ ? netns_->udp_counters() : read_udp_counters();
  if (!sampled_ && flight_end_ != FlightEnd::Interrupted) {
    spdlog::warn("the uavs ended before the resource sample ({} s in): no pss/rss/threads in metrics.json",
                 0.6 * plan_.ticks / plan_.rate_hz);
  }
}

RunRecord Supervisor::record() const {
  RunRecord r;
  r.processes = children_;
  r.faults = fault_metrics();
  r.fault_failures = fault_failures_;
  r.dds = plan_.dds.describe();
  r.share = plan_.share;
  r.resources_sampled_at_s = sampled_at_s_;
  r.wall_s = wall_s_;
  r.run_t0_unix_ms = run_t0_unix_ms_;
  r.udp_start = udp_start_;
  r.udp_end = udp_end_;
  r.ticks_asked = plan_.ticks;
  if (windows_taken_ == 2) {
    r.steady = SteadyWindow{std::chrono::duration<double>(window_at_[1] - window_at_[0]).count(), plan_.rate_hz,
                            window_udp_[0], window_udp_[1]};
  }
  return r;
}

void Supervisor::clean_up() {
  stop_discovery_server();
  clean_fastdds_shm();
  if (netns_) {
    netns_->teardown();
    spdlog::info("network namespaces {}-* removed", netns_->prefix());
  }
}

void Supervisor::clean_fastdds_shm() const {
  // Our one-host Fast DDS profiles are UDP-only and leave nothing behind. With
  // any other profile Fast DDS may use shared memory, whose files a killed
  // process leaves in /dev/shm: remove those of dead processes.
  const std::string& profile = plan_.options.dds_profile;
  if (profile == "onehost" || profile == "onehost-unicast" || profile == "netns" || profile == "cells") return;
  const bool fastdds =
      std::any_of(children_.begin(), children_.end(), [](const auto& c) { return c.dds == "fastdds"; });
  const bool died =
      std::any_of(children_.begin(), children_.end(), [](const auto& c) { return c.term_signal != 0 || c.crashed(); });
  if (!fastdds || !died) return;
  const int rc = std::system("fastdds shm clean > /dev/null 2>&1");
  if (rc == 0) {
    spdlog::info("removed the shared-memory files of killed Fast DDS processes (fastdds shm clean)");
  } else {
    spdlog::warn(
        "Fast DDS processes were killed with profile '{}'; run `fastdds shm clean` to remove their /dev/shm files",
        profile);
  }
}

// --- the control line ---------------------------------------------------------

void Supervisor::serve_control() {
  if (ctl_fd_ < 0) return;
  char buf[512];
  for (;;) {
    const ssize_t n = recv(ctl_fd_, buf, sizeof buf, MSG_DONTWAIT);
    if (n == 0) {  // the ground station is gone
      close(ctl_fd_);
      ctl_fd_ = -1;
      return;
    }
    if (n < 0) break;
    ctl_buffer_.append(buf, static_cast<std::size_t>(n));
    if (ctl_buffer_.size() > 4096) ctl_buffer_.clear();  // not our protocol
  }
  for (auto nl = ctl_buffer_.find('\n'); nl != std::string::npos; nl = ctl_buffer_.find('\n')) {
    const std::string line = ctl_buffer_.substr(0, nl);
    ctl_buffer_.erase(0, nl + 1);
    const std::string reply = handle_control(line) + "\n";
    send(ctl_fd_, reply.data(), reply.size(), MSG_NOSIGNAL);
  }
}

std::string Supervisor::handle_control(const std::string& line) {
  const auto now = Clock::now();
  if (line == "pause") {
    if (!paused_since_) paused_since_ = now;
    return "ok paused";
  }
  if (line == "resume") {
    if (paused_since_) paused_total_ += now - *paused_since_;
    paused_since_.reset();
    return "ok resumed";
  }
  if (line == "started") {
    // The ground station started the swarm (realtime): the steady window
    // counts from here (watch_resources).
    if (!started_at_) started_at_ = now;
    return "ok";
  }
  if (line == "stop") {
    // A MAVLink station's stop (docs/mavlink.md): as the operator's SIGINT,
    // the swarm is stopped in order and the run ends as interrupted.
    spdlog::warn("the ground station asks to stop the run (a MAVLink station's disarm): stopping the swarm");
    runtime::request_shutdown();
    return "ok stopping the swarm";
  }
  if (line.rfind("faults ", 0) == 0) {
    const std::string k = line.substr(7);
    if (k.empty() || k.size() > 9 || k.find_first_not_of("0123456789") != std::string::npos) {
      return "error bad tick in '" + line + "'";
    }
    return answer_faults(static_cast<uint32_t>(std::stoul(k)));
  }
  char verb[16] = {}, role[16] = {};
  unsigned index = 0;
  if (std::sscanf(line.c_str(), "%15s %15s %u", verb, role, &index) != 3) return "error unknown request '" + line + "'";
  return control_process(verb, role, index);
}

std::string Supervisor::control_process(const std::string& verb, const std::string& role, uint32_t index) {
  if (role != "uav" && role != "place") return "error unknown role '" + role + "'";
  const std::string name = role + "-" + std::to_string(index);
  ChildProcess* c = find(name);
  if (c == nullptr) return "error there is no " + name;
  if (verb == "kill") {
    if (!c->running) return "error " + name + " is not running (" + c->describe() + ")";
    spdlog::warn("console: SIGKILL to {} (pid {})", c->name, c->pid);
    c->killed_on_purpose = true;
    kill(c->pid, SIGKILL);
    return "ok SIGKILL sent to " + name + " (pid " + std::to_string(c->pid) + ")";
  }
  if (verb == "restart" && role == "uav") {
    auto pid = respawn(name);
    if (!pid) return "error " + pid.error().message;
    spdlog::warn("console: restarted {} (pid {})", name, pid.value());
    return "ok restarted " + name + " (pid " + std::to_string(pid.value()) + ")";
  }
  return "error cannot " + verb + " a " + role;
}

}  // namespace pheromesh::cli
