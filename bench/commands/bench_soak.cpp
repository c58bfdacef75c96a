#include "bench_soak.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "launch/child_spawn.hpp"
#include "launch/launcher.hpp"
#include "pheromesh/core/atomic_file.hpp"
#include "pheromesh/core/scenario.hpp"
#include "launch/proc_stats.hpp"

namespace pheromesh::cli {

const char* const kBenchSoakFooter = R"(How it is measured:
  One `pheromesh run SCENARIO --uavs N --duration D --faults ...` with N chosen
  so that UAVs + place agents (x2 with standbys) + the ground station make
  --processes. Every --sample-every the bench walks /proc for the launcher and
  all its descendants and reads, per process: RSS (/proc/PID/smaps_rollup),
  open file descriptors (entries of /proc/PID/fd) and threads
  (/proc/PID/status). The role comes from the program's name: pheromesh-uav,
  pheromesh-place, pheromesh-ground, pheromesh (the launcher).
  Faults: one per --fault-every, rotating through `restart uav:K for 2s`,
  `stop place:R for 5s`, `restart place:R for 2s`, `stop uav:K for 10s` and
  `stop ground for 3s`, over distinct targets (docs/faults.md).
  Growth per hour: least-squares slope of the role's mean per process over
  the samples after --warmup, times 3600 s. A restarted process starts small
  again, which pulls its role's mean down briefly; the max column shows the
  largest single process.
Output (--out): soak.md (the summary, also printed), soak.csv (one row per
  sample and role), soak-processes.csv (one row per sample and process),
  run/ (the swarm's metrics.json and logs/), run.txt (the launcher's output).
)";

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::atomic<bool> g_interrupted{false};
void on_signal(int) { g_interrupted.store(true); }

struct ProcStat {
  pid_t pid = 0;
  std::string role;
  double rss_mib = 0;
  uint64_t fds = 0;
  uint64_t threads = 0;
};

// Parent pid from /proc/PID/stat: the field after the ")" that closes comm.
std::optional<pid_t> parent_of(pid_t pid) {
  const std::string path = "/proc/" + std::to_string(pid) + "/stat";
  const auto text = read_small_file(path.c_str());
  if (!text) return std::nullopt;
  const auto close = text->rfind(')');
  if (close == std::string::npos || close + 4 >= text->size()) return std::nullopt;
  // ") S PPID ..."
  const char* p = text->c_str() + close + 4;
  char* end = nullptr;
  const long v = std::strtol(p, &end, 10);
  if (end == p) return std::nullopt;
  return static_cast<pid_t>(v);
}

std::string role_of(pid_t pid) {
  const std::string path = "/proc/" + std::to_string(pid) + "/cmdline";
  const auto text = read_small_file(path.c_str());
  if (!text || text->empty()) return "";
  const std::string argv0 = fs::path(text->c_str()).filename().string();
  if (argv0 == "pheromesh-uav") return "uav";
  if (argv0 == "pheromesh-place") return "place";
  if (argv0 == "pheromesh-ground") return "ground";
  if (argv0 == "pheromesh") return "launcher";
  return "";  // a helper of the launcher (e.g. a shell); not counted
}

uint64_t count_fds(pid_t pid) {
  const std::string path = "/proc/" + std::to_string(pid) + "/fd";
  DIR* d = opendir(path.c_str());
  if (d == nullptr) return 0;
  uint64_t n = 0;
  while (const dirent* e = readdir(d)) {
    if (e->d_name[0] != '.') ++n;
  }
  closedir(d);
  return n;
}

// The launcher and every descendant of it, with their figures.
std::vector<ProcStat> sample_tree(pid_t root) {
  std::map<pid_t, pid_t> parent;
  if (DIR* d = opendir("/proc")) {
    while (const dirent* e = readdir(d)) {
      char* end = nullptr;
      const long pid = std::strtol(e->d_name, &end, 10);
      if (end == e->d_name || *end != '\0') continue;
      if (auto pp = parent_of(static_cast<pid_t>(pid))) parent[static_cast<pid_t>(pid)] = *pp;
    }
    closedir(d);
  }
  std::vector<ProcStat> out;
  for (const auto& [pid, pp] : parent) {
    pid_t up = pid;
    bool ours = false;
    for (int depth = 0; depth < 16 && up > 1; ++depth) {
      if (up == root) {
        ours = true;
        break;
      }
      auto it = parent.find(up);
      if (it == parent.end()) break;
      up = it->second;
    }
    if (!ours) continue;
    ProcStat s;
    s.pid = pid;
    s.role = role_of(pid);
    if (s.role.empty()) continue;
    const auto sample = sample_process(pid);
    if (!sample || !sample->rss_mib) continue;  // gone or a zombie
    s.rss_mib = *sample->rss_mib;
    s.threads = sample->threads.value_or(0);
    s.fds = count_fds(pid);
    out.push_back(std::move(s));
  }
  return out;
}

struct RoleSample {
  double t_s = 0;
  std::size_t count = 0;
  double rss_mean = 0, rss_max = 0, rss_sum = 0;
  double fds_mean = 0, fds_max = 0;
  double threads_mean = 0, threads_max = 0;
};

RoleSample aggregate(double t_s, const std::vector<ProcStat>& procs, const std::string& role) {
  RoleSample r;
  r.t_s = t_s;
  for (const auto& p : procs) {
    if (p.role != role) continue;
    ++r.count;
    r.rss_sum += p.rss_mib;
    r.rss_max = std::max(r.rss_max, p.rss_mib);
    r.fds_mean += static_cast<double>(p.fds);
    r.fds_max = std::max(r.fds_max, static_cast<double>(p.fds));
    r.threads_mean += static_cast<double>(p.threads);
    r.threads_max = std::max(r.threads_max, static_cast<double>(p.threads));
  }
  if (r.count > 0) {
    const auto n = static_cast<double>(r.count);
    r.rss_mean = r.rss_sum / n;
    r.fds_mean /= n;
    r.threads_mean /= n;
  }
  return r;
}

std::string fmt(double v, int precision = 1) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", precision, v);
  return buf;
}

std::string signed_fmt(double v, int precision = 1) { return (v >= 0 ? "+" : "") + fmt(v, precision); }

const char* const kRoles[] = {"uav", "place", "ground", "launcher"};

std::string summary_markdown(const BenchSoakOptions& o, double duration_s, double warmup_s, uint32_t uavs,
                             uint32_t regions, const std::string& faults, int exit_code, double wall_s,
                             const std::map<std::string, std::vector<RoleSample>>& series) {
  std::ostringstream md;
  md << "# pheromesh bench soak\n\n*Scenario:* " << o.scenario << "  \n*Swarm:* " << uavs << " UAVs, " << regions
     << " place agents, 1 ground station (" << o.processes << " processes + the launcher), " << o.dds << ", "
     << fmt(o.rate_hz, 1) << " Hz, lease " << o.lease_ms << " ms, domain " << o.domain << "  \n*Ran:* "
     << fmt(wall_s, 0) << " s of " << fmt(duration_s, 0) << " s asked; launcher exit code " << exit_code
     << "  \n*Faults:* " << (faults.empty() ? std::string("none") : faults) << "  \n*Sampled:* every "
     << o.sample_every << "; growth fitted after " << fmt(warmup_s, 0) << " s\n\n";
  md << "| role | procs start/end | RSS/proc start | end | max (one proc) | growth/h | fds/proc start | end | max | "
        "growth/h | threads/proc start | end | max | growth/h |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const char* role : kRoles) {
    auto it = series.find(role);
    if (it == series.end() || it->second.empty()) continue;
    const auto& s = it->second;
    std::vector<double> t, rss, fds, thr;
    double rss_max = 0, fds_max = 0, thr_max = 0;
    for (const auto& r : s) {
      rss_max = std::max(rss_max, r.rss_max);
      fds_max = std::max(fds_max, r.fds_max);
      thr_max = std::max(thr_max, r.threads_max);
      if (r.t_s < warmup_s || r.count == 0) continue;
      t.push_back(r.t_s);
      rss.push_back(r.rss_mean);
      fds.push_back(r.fds_mean);
      thr.push_back(r.threads_mean);
    }
    const auto per_h = [&](const std::vector<double>& y) {
      return t.size() < 2 ? std::string("–") : signed_fmt(3600.0 * linear_slope(t.data(), y.data(), t.size()), 2);
    };
    const RoleSample& a = s.front();
    const RoleSample& b = s.back();
    md << "| " << role << " | " << a.count << " / " << b.count << " | " << fmt(a.rss_mean) << " MiB | "
       << fmt(b.rss_mean) << " MiB | " << fmt(rss_max) << " MiB | " << per_h(rss) << " MiB | " << fmt(a.fds_mean)
       << " | " << fmt(b.fds_mean) << " | " << fmt(fds_max, 0) << " | " << per_h(fds) << " | "
       << fmt(a.threads_mean) << " | " << fmt(b.threads_mean) << " | " << fmt(thr_max, 0) << " | " << per_h(thr)
       << " |\n";
  }
  md << "\nStart = first sample, end = last sample before the swarm's own shutdown; per-process figures are the "
        "role's mean. Growth/h extrapolates the run's slope to an hour: for a run shorter than an hour it is a "
        "rate, not a measurement of an hour.\n\n## How it is measured\n\n```\n"
     << kBenchSoakFooter << "```\n";
  return md.str();
}

}  // namespace

double parse_duration_s(const std::string& text) {
  if (text.empty()) return -1;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || !std::isfinite(v) || v < 0) return -1;
  const std::string unit(end);
  if (unit.empty() || unit == "s") return v;
  if (unit == "ms") return v / 1000.0;
  if (unit == "m" || unit == "min") return v * 60.0;
  if (unit == "h") return v * 3600.0;
  return -1;
}

double linear_slope(const double* x, const double* y, std::size_t n) {
  if (n < 2) return 0;
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < n; ++i) {
    mx += x[i];
    my += y[i];
  }
  mx /= static_cast<double>(n);
  my /= static_cast<double>(n);
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
  }
  return sxx > 0 ? sxy / sxx : 0;
}

std::string soak_fault_schedule(double duration_s, double every_s, uint32_t uavs, uint32_t regions) {
  if (every_s <= 0 || uavs == 0 || regions == 0) return "";
  std::string out;
  uint32_t k = 0;
  // The last period is left free, so the last fault ends before the swarm does.
  for (double t = every_s; t + every_s <= duration_s + 1e-9; t += every_s, ++k) {
    const std::string at = " @" + std::to_string(static_cast<long long>(std::llround(t))) + "s";
    const uint32_t uav = (k * 7U + 1U) % uavs;  // spread over the swarm
    const uint32_t place = (k / 5U) % regions;
    std::string e;
    switch (k % 5U) {
      case 0: e = "restart uav:" + std::to_string(uav) + at + " for 2s"; break;
      case 1: e = "stop place:" + std::to_string(place) + at + " for 5s"; break;
      case 2: e = "restart place:" + std::to_string(place) + at + " for 2s"; break;
      case 3: e = "stop uav:" + std::to_string(uav) + at + " for 10s"; break;
      default: e = "stop ground" + at + " for 3s"; break;
    }
    out += (out.empty() ? "" : "; ") + e;
  }
  return out;
}

namespace {

// The soak as the options and the scenario give it.
struct SoakPlan {
  double duration_s = 0, every_s = 0, sample_s = 0, warmup_s = 0;
  uint32_t regions = 0, places = 0, uavs = 0;
  std::string faults;  // --faults of the run
};

// The plan, or the exit code (the reason printed).
std::variant<SoakPlan, int> plan_soak(const BenchSoakOptions& o) {
  SoakPlan p;
  p.duration_s = parse_duration_s(o.duration);
  p.every_s = o.fault_every == "0" ? 0 : parse_duration_s(o.fault_every);
  p.sample_s = parse_duration_s(o.sample_every);
  p.warmup_s = parse_duration_s(o.warmup);
  if (p.duration_s <= 0 || p.every_s < 0 || p.sample_s <= 0 || p.warmup_s < 0) {
    std::fprintf(stderr, "bench soak: --duration, --fault-every, --sample-every and --warmup take e.g. 1h, 10m, 60s, 500ms\n");
    return 2;
  }
  auto scenario = core::load_scenario(o.scenario);
  if (!scenario) {
    std::fprintf(stderr, "%s\n", scenario.error().message.c_str());
    return 2;
  }
  p.regions = scenario->geometry().region_count();
  p.places = p.regions * (scenario->standby ? 2U : 1U);
  if (o.processes < p.places + 2) {
    std::fprintf(stderr,
                 "bench soak: --processes %u leaves no UAV: the scenario has %u place agents and a ground station\n",
                 o.processes, p.places);
    return 2;
  }
  p.uavs = o.processes - p.places - 1;
  p.faults = soak_fault_schedule(p.duration_s, p.every_s, p.uavs, p.regions);
  return p;
}

// The `pheromesh run` command line of the soak.
std::vector<std::string> soak_run_args(const BenchSoakOptions& o, const SoakPlan& p, const std::string& exe,
                                       const fs::path& dir) {
  std::vector<std::string> args{exe,
                                "run",
                                o.scenario,
                                "--uavs",
                                std::to_string(p.uavs),
                                "--rate",
                                fmt(o.rate_hz, 3),
                                "--duration",
                                fmt(p.duration_s, 1),
                                "--lease-ms",
                                std::to_string(o.lease_ms),
                                "--dds",
                                o.dds,
                                "--domain",
                                std::to_string(o.domain),
                                "--out",
                                (dir / "run").string(),
                                "--progress",
                                "30"};
  if (!p.faults.empty()) {
    args.emplace_back("--faults");
    args.push_back(p.faults);
  }
  std::istringstream extra(o.extra);
  for (std::string w; extra >> w;) args.push_back(w);
  return args;
}

// What the sampling saw: per role over time, every process's rows, the last
// sample's time.
struct SoakSeries {
  std::map<std::string, std::vector<RoleSample>> roles;
  std::string proc_csv = "t_s,role,pid,rss_mib,fds,threads\n";
  double last_t = 0;
  std::size_t max_uavs_seen = 0;
  bool ended = false;
};

// One sample of the launcher's tree at `t` [s] into `s` (none once the swarm shuts down).
void sample_soak(pid_t pid, double t, bool forwarded, SoakSeries& s) {
  const auto procs = sample_tree(pid);
  // The swarm's own shutdown at the end (UAVs end their flights, then the
  // place agents stop) is not a state worth fitting: sampling ends when
  // the UAVs drop below 80 % of the most seen, which one fault never does
  // in a swarm of ten or more.
  std::size_t uavs_now = 0;
  for (const auto& p : procs) uavs_now += p.role == "uav" ? 1U : 0U;
  s.max_uavs_seen = std::max(s.max_uavs_seen, uavs_now);
  s.ended = s.ended || forwarded ||
            (s.max_uavs_seen > 0 && static_cast<double>(uavs_now) < 0.8 * static_cast<double>(s.max_uavs_seen));
  const bool shutting_down = s.ended;
  if (procs.empty() || shutting_down) return;
  s.last_t = t;
  for (const auto& p : procs) {
    s.proc_csv += fmt(t, 1) + "," + p.role + "," + std::to_string(p.pid) + "," + fmt(p.rss_mib, 2) + "," +
                  std::to_string(p.fds) + "," + std::to_string(p.threads) + "\n";
  }
  std::string line;
  for (const char* role : kRoles) {
    const RoleSample r = aggregate(t, procs, role);
    s.roles[role].push_back(r);
    if (r.count > 0) {
      line += std::string(line.empty() ? "" : "  ") + role + " " + std::to_string(r.count) + "x " + fmt(r.rss_mean) +
              " MiB " + fmt(r.fds_mean, 0) + " fd " + fmt(r.threads_mean, 0) + " thr";
    }
  }
  std::printf("[%6.0f s] %s\n", t, line.c_str());
  std::fflush(stdout);
}

// Samples the launcher `pid` every plan.sample_s until it exits; its wait status.
int watch_soak(pid_t pid, const BenchSoakOptions& o, const SoakPlan& plan, SoakSeries& s) {
  const auto start = Clock::now();
  // The launcher bounds its own run by ticks; this only guards against a hung
  // one. Generous: on an overloaded host ticks run late and the swarm's
  // flight takes longer than --duration (measured: 200 processes on 2 shared
  // cores flew 600 s worth of ticks in ~1000 s).
  const auto deadline = start + std::chrono::duration<double>(2.0 * plan.duration_s + 0.5 * o.processes + 300.0);
  auto next_sample = start + std::chrono::seconds(2);
  int status = 0;
  bool forwarded = false;
  for (;;) {
    if (waitpid(pid, &status, WNOHANG) == pid) return status;
    const auto now = Clock::now();
    if ((g_interrupted.load() || now > deadline) && !forwarded) {
      kill(pid, SIGINT);  // the launcher stops its swarm in order and writes metrics.json
      forwarded = true;
    }
    if (now >= next_sample) {
      sample_soak(pid, std::chrono::duration<double>(now - start).count(), forwarded, s);
      // A sample that took longer than the period (a loaded host) is not
      // followed by a burst of catch-up samples.
      next_sample = std::max(
          next_sample + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(plan.sample_s)),
          Clock::now());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
}

std::string soak_role_csv(const std::map<std::string, std::vector<RoleSample>>& roles) {
  std::string csv = "t_s,role,count,rss_mib_mean,rss_mib_max,rss_mib_sum,fds_mean,fds_max,threads_mean,threads_max\n";
  for (const char* role : kRoles) {
    auto it = roles.find(role);
    if (it == roles.end()) continue;
    for (const auto& r : it->second) {
      csv += fmt(r.t_s, 1) + "," + role + "," + std::to_string(r.count) + "," + fmt(r.rss_mean, 2) + "," +
             fmt(r.rss_max, 2) + "," + fmt(r.rss_sum, 1) + "," + fmt(r.fds_mean, 2) + "," + fmt(r.fds_max, 0) + "," +
             fmt(r.threads_mean, 2) + "," + fmt(r.threads_max, 0) + "\n";
    }
  }
  return csv;
}

// Starts the launcher with its output on `fd` (closed here); its pid, or -1
// (the reason printed). SIGINT and SIGTERM end the soak in order from now on.
pid_t start_soak(const std::string& exe, const std::vector<std::string>& args, int fd) {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  const pid_t pid = spawn_logged_child(exe, args, fd, /*default_signals=*/true);
  if (pid < 0) std::fprintf(stderr, "fork failed: %s\n", std::strerror(errno));
  close(fd);
  return pid;
}

}  // namespace

int run_bench_soak(const BenchSoakOptions& o) {
  const auto planned = plan_soak(o);
  if (const int* rc = std::get_if<int>(&planned)) return *rc;
  const SoakPlan& plan = std::get<SoakPlan>(planned);
  const fs::path dir(o.out_dir);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    std::fprintf(stderr, "cannot create %s: %s\n", o.out_dir.c_str(), ec.message().c_str());
    return 5;
  }
  const std::string exe = executable_dir() + "/pheromesh";
  const std::vector<std::string> args = soak_run_args(o, plan, exe, dir);
  const std::string log = (dir / "run.txt").string();
  const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    std::fprintf(stderr, "cannot write %s: %s\n", log.c_str(), std::strerror(errno));
    return 5;
  }
  std::printf(
      "bench soak: %u UAVs + %u place agents + 1 ground station for %.0f s, a fault every %.0f s, sampled every %.0f s "
      "-> %s\n",
      plan.uavs, plan.places, plan.duration_s, plan.every_s, plan.sample_s, o.out_dir.c_str());
  std::fflush(stdout);
  const pid_t pid = start_soak(exe, args, fd);
  if (pid < 0) return 5;

  SoakSeries series;
  const int status = watch_soak(pid, o, plan, series);
  const int exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  const std::string role_csv = soak_role_csv(series.roles);
  const std::string md = summary_markdown(o, plan.duration_s, plan.warmup_s, plan.uavs, plan.places, plan.faults,
                                          exit_code, series.last_t, series.roles);
  for (const auto& [name, text] : {std::pair<std::string, const std::string&>{"soak.md", md},
                                   {"soak.csv", role_csv},
                                   {"soak-processes.csv", series.proc_csv}}) {
    if (auto w = core::write_file_atomically((dir / name).string(), text); !w) {
      std::fprintf(stderr, "%s\n", w.error().message.c_str());
      return 5;
    }
  }
  std::printf("\n%s", md.c_str());
  if (g_interrupted.load()) return 130;
  return exit_code == 0 ? 0 : 1;
}

}  // namespace pheromesh::cli
