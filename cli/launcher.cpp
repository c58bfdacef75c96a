#include "launcher.hpp"

#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <sys/prctl.h>
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

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/console/control.hpp"
#include "pheromesh/console/server.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/runtime/process.hpp"

namespace pheromesh::cli {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

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

void Launcher::spawn(const std::string& role, uint32_t index, const std::vector<std::string>& extra_args) {
  ChildProcess c;
  c.role = role;
  c.index = index;
  c.name = role == "ground" ? "ground" : role + "-" + std::to_string(index);
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
  if (o_.uavs > 0) args.insert(args.end(), {"--uavs", std::to_string(o_.uavs)});
  if (o_.seed > 0) args.insert(args.end(), {"--seed", std::to_string(o_.seed)});
  if (o_.rate_hz > 0) args.insert(args.end(), {"--rate", std::to_string(o_.rate_hz)});
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  const std::string log_path = (fs::path(o_.out_dir) / "logs" / (c.name + ".log")).string();

  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(std::string("fork failed: ") + std::strerror(errno));
  if (pid == 0) {
    // Child: own process group (the launcher orders the shutdown), die with
    // the launcher, output to its log file (the ground station also to ours).
    setpgid(0, 0);
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) _exit(127);
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
  children_.push_back(std::move(c));
}

void Launcher::reap() {
  for (auto& c : children_) {
    if (!c.running) continue;
    int status = 0;
    const pid_t r = waitpid(c.pid, &status, WNOHANG);
    if (r != c.pid) continue;
    c.running = false;
    if (WIFEXITED(status)) c.exit_code = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) c.term_signal = WTERMSIG(status);
    if (c.crashed()) {
      spdlog::error("{} (pid {}) {} — see {}/logs/{}.log", c.name, c.pid, c.describe(), o_.out_dir, c.name);
    } else if (c.killed_on_purpose) {
      spdlog::info("{} (pid {}) {}", c.name, c.pid, c.describe());
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
    if (c->running) return "error " + name + " is running; kill it first";
    const auto flown = std::chrono::duration<double>(now - t0_ - paused_total_).count();
    const auto remaining = static_cast<int64_t>(ticks_) - static_cast<int64_t>(flown * rate_);
    if (remaining < 1) return "error the run is over for " + name;
    const uint32_t life = ++lives_[index];
    // Deposits of each life are numbered above the earlier lives' (place
    // agents drop sequence numbers they have seen).
    spawn("uav", index, {"--id", std::to_string(index), "--ticks", std::to_string(remaining), "--seq-base",
                         std::to_string(life << 24U)});
    ChildProcess* fresh = find(name);
    spdlog::warn("console: restarted {} (pid {}) for its remaining {} ticks", name, fresh->pid, remaining);
    return "ok restarted " + name + " (pid " + std::to_string(fresh->pid) + ") for " + std::to_string(remaining) + " ticks";
  }
  return "error cannot " + v + " a " + r;
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

int Launcher::run() {
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
  auto plan = parse_dds_plan(o_.dds, bus::available_vendors());
  if (!plan) {
    spdlog::error("{}", plan.error().message);
    return 2;
  }
  plan_ = std::move(plan).value();
  std::vector<KillEvent> kills;
  if (!o_.kill_spec.empty()) {
    auto k = parse_kill_spec(o_.kill_spec);
    if (!k) {
      spdlog::error("{}", k.error().message);
      return 2;
    }
    kills = std::move(k).value();
    for (const auto& e : kills) {
      const uint32_t n = e.role == "uav" ? uavs : regions;
      if (e.index >= n) {
        spdlog::error("--kill: {} does not exist (this run has {} {}s)", e.process_name(), n, e.role);
        return 2;
      }
    }
  }
  bin_dir_ = executable_dir();
  for (const char* exe : {"pheromesh-uav", "pheromesh-place", "pheromesh-ground"}) {
    if (access((bin_dir_ + "/" + exe).c_str(), X_OK) != 0) {
      spdlog::error("cannot find {} next to pheromesh in {}", exe, bin_dir_);
      return 3;
    }
  }
  fs::create_directories(fs::path(o_.out_dir) / "logs");
  fs::remove(fs::path(o_.out_dir) / "metrics.json");
  spdlog::info("run '{}' ({}): {} place agents, {} uavs, {} ticks, {} clock{}, over {} (domain {}, profile {}); logs in {}/logs",
               s.name, o_.scenario, regions, uavs, ticks, o_.clock,
               o_.clock == "lockstep" ? "" : fmt::format(" at {:.1f} Hz", rate), plan_.describe(), o_.domain, o_.dds_profile,
               o_.out_dir);

  runtime::install_shutdown_handlers();
  ticks_ = ticks;
  rate_ = rate;
  // Every process of this swarm shares a fresh control key: only this
  // ground station can sign commands they act on (docs/console.md).
  setenv(console::kControlKeyEnv, console::random_control_key_hex().c_str(), 1);
  std::vector<std::string> ground_args{"--out", o_.out_dir, "--progress", std::to_string(o_.progress_s), "--ticks",
                                       std::to_string(ticks), "--expect-uavs", std::to_string(uavs)};
  std::string token;
  if (o_.http_port) {
    int sv[2];
    if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0) {
      throw std::runtime_error(std::string("socketpair: ") + std::strerror(errno));
    }
    ctl_fd_ = sv[0];
    child_ctl_fd_ = sv[1];
    token = console::random_token();
    setenv("PHEROMESH_CONSOLE_TOKEN", token.c_str(), 1);
    const std::string record = o_.no_record ? "" : !o_.record.empty() ? o_.record : (fs::path(o_.out_dir) / "console.phrec").string();
    ground_args.insert(ground_args.end(), {"--http", std::to_string(*o_.http_port), "--http-bind", o_.http_bind,
                                           "--launcher-fd", "3"});
    if (!record.empty()) ground_args.insert(ground_args.end(), {"--record", record});
  }
  spawn("ground", 0, ground_args);
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
  for (uint32_t r = 0; r < regions; ++r) spawn("place", r, {"--region", std::to_string(r)});
  for (uint32_t u = 0; u < uavs; ++u) spawn("uav", u, {"--id", std::to_string(u), "--ticks", std::to_string(ticks)});
  const auto t0 = Clock::now();
  t0_ = t0;
  // Generous bound on the UAV phase: the run itself, discovery, and slack for
  // a loaded machine. UAVs still flying then are stopped (and reported).
  // Lockstep runs as fast as the slowest process; allow 0.5 s per tick.
  const double expected_s = o_.clock == "lockstep" ? 0.5 * ticks : ticks / rate * 2.0;
  const auto uav_deadline =
      t0 + std::chrono::milliseconds(static_cast<int64_t>(1000.0 * expected_s)) + std::chrono::seconds(45);
  std::size_t next_kill = 0;
  bool interrupted = false;
  while (any_running("uav")) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    reap();
    serve_control();
    const auto now = Clock::now();
    while (next_kill < kills.size() && now - t0 >= kills[next_kill].at) {
      const KillEvent& e = kills[next_kill++];
      ChildProcess* c = find(e.process_name());
      if (c != nullptr && c->running) {
        spdlog::warn("fault injection: SIGKILL to {} (pid {}) at {} ms", c->name, c->pid, e.at.count());
        c->killed_on_purpose = true;
        kill(c->pid, SIGKILL);
      } else {
        spdlog::warn("fault injection: {} is not running at {} ms; nothing to kill", e.process_name(), e.at.count());
      }
    }
    if (runtime::shutdown_requested() && !interrupted) {
      spdlog::warn("interrupted: stopping the swarm");
      interrupted = true;
      stop_role("uav", std::chrono::seconds(10));
    }
    const auto paused_for = paused_total_ + (paused_since_ ? now - *paused_since_ : Clock::duration{});
    if (now > uav_deadline + paused_for) {
      spdlog::error("uavs still flying long after the expected end; stopping them");
      stop_role("uav", std::chrono::seconds(10));
    }
  }
  spdlog::info("all uavs ended; stopping place agents");
  stop_role("place", std::chrono::seconds(15));
  stop_role("ground", std::chrono::seconds(15));
  int exit_code = 0;
  finish_metrics(exit_code);
  clean_fastdds_shm();
  return interrupted ? 130 : exit_code;
}

void Launcher::clean_fastdds_shm() const {
  // Our one-host Fast DDS profiles are UDP-only and leave nothing behind. With
  // any other profile Fast DDS may use shared memory, whose files a killed
  // process leaves in /dev/shm: remove those of dead processes.
  if (o_.dds_profile == "onehost" || o_.dds_profile == "onehost-unicast") return;
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
  for (const auto& c : children_) {
    killed += c.killed_on_purpose ? 1 : 0;
    crashed += c.crashed() ? 1 : 0;
    procs.push_back(
        {{"name", c.name}, {"pid", c.pid}, {"dds", c.dds}, {"status", c.describe()}, {"crashed", c.crashed()}});
  }
  const fs::path path = fs::path(o_.out_dir) / "metrics.json";
  nlohmann::json m;
  std::ifstream in(path);
  if (in) {
    try {
      in >> m;
    } catch (const std::exception& e) {
      spdlog::error("{} is not valid JSON: {}", path.string(), e.what());
    }
  }
  if (m.is_null()) {
    spdlog::error("the ground station left no {}", path.string());
    exit_code = 1;
    m = nlohmann::json::object();
  }
  m["processes_killed"] = killed;
  m["processes_crashed"] = crashed;
  m["processes"] = procs;
  m["dds"] = plan_.describe();
  std::ofstream(path) << m.dump(2) << "\n";
  if (crashed > 0) exit_code = 1;
  spdlog::info("done: coverage {:.1f}%, targets {}/{}, deposits sent {} applied {} rejected {}, killed {}, crashed {} -> {}",
               100.0 * m.value("coverage", 0.0), m.value("targets_found", 0), m.value("targets_total", 0),
               m.value("deposits_sent", 0), m.value("deposits_applied", 0), m.value("deposits_rejected", 0), killed,
               crashed, path.string());
}

}  // namespace pheromesh::cli
