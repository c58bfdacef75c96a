#include "launcher.hpp"

#include "pheromesh/bus/security.hpp"

#include <fcntl.h>
#include <sched.h>
#include <spdlog/spdlog.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "host_fit.hpp"
#include "pheromesh/bus/bus.hpp"
#include "pheromesh/auth/control.hpp"
#include "pheromesh/console/server.hpp"
#include "pheromesh/core/atomic_file.hpp"
#include "pheromesh/core/conductor.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/scenario_limits.hpp"
#include "pheromesh/runtime/process.hpp"
#include "pheromesh/runtime/report.hpp"

namespace pheromesh::cli {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// Above this many processes the UAVs start at --start-rate per second: every
// new participant is discovered by every other one (SPDP/SEDP), and when a
// few hundred arrive at once on a small host the discovery traffic starves
// the processes that must acknowledge it, their peers repeat it, and the
// storm lasts (measured, docs/dds.md "Scale").
constexpr std::size_t kStaggerAbove = 64;
// --discovery-server listens on this port + the domain id.
constexpr int kDiscoveryServerPort = 11811;
// Each process adds discovery and shutdown work; the UAV deadline grows by
// this much per process.
constexpr auto kDeadlinePerProcess = std::chrono::milliseconds(200);

double seconds(const timeval& tv) { return static_cast<double>(tv.tv_sec) + static_cast<double>(tv.tv_usec) / 1e6; }

// Three decimals are plenty for seconds and MiB, and keep metrics.json readable.
double round3(double v) { return std::round(v * 1000.0) / 1000.0; }

nlohmann::json opt_json(const std::optional<double>& v) { return v ? nlohmann::json(round3(*v)) : nlohmann::json(nullptr); }

int64_t unix_ms_now() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

}  // namespace

bool ChildProcess::crashed() const {
  if (running || pid < 0) return false;
  if (term_signal != 0) return !killed_on_purpose;
  return exit_code != 0;
}

std::string ChildProcess::describe() const {
  if (running) return "running";
  if (term_signal != 0) {
    return std::string("killed by ") + strsignal(term_signal) + (killed_on_purpose ? " (on purpose)" : "");
  }
  return "exited with " + std::to_string(exit_code);
}

std::string executable_dir() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(".") : self.parent_path().string();
}

std::string process_name(const std::string& role, uint32_t index, uint32_t replica) {
  if (role == "ground") return role;
  std::string n = role + "-" + std::to_string(index);
  if (replica > 0) n += ".r" + std::to_string(replica);
  return n;
}

Launcher::Launcher(RunOptions o) : o_(std::move(o)) {}

// Out of line: the namespaces go (NetnsSwarm's destructor) whenever the
// launcher does, also when run() ends by an exception.
Launcher::~Launcher() = default;

void Launcher::spawn(const std::string& role, uint32_t index, const std::vector<std::string>& extra_args,
                     uint32_t replica) {
  if (!o_.secure.empty() && plan_.ground == "fastdds") {
    // Fast DDS 2.9.1 leaves some pairs of secure participants that start
    // within the same instant unauthenticated for good (measured: 4 of 10
    // probes started together never saw one peer in 120 s; none when started
    // 300 ms apart; docs/security.md). Start them apart.
    const auto until = last_secure_spawn_ + kSecureFastDdsSpawnGap;
    while (Clock::now() < until) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      reap();
    }
    last_secure_spawn_ = Clock::now();
  }
  ChildProcess c;
  c.role = role;
  c.index = index;
  c.replica = replica;
  c.name = process_name(role, index, replica);
  c.dds = plan_.vendor_of(role, index);
  const std::string exe = bin_dir_ + "/pheromesh-" + (role == "uav" ? "uav" : role == "place" ? "place" : "ground");
  std::vector<std::string> args{exe,
                                "--scenario", o_.scenario,
                                "--dds", c.dds,
                                "--dds-profile", o_.dds_profile,
                                "--domain", std::to_string(o_.domain),
                                "--log-level", o_.log_level,
                                "--clock", o_.clock,
                                "--lease-ms", std::to_string(o_.lease_ms)};
  if (!o_.dds_peers.empty()) args.insert(args.end(), {"--dds-peers", o_.dds_peers});
  if (!o_.secure.empty()) args.insert(args.end(), {"--secure", o_.secure});
  if (o_.uavs > 0) args.insert(args.end(), {"--uavs", std::to_string(o_.uavs)});
  if (o_.seed > 0) args.insert(args.end(), {"--seed", std::to_string(o_.seed)});
  if (o_.rate_hz > 0) args.insert(args.end(), {"--rate", std::to_string(o_.rate_hz)});
  if (standby_) args.emplace_back("--standby");
  // Fast DDS 2.9 keeps an instance with its dead owner (docs/faults.md):
  // exclusive ownership only in all-Cyclone swarms.
  if (standby_ && !(plan_.single_vendor() && plan_.ground == "cyclone")) args.emplace_back("--shared-ownership");
  if (replica > 0) args.insert(args.end(), {"--replica", std::to_string(replica)});
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  const std::string log_path = (fs::path(o_.out_dir) / "logs" / (c.name + ".log")).string();

  // A participant id per process: Fast DDS takes its ports from it (7410 +
  // 250 domain + 2 id) instead of searching for free ones, which stops at
  // about 120 processes per host (docs/dds.md). Numbered in the order this
  // host starts them (the ground station, place agents, UAVs; standbys
  // started later after them), so that a host's ids stay below the 120 that
  // unicast discovery probes (lan-unicast); a restarted process gets its old
  // id (its ports are free).
  const auto known = participant_of_.find(c.name);
  const uint32_t participant =
      known != participant_of_.end() ? known->second : static_cast<uint32_t>(participant_of_.size());
  participant_of_[c.name] = participant;
  std::string participant_env = "PHEROMESH_PARTICIPANT_ID=" + std::to_string(participant);
  // Network faults: the process runs in its own network namespace.
  int netns_fd = -1;
  if (netns_) {
    if (auto err = netns_->add(c.name))
      throw std::runtime_error("cannot give " + c.name + " a network namespace: " + *err);
    netns_fd = netns_->fd_of(c.name);
  }
  const pid_t parent = getpid();
  pid_t pid = fork();
  // EAGAIN: the process or thread limit is reached for now (a big swarm's
  // start); give exiting processes a moment.
  for (int attempt = 0; pid < 0 && errno == EAGAIN && attempt < 5; ++attempt) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    pid = fork();
  }
  if (pid < 0) throw std::runtime_error(std::string("fork failed: ") + std::strerror(errno));
  if (pid == 0) {
    // Child: own process group (the launcher orders the shutdown), die with
    // the launcher, output to its log file (the ground station also to ours).
    setpgid(0, 0);
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    putenv(participant_env.data());  // single-threaded launcher: safe after fork
    if (getppid() != parent) _exit(127);
    if (netns_fd >= 0 && setns(netns_fd, CLONE_NEWNET) != 0) {
      dprintf(STDERR_FILENO, "cannot enter the network namespace of %s: %s\n", c.name.c_str(), std::strerror(errno));
      _exit(126);
    }
    if (role == "ground" && child_ctl_fd_ >= 0) {
      // The console's control socket, as fd 3 (dup2 clears close-on-exec).
      if (child_ctl_fd_ == 3) {
        fcntl(3, F_SETFD, 0);
      } else {
        dup2(child_ctl_fd_, 3);
      }
    }
    const int fd = open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd >= 0) {
      dup2(fd, STDOUT_FILENO);
      if (role != "ground") dup2(fd, STDERR_FILENO);
    }
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(exe.c_str(), argv.data());
    dprintf(STDERR_FILENO, "cannot execute %s: %s\n", exe.c_str(), std::strerror(errno));
    _exit(127);
  }
  c.pid = pid;
  c.running = true;
  unreaped_[pid] = children_.size();
  children_.push_back(std::move(c));
}

void Launcher::spawn_place(uint32_t region, uint32_t replica) {
  // --ticks only so that the run the place agent publishes for monitors
  // (RunScenario) is the UAVs'; a realtime place agent runs until the end.
  spawn("place", region, {"--region", std::to_string(region), "--ticks", std::to_string(ticks_)}, replica);
  top_replica_[region] = std::max(top_replica_[region], replica);
}

bool Launcher::on_this_host(const std::string& role, uint32_t index, uint32_t replica) const {
  if (o_.hosts <= 1) return true;
  if (role == "ground") return o_.host_index == o_.ground_host;
  if (role == "place") return (index + replica) % o_.hosts == o_.host_index;
  return index % o_.hosts == o_.host_index;
}

bool Launcher::spawn_swarm(uint32_t regions, uint32_t uavs, uint32_t ticks) {
  for (uint32_t r = 0; r < regions; ++r) {
    if (on_this_host("place", r, 0)) spawn_place(r, 0);
  }
  if (o_.standby || standby_from_scenario_) {
    for (uint32_t r = 0; r < regions; ++r) {
      if (on_this_host("place", r, 1)) spawn_place(r, 1);
    }
  }
  const bool stagger = 1 + std::size_t{regions} + uavs > kStaggerAbove && o_.start_rate > 0;
  // Batches of a tenth of a second's worth of UAVs.
  const auto batch = std::max<uint32_t>(1, static_cast<uint32_t>(o_.start_rate / 10.0));
  const auto pause = std::chrono::milliseconds(static_cast<int64_t>(1000.0 * batch / std::max(o_.start_rate, 1e-3)));
  if (stagger) {
    spdlog::info("{} processes: starting the uavs {} at a time, {} ms apart ({:.0f} per second, --start-rate)",
                 1 + regions + uavs, batch, pause.count(), o_.start_rate);
  }
  for (uint32_t u = 0; u < uavs; ++u) {
    if (stagger && u % batch == 0) {
      // The pause before the first batch gives the place agents a head start.
      const auto until = Clock::now() + pause;
      while (Clock::now() < until) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        reap();
      }
      if (runtime::shutdown_requested()) {
        spdlog::warn("interrupted after starting {} of {} uavs", u, uavs);
        return false;
      }
    }
    if (!on_this_host("uav", u)) continue;
    spawn("uav", u, {"--id", std::to_string(u), "--ticks", std::to_string(ticks)});
  }
  return true;
}

bool Launcher::start_discovery_server() {
  // Fast DDS's discovery server: every Fast DDS process discovers through it
  // instead of with every other process (its clients take the server's
  // address from ROS_DISCOVERY_SERVER). Cyclone processes cannot use it.
  for (const char* role : {"ground", "place", "uav"}) {
    if (plan_.vendor_of(role, 0) != "fastdds" || plan_.vendor_of(role, 1) != "fastdds") {
      spdlog::error("--discovery-server needs every process on Fast DDS (--dds fastdds); {} processes are not", role);
      return false;
    }
  }
  const std::string port = std::to_string(kDiscoveryServerPort + o_.domain);
  const std::string log_path = (fs::path(o_.out_dir) / "logs" / "discovery-server.log").string();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(std::string("fork failed: ") + std::strerror(errno));
  if (pid == 0) {
    setpgid(0, 0);
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    const int fd = open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd >= 0) {
      dup2(fd, STDOUT_FILENO);
      dup2(fd, STDERR_FILENO);
    }
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

void Launcher::stop_discovery_server() {
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

void Launcher::reap() {
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

void Launcher::record_exit(pid_t pid, int status, const rusage& ru) {
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
    spdlog::error("{} (pid {}) {} — see {}/logs/{}.log", c.name, c.pid, c.describe(), o_.out_dir, c.name);
  } else if (c.killed_on_purpose) {
    spdlog::info("{} (pid {}) {}", c.name, c.pid, c.describe());
  }
}

void Launcher::kill_and_reap(ChildProcess& c) {
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

void Launcher::sample_resources() {
  // Once per run, mid-flight: smaps_rollup (Rss and Pss: shared pages such as
  // the DDS libraries counted once per sharer) and the thread count of every
  // process still running. Reading a thousand processes' files takes a few
  // hundred ms; a process that ended meanwhile is simply left out.
  const auto start = Clock::now();
  std::size_t sampled = 0, running = 0;
  for (auto& c : children_) {
    if (!c.running) continue;
    ++running;
    c.sample = sample_process(c.pid);
    sampled += c.sample ? 1 : 0;
  }
  sampled_at_s_ = std::chrono::duration<double>(start - spawn_t0_).count();
  spdlog::debug("resources: sampled {} of {} running processes in {:.0f} ms, {:.1f} s after the first spawn", sampled,
                running, std::chrono::duration<double, std::milli>(Clock::now() - start).count(), *sampled_at_s_);
}

void Launcher::raise_fd_limit() {
  // Each DDS participant holds a dozen sockets and each child a log file;
  // children inherit the raised limit. The thread limit (RLIMIT_NPROC counts
  // every thread of the user) is raised alike, for a thousand DDS processes.
  for (const auto& [resource, name] : {std::pair{RLIMIT_NOFILE, "RLIMIT_NOFILE"}, std::pair{RLIMIT_NPROC, "RLIMIT_NPROC"}}) {
    rlimit rl{};
    if (getrlimit(resource, &rl) != 0) continue;
    if (rl.rlim_cur == rl.rlim_max) {
      spdlog::debug("{}: soft limit already at the hard limit ({})", name, rl.rlim_max);
      continue;
    }
    const rlim_t before = rl.rlim_cur;
    rl.rlim_cur = rl.rlim_max;
    if (setrlimit(resource, &rl) == 0) {
      spdlog::debug("{}: soft limit raised from {} to the hard limit {}", name, before, rl.rlim_max);
    } else {
      spdlog::debug("{}: cannot raise the soft limit {} to {}: {}", name, before, rl.rlim_max, std::strerror(errno));
    }
  }
}

bool Launcher::any_running(const std::string& role) const {
  return std::any_of(children_.begin(), children_.end(), [&](const auto& c) { return c.role == role && c.running; });
}

ChildProcess* Launcher::find(const std::string& name) {
  // A restarted UAV has several entries: the running one, else the latest.
  ChildProcess* latest = nullptr;
  for (auto& c : children_) {
    if (c.name != name) continue;
    if (c.running) return &c;
    latest = &c;
  }
  return latest;
}

void Launcher::serve_control() {
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

std::string Launcher::handle_control(const std::string& line) {
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
  const std::string v = verb, r = role;
  if (r != "uav" && r != "place") return "error unknown role '" + r + "'";
  const std::string name = r + "-" + std::to_string(index);
  ChildProcess* c = find(name);
  if (c == nullptr) return "error there is no " + name;
  if (v == "kill") {
    if (!c->running) return "error " + name + " is not running (" + c->describe() + ")";
    spdlog::warn("console: SIGKILL to {} (pid {})", c->name, c->pid);
    c->killed_on_purpose = true;
    kill(c->pid, SIGKILL);
    return "ok SIGKILL sent to " + name + " (pid " + std::to_string(c->pid) + ")";
  }
  if (v == "restart" && r == "uav") {
    auto pid = respawn(name);
    if (!pid) return "error " + pid.error().message;
    spdlog::warn("console: restarted {} (pid {})", name, pid.value());
    return "ok restarted " + name + " (pid " + std::to_string(pid.value()) + ")";
  }
  return "error cannot " + v + " a " + r;
}

core::Result<pid_t> Launcher::respawn(const std::string& name) {
  const ChildProcess* c = find(name);
  if (c == nullptr) return core::Error{"there is no " + name};
  if (c->running) return core::Error{name + " is running; kill it first"};
  const std::string role = c->role;
  const uint32_t index = c->index, replica = c->replica;
  if (role == "uav") {
    // A lockstep run knows its tick from the conductor's last `faults K`;
    // a realtime one counts the ticks flown by the wall clock.
    int64_t remaining = 0;
    if (o_.clock == "lockstep" && last_fault_tick_) {
      remaining = static_cast<int64_t>(ticks_) - static_cast<int64_t>(*last_fault_tick_);
    } else {
      const auto flown = std::chrono::duration<double>(Clock::now() - t0_ - paused_total_).count();
      remaining = static_cast<int64_t>(ticks_) - static_cast<int64_t>(flown * rate_);
    }
    if (remaining < 1) return core::Error{"the run is over for " + name};
    const uint32_t life = ++lives_[index];
    // Deposits of each life are numbered above the earlier lives' (place
    // agents drop sequence numbers they have seen).
    spawn("uav", index, {"--id", std::to_string(index), "--ticks", std::to_string(remaining), "--seq-base",
                         std::to_string(life << 24U)});
    spdlog::info("{} started again for its remaining {} ticks", name, remaining);
  } else if (role == "place") {
    spawn_place(index, replica);
  } else {
    return core::Error{"cannot restart the " + name};
  }
  return find(name)->pid;
}

void Launcher::stop_role(const std::string& role, std::chrono::seconds grace) {
  for (auto& c : children_) {
    if (c.role == role && c.running) {
      c.asked_to_stop = true;
      kill(c.pid, SIGTERM);
    }
  }
  const auto deadline = Clock::now() + grace;
  while (any_running(role) && Clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    reap();
  }
  for (auto& c : children_) {
    if (c.role == role && c.running) {
      spdlog::error("{} did not stop within {} s of SIGTERM; sending SIGKILL", c.name, grace.count());
      kill(c.pid, SIGKILL);
    }
  }
  while (any_running(role)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    reap();
  }
}

std::optional<std::string> Launcher::check_secure(uint32_t uavs, uint32_t regions) const {
  if (o_.secure.empty()) return std::nullopt;
  if (!plan_.single_vendor()) {
    // Measured (docs/security.md, "Mixed vendors"): Fast DDS 2.9.1 sends its
    // PKI-DH key-agreement value as raw bytes where Cyclone 0.10.2 expects an
    // ASN.1 integer, and no handshake between the two completes.
    return "--secure needs every process on one DDS vendor (--dds cyclone or --dds fastdds): the DDS Security "
           "handshakes of Cyclone DDS 0.10.2 and Fast DDS 2.9.1 do not interoperate (docs/security.md)";
  }
  // Every process this host starts needs its identity: say which is missing
  // before starting any (a missing one would stop that process at start).
  std::vector<std::string> names;
  if (on_this_host("ground", 0)) names.emplace_back("ground");
  for (uint32_t r = 0; r < regions; ++r) {
    for (uint32_t k = 0; k < (standby_ ? 2U : 1U); ++k) {
      if (on_this_host("place", r, k)) names.push_back(process_name("place", r, k));
    }
  }
  for (uint32_t u = 0; u < uavs; ++u) {
    if (on_this_host("uav", u)) names.push_back(process_name("uav", u, 0));
  }
  for (const auto& n : names) {
    auto f = bus::find_security_files(o_.secure, n);
    if (!f) return f.error().message;
  }
  return std::nullopt;
}

std::optional<std::string> Launcher::check_multi_host(const core::ScenarioConfig& s) const {
  if (o_.hosts == 0) return "--hosts must be at least 1";
  if (o_.host_index >= o_.hosts) {
    return "--host-index " + std::to_string(o_.host_index) + " is not below --hosts " + std::to_string(o_.hosts) +
           " (hosts are numbered 0.." + std::to_string(o_.hosts - 1) + ")";
  }
  if (o_.ground_host >= o_.hosts) {
    return "--ground-host " + std::to_string(o_.ground_host) + " is not below --hosts " + std::to_string(o_.hosts);
  }
  if (!multi_host()) return std::nullopt;
  if (o_.dds_profile == "onehost" || o_.dds_profile == "onehost-unicast" || o_.dds_profile == "netns") {
    return "--hosts " + std::to_string(o_.hosts) + ": DDS profile '" + o_.dds_profile +
           "' keeps traffic on this host; use --dds-profile lan (multicast discovery) or lan-unicast --dds-peers "
           "HOST,HOST,... (docs/deployment.md)";
  }
  if (o_.dds_profile == "lan-unicast" && o_.dds_peers.empty()) {
    return "--dds-profile lan-unicast needs --dds-peers: the address or name of every host of the swarm";
  }
  auto key = auth::control_key_from_env();
  if (!key || !key.value()) {
    return std::string("--hosts ") + std::to_string(o_.hosts) +
           ": every host of one swarm needs the same control key in $" + auth::kControlKeyEnv +
           " (the ground station signs the start and the end of the run with it); make one with " +
           "`pheromesh key` and export it on every host" +
           (key ? "" : " (the one set is malformed: " + key.error().message + ")");
  }
  if (o_.discovery_server) return "--discovery-server runs on one host; it does not work with --hosts";
  if (o_.http_port && !on_this_host("ground", 0)) {
    return "--http: the web console is served by the ground station, which runs on host " +
           std::to_string(o_.ground_host) +
           " (--ground-host); give --http there, or attach a monitor anywhere with `pheromesh attach --http PORT`";
  }
  if (faults_) {
    if (faults_->schedule().has_network()) {
      return "fault schedule: partition and loss put every process of one host in its own network namespace; they do "
             "not work with --hosts (use them on one host, or shape the LAN itself)";
    }
    if (o_.clock == "lockstep") {
      return "fault schedule: a lockstep run injects faults through the conductor's line to its launcher, on one host; "
             "with --hosts give the faults to a realtime run";
    }
    const uint32_t replicas = (o_.standby || s.standby) ? 2 : 1;
    for (const auto& e : faults_->schedule().events) {
      for (const auto& t : e.targets) {
        bool here = false;
        for (uint32_t k = 0; k < (t.role == "place" ? replicas : 1); ++k)
          here = here || on_this_host(t.role, t.index, k);
        if (!here) {
          return "fault schedule: '" + e.text + "': " + t.process_name() + " does not run on host " +
                 std::to_string(o_.host_index) + " (--hosts " + std::to_string(o_.hosts) +
                 ": place agent R on host R % hosts, its standby on the next, UAV U on host U % hosts, the ground "
                 "station on --ground-host); give this fault to that host's pheromesh run";
        }
      }
    }
  }
  return std::nullopt;
}

int Launcher::run() {
  raise_fd_limit();
  auto scenario = core::load_scenario(o_.scenario);
  if (!scenario) {
    spdlog::error("invalid scenario:\n{}", scenario.error().message);
    return 2;
  }
  const core::ScenarioConfig& s = scenario.value();
  const double rate = o_.rate_hz > 0 ? o_.rate_hz : s.tick_rate_hz;
  if (o_.duration_s > 0) o_.ticks = static_cast<uint32_t>(std::ceil(o_.duration_s * rate));
  const uint32_t ticks = o_.ticks > 0 ? o_.ticks : s.ticks;
  const uint32_t uavs = o_.uavs > 0 ? o_.uavs : s.uavs;
  const uint32_t regions = s.geometry().region_count();
  regions_ = regions;
  uavs_ = uavs;
  standby_from_scenario_ = s.standby;
  standby_ = o_.standby || s.standby;
  {
    // --uavs and --standby change what the scenario asks of the machine.
    core::ScenarioConfig asked = s;
    asked.uavs = uavs;
    asked.standby = standby_;
    auto limits = core::ScenarioLimits::from_environment();
    auto ok = limits ? core::check_limits(asked, limits.value(), o_.scenario) : core::Result<bool>(limits.error());
    if (!ok) {
      spdlog::error("the swarm asked for exceeds a limit:\n{}", ok.error().message);
      return 2;
    }
  }
  auto plan = parse_dds_plan(o_.dds, bus::available_vendors());
  if (!plan) {
    spdlog::error("{}", plan.error().message);
    return 2;
  }
  plan_ = std::move(plan).value();
  bin_dir_ = executable_dir();
  for (const char* exe : {"pheromesh-uav", "pheromesh-place", "pheromesh-ground"}) {
    if (access((bin_dir_ + "/" + exe).c_str(), X_OK) != 0) {
      spdlog::error("cannot find {} next to pheromesh in {}", exe, bin_dir_);
      return 3;
    }
  }
  if (auto err = prepare_faults(s, uavs, regions)) {
    spdlog::error("{}", *err);
    return 2;
  }
  if (auto err = check_secure(uavs, regions)) {
    spdlog::error("{}", *err);
    return 2;
  }
  if (auto err = check_multi_host(s)) {
    spdlog::error("{}", *err);
    return 2;
  }
  fs::create_directories(fs::path(o_.out_dir) / "logs");
  fs::remove(fs::path(o_.out_dir) / "metrics.json");
  if (o_.clock != "lockstep") {
    if (auto w = host_fit_warning(uavs, rate, std::thread::hardware_concurrency(), o_.dds, o_.discovery_server)) {
      spdlog::warn("this swarm may not keep time on this host: {}", *w);
    }
  }
  spdlog::info("run '{}' ({}): {} place agents, {} uavs, {} ticks, {} clock{}, over {} (domain {}, profile {}); logs in {}/logs",
               s.name, o_.scenario, regions, uavs, ticks, o_.clock,
               o_.clock == "lockstep" ? "" : fmt::format(" at {:.1f} Hz", rate), plan_.describe(), o_.domain, o_.dds_profile,
               o_.out_dir);
  if (multi_host()) {
    uint32_t places_here = 0, uavs_here = 0;
    const uint32_t replicas = (o_.standby || s.standby) ? 2 : 1;
    for (uint32_t r = 0; r < regions; ++r) {
      for (uint32_t k = 0; k < replicas; ++k) places_here += on_this_host("place", r, k) ? 1 : 0;
    }
    for (uint32_t u = 0; u < uavs; ++u) uavs_here += on_this_host("uav", u) ? 1 : 0;
    spdlog::info("host {} of {}: {} place agents, {} uavs{} here; the ground station {}", o_.host_index, o_.hosts,
                 places_here, uavs_here, o_.dds_peers.empty() ? "" : fmt::format(" (DDS peers {})", o_.dds_peers),
                 on_this_host("ground", 0) ? "too (it ends the run)" : fmt::format("on host {}", o_.ground_host));
  }

  runtime::install_shutdown_handlers();
  ticks_ = ticks;
  rate_ = rate;
  uavs_ = uavs;
  if (auto err = prepare_netns(uavs, regions)) {
    spdlog::error("{}", *err);
    return 2;
  }
  const bool lockstep_faults = faults_ && o_.clock == "lockstep";
  // Every process of this swarm shares a fresh control key: only this
  // ground station can sign commands they act on (docs/console.md). Over
  // several hosts every host has the same one, from the environment
  // (check_multi_host).
  if (!multi_host()) setenv(auth::kControlKeyEnv, auth::random_control_key_hex().c_str(), 1);
  std::vector<std::string> ground_args{"--out", o_.out_dir, "--progress", std::to_string(o_.progress_s), "--ticks",
                                       std::to_string(ticks), "--expect-uavs", std::to_string(uavs)};
  // No launcher sees every process: the ground station ends the run.
  if (multi_host()) ground_args.emplace_back("--until-done");
  std::string token;
  // The launch instant: wall_s and the ground station's discovery_s count from
  // here (children inherit PHEROMESH_RUN_T0_MS).
  // With network faults every process counts its own datagrams in its own
  // namespace: exactly this swarm's.
  udp_start_ = netns_ ? netns_->udp_counters() : read_udp_counters();
  spawn_t0_ = Clock::now();
  run_t0_unix_ms_ = unix_ms_now();
  setenv("PHEROMESH_RUN_T0_MS", std::to_string(run_t0_unix_ms_).c_str(), 1);
  // The ground station's line to us: the console's kill / restart requests,
  // and the lockstep conductor's `faults K`.
  if (o_.http_port || lockstep_faults) {
    int sv[2];
    if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0) {
      throw std::runtime_error(std::string("socketpair: ") + std::strerror(errno));
    }
    ctl_fd_ = sv[0];
    child_ctl_fd_ = sv[1];
    ground_args.insert(ground_args.end(), {"--launcher-fd", "3"});
  }
  if (lockstep_faults) {
    std::string list;
    for (const uint32_t k : faults_->fault_ticks()) list += (list.empty() ? "" : ",") + std::to_string(k);
    ground_args.insert(ground_args.end(), {"--fault-ticks", list});
  }
  if (o_.http_port) {
    token = console::random_token();
    setenv("PHEROMESH_CONSOLE_TOKEN", token.c_str(), 1);
    const std::string record = o_.no_record ? "" : !o_.record.empty() ? o_.record : (fs::path(o_.out_dir) / "console.phrec").string();
    ground_args.insert(ground_args.end(), {"--http", std::to_string(*o_.http_port), "--http-bind", o_.http_bind});
    if (!record.empty()) ground_args.insert(ground_args.end(), {"--record", record});
  }
  if (o_.discovery_server && !start_discovery_server()) return 3;
  if (on_this_host("ground", 0)) spawn("ground", 0, ground_args);
  if (child_ctl_fd_ >= 0) {
    close(child_ctl_fd_);
    child_ctl_fd_ = -1;
  }
  unsetenv("PHEROMESH_CONSOLE_TOKEN");
  if (o_.http_port && *o_.http_port != 0) {
    const std::string host = o_.http_bind == "0.0.0.0" ? "127.0.0.1" : o_.http_bind;
    spdlog::info("web console: http://{}:{}/?token={}", host, *o_.http_port, token);
  } else if (o_.http_port) {
    spdlog::info("web console: the ground station prints its URL (port chosen by the system)");
  }
  spawn_swarm(regions, uavs, ticks);  // if interrupted, the loop below stops what was started
  const auto t0 = Clock::now();
  t0_ = t0;
  // Generous bound on the UAV phase: the run itself, discovery, and slack for
  // a loaded machine, growing with the swarm (discovery and shutdown work per
  // process). UAVs still flying then are stopped (and reported).
  // A lockstep run has no such bound: it goes as fast as its slowest
  // process (under packet loss, seconds per tick), the conductor bounds each
  // phase (--phase-timeout) and every UAV and place agent ends when the
  // conductor's clock falls silent (core::ConductorWatch).
  const double expected_s = o_.clock == "lockstep" ? 365.0 * 24 * 3600 : ticks / rate * 2.0;
  const auto uav_deadline = t0 + std::chrono::milliseconds(static_cast<int64_t>(1000.0 * expected_s)) +
                            std::chrono::seconds(45) + kDeadlinePerProcess * children_.size();
  // The resource sample: at 60 % of the flight (ticks / rate). A lockstep
  // flight goes as fast as the slowest process and its length is unknown, so
  // there the sample is also taken when the first UAV ends by itself, if that
  // comes earlier.
  const auto sample_at = t0 + std::chrono::milliseconds(static_cast<int64_t>(600.0 * ticks / rate));
  bool sampled = false;
  bool interrupted = false;
  // Lockstep: when the conductor ended, and how long its processes get to
  // notice by themselves (their ConductorWatch limit, plus slack for a busy host).
  std::optional<Clock::time_point> conductor_gone_at;
  const auto conductor_grace = std::chrono::milliseconds(int64_t{o_.lease_ms} * core::ConductorWatch::kLeases) +
                               std::chrono::seconds(15);
  // Over several hosts this host's place agents and ground station end by
  // themselves, on the ground station's End, after every UAV of the swarm.
  const auto flying = [&] {
    return any_running("uav") || (multi_host() && (any_running("place") || any_running("ground")));
  };
  const auto stop_here = [&] {
    stop_role("uav", std::chrono::seconds(10));
    if (multi_host()) {
      stop_role("place", std::chrono::seconds(15));
      stop_role("ground", std::chrono::seconds(15));
    }
  };
  while (flying()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (!sampled && o_.clock == "lockstep" &&
        std::any_of(children_.begin(), children_.end(), [](const auto& c) {
          return c.role == "uav" && !c.running && !c.killed_on_purpose && !c.asked_to_stop;
        })) {
      sample_resources();
      sampled = true;
    }
    reap();
    serve_control();
    const auto now = Clock::now();
    const auto paused_now = paused_total_ + (paused_since_ ? now - *paused_since_ : Clock::duration{});
    if (!sampled && now >= sample_at + paused_now) {
      sample_resources();
      sampled = true;
    }
    // Realtime faults by the wall clock since the swarm was started
    // (lockstep ones come with the conductor's `faults K`, in
    // serve_control); the ends of lasting ones in both clocks.
    if (faults_ && !faults_->schedule().in_ticks() && !interrupted) {
      for (const auto i : faults_->take_due_at(fault_clock_s())) execute_fault(i, std::nullopt);
    }
    end_due_faults();
    // A lockstep swarm whose conductor crashed: every UAV and place agent
    // that has had a clock ends by itself, with an error naming the
    // conductor, once the clock has been silent for its ConductorWatch limit
    // (kLeases leases). One still waiting for its first clock would wait
    // kFirstClock (minutes): past the limit and some slack, stop the rest.
    if (o_.clock == "lockstep" && !conductor_gone_at &&
        std::any_of(children_.begin(), children_.end(), [](const auto& c) {
          return c.role == "ground" && !c.running && !c.killed_on_purpose && !c.asked_to_stop;
        })) {
      spdlog::error("the ground station (the lockstep conductor) ended: the swarm's processes end within {} ms",
                    conductor_grace.count());
      conductor_gone_at = now;
    }
    if (conductor_gone_at && !interrupted && now - *conductor_gone_at > conductor_grace) {
      spdlog::error("processes still running {} ms after the conductor ended: stopping them", conductor_grace.count());
      interrupted = true;
      end_open_faults();
      stop_here();
    }
    if (runtime::shutdown_requested() && !interrupted) {
      spdlog::warn("interrupted: stopping the swarm");
      interrupted = true;
      end_open_faults();  // a stopped process would not hear SIGTERM
      stop_here();
    }
    // Over several hosts: a minute more for the End of a ground station on
    // another host (it waits for the slowest host's UAVs).
    if (now > uav_deadline + paused_now + (multi_host() ? std::chrono::seconds(60) : std::chrono::seconds(0))) {
      spdlog::error(multi_host() ? "this host's processes still running long after the expected end; stopping them"
                                 : "uavs still flying long after the expected end; stopping them");
      end_open_faults();
      stop_here();
    }
  }
  // Stopped processes continue, cut-off ones are reconnected, restarts due
  // later do not happen: the place agents and the ground station must be
  // able to hear SIGTERM and finish.
  end_open_faults();
  spdlog::info(multi_host() ? "this host's processes ended" : "all uavs ended; stopping place agents");
  stop_role("place", std::chrono::seconds(15));
  stop_role("ground", std::chrono::seconds(15));
  wall_s_ = std::chrono::duration<double>(Clock::now() - spawn_t0_).count();
  udp_end_ = netns_ ? netns_->udp_counters() : read_udp_counters();
  if (!sampled && !interrupted) {
    spdlog::warn("the uavs ended before the resource sample ({} s in): no pss/rss/threads in metrics.json",
                 0.6 * ticks / rate);
  }
  int exit_code = 0;
  finish_metrics(exit_code);
  stop_discovery_server();
  clean_fastdds_shm();
  if (netns_) {
    netns_->teardown();
    spdlog::info("network namespaces {}-* removed", netns_->prefix());
  }
  return interrupted ? 130 : exit_code;
}

void Launcher::clean_fastdds_shm() const {
  // Our one-host Fast DDS profiles are UDP-only and leave nothing behind. With
  // any other profile Fast DDS may use shared memory, whose files a killed
  // process leaves in /dev/shm: remove those of dead processes.
  if (o_.dds_profile == "onehost" || o_.dds_profile == "onehost-unicast" || o_.dds_profile == "netns") return;
  const bool fastdds = std::any_of(children_.begin(), children_.end(), [](const auto& c) { return c.dds == "fastdds"; });
  const bool died = std::any_of(children_.begin(), children_.end(),
                                [](const auto& c) { return c.term_signal != 0 || c.crashed(); });
  if (!fastdds || !died) return;
  const int rc = std::system("fastdds shm clean > /dev/null 2>&1");
  if (rc == 0) {
    spdlog::info("removed the shared-memory files of killed Fast DDS processes (fastdds shm clean)");
  } else {
    spdlog::warn("Fast DDS processes were killed with profile '{}'; run `fastdds shm clean` to remove their /dev/shm files",
                 o_.dds_profile);
  }
}

void Launcher::finish_metrics(int& exit_code) {
  uint32_t killed = 0, crashed = 0;
  nlohmann::json procs = nlohmann::json::array();
  // Per role: sums of CPU, means over the processes sampled mid-flight.
  struct RoleTotals {
    uint32_t count = 0, reaped = 0, sampled = 0;
    double user_s = 0, sys_s = 0, max_rss_sum = 0;
    std::vector<double> pss, rss, threads;
  };
  std::map<std::string, RoleTotals> roles{{"uav", {}}, {"place", {}}, {"ground", {}}};
  for (const auto& c : children_) {
    killed += c.killed_on_purpose ? 1 : 0;
    crashed += c.crashed() ? 1 : 0;
    nlohmann::json p = {{"name", c.name}, {"pid", c.pid}, {"dds", c.dds}, {"status", c.describe()}, {"crashed", c.crashed()}};
    p["cpu_user_s"] = c.reaped ? nlohmann::json(round3(c.cpu_user_s)) : nlohmann::json(nullptr);
    p["cpu_sys_s"] = c.reaped ? nlohmann::json(round3(c.cpu_sys_s)) : nlohmann::json(nullptr);
    p["max_rss_mib"] = c.reaped ? nlohmann::json(round3(c.max_rss_mib)) : nlohmann::json(nullptr);
    p["pss_mib"] = opt_json(c.sample ? c.sample->pss_mib : std::nullopt);
    p["rss_mib"] = opt_json(c.sample ? c.sample->rss_mib : std::nullopt);
    p["threads"] = c.sample && c.sample->threads ? nlohmann::json(*c.sample->threads) : nlohmann::json(nullptr);
    procs.push_back(std::move(p));
    RoleTotals& t = roles[c.role];
    ++t.count;
    if (c.reaped) {
      ++t.reaped;
      t.user_s += c.cpu_user_s;
      t.sys_s += c.cpu_sys_s;
      t.max_rss_sum += c.max_rss_mib;
    }
    if (c.sample) {
      ++t.sampled;
      if (c.sample->pss_mib) t.pss.push_back(*c.sample->pss_mib);
      if (c.sample->rss_mib) t.rss.push_back(*c.sample->rss_mib);
      if (c.sample->threads) t.threads.push_back(static_cast<double>(*c.sample->threads));
    }
  }
  auto mean_of = [](const std::vector<double>& v) -> std::optional<double> {
    if (v.empty()) return std::nullopt;
    double sum = 0;
    for (double x : v) sum += x;
    return sum / static_cast<double>(v.size());
  };
  auto max_of = [](const std::vector<double>& v) -> std::optional<double> {
    if (v.empty()) return std::nullopt;
    return *std::max_element(v.begin(), v.end());
  };
  nlohmann::json resources = nlohmann::json::object();
  for (const auto& [role, t] : roles) {
    resources[role] = {
        {"count", t.count},
        {"cpu_user_s", round3(t.user_s)},
        {"cpu_sys_s", round3(t.sys_s)},
        {"sampled", t.sampled},
        {"pss_mib_mean", opt_json(mean_of(t.pss))},
        {"pss_mib_max", opt_json(max_of(t.pss))},
        {"rss_mib_mean", opt_json(mean_of(t.rss))},
        {"max_rss_mib_mean",
         opt_json(t.reaped > 0 ? std::optional<double>(t.max_rss_sum / t.reaped) : std::nullopt)},
        {"threads_mean", opt_json(mean_of(t.threads))},
    };
  }
  // Over several hosts the swarm's metrics.json is the ground station's host's;
  // every other host writes what it ran to host-I.json.
  const bool ground_here = on_this_host("ground", 0);
  const fs::path path = fs::path(o_.out_dir) /
                        (ground_here ? std::string("metrics.json") : "host-" + std::to_string(o_.host_index) + ".json");
  nlohmann::json m;
  std::ifstream in(ground_here ? path : fs::path());
  if (in) {
    try {
      in >> m;
    } catch (const std::exception& e) {
      spdlog::error("{} is not valid JSON: {}", path.string(), e.what());
    }
  }
  if (m.is_null()) {
    if (ground_here) {
      spdlog::error("the ground station left no {}", path.string());
      exit_code = 1;
    }
    m = nlohmann::json::object();
  }
  if (multi_host()) {
    m["hosts"] = o_.hosts;
    m["host_index"] = o_.host_index;
    m["ground_host"] = o_.ground_host;
  }
  add_fault_metrics(m);
  if (fault_failures_ > 0) {
    spdlog::error("{} fault events could not be injected (metrics.json \"faults\")", fault_failures_);
    exit_code = 1;
  }
  m["processes_killed"] = killed;
  m["processes_crashed"] = crashed;
  m["processes"] = procs;
  m["dds"] = plan_.describe();
  m["resources"] = resources;
  m["resources_sampled_at_s"] = opt_json(sampled_at_s_);
  m["wall_s"] = opt_json(wall_s_);
  m["run_t0_unix_ms"] = run_t0_unix_ms_;
  // /proc/net/snmp counts the IPv4 UDP datagrams of the whole host (its
  // network namespace), not only this swarm's: anything else sending UDP
  // meanwhile (another swarm, DNS, ...) is included. IPv6 is not counted
  // (/proc/net/snmp6); the onehost profiles use IPv4 loopback.
  const bool udp = udp_start_ && udp_end_ && udp_end_->in_datagrams >= udp_start_->in_datagrams &&
                   udp_end_->out_datagrams >= udp_start_->out_datagrams;
  m["udp_in_datagrams"] =
      udp ? nlohmann::json(udp_end_->in_datagrams - udp_start_->in_datagrams) : nlohmann::json(nullptr);
  m["udp_out_datagrams"] =
      udp ? nlohmann::json(udp_end_->out_datagrams - udp_start_->out_datagrams) : nlohmann::json(nullptr);
  // Written over the ground station's file atomically: a launcher killed here
  // leaves the ground station's metrics.json, not half of the merged one.
  if (auto written = core::write_file_atomically(path.string(), runtime::json_text(m, 2) + "\n"); !written) {
    spdlog::error("{}", written.error().message);
    exit_code = 1;
  }
  if (crashed > 0) exit_code = 1;
  if (!ground_here) {
    spdlog::info("done on host {}: {} processes, killed {}, crashed {} -> {} (the swarm's metrics.json is on host {})",
                 o_.host_index, children_.size(), killed, crashed, path.string(), o_.ground_host);
    return;
  }
  spdlog::info("done: coverage {:.1f}%, targets {}/{}, deposits sent {} applied {} rejected {}, killed {}, crashed {} -> {}",
               100.0 * m.value("coverage", 0.0), m.value("targets_found", 0), m.value("targets_total", 0),
               m.value("deposits_sent", 0), m.value("deposits_applied", 0), m.value("deposits_rejected", 0), killed,
               crashed, path.string());
}

}  // namespace pheromesh::cli
