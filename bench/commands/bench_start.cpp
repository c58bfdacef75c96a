// pheromesh bench start (bench_start.hpp).
#include "bench/commands/bench_start.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string_view>
#include <thread>

#include "launch/proc_stats.hpp"

extern char** environ;  // NOLINT: posix_spawn's environment

namespace pheromesh::cli {

const char* const kBenchStartFooter =
    "Each row starts one program `--runs` times, one after another, and reads what the kernel counted for it "
    "(wait4: user + system CPU). `/bin/true`, a process that does nothing, is the "
    "baseline of the same run; the UAV program's `--help` is its load alone (mapping and relocating its "
    "libraries, its static initialisers); the vendor rows add a DDS participant, the scenario and one tick, "
    "with no place agent and no ground station; the waiting rows give it a control key (so it waits for a start) "
    "and a big swarm's lease (5 s) and no ground station: it waits --wait seconds, then flies its tick, and the CPU "
    "that its threads ran from 1.5 s after its start to 0.5 s before its wait ends (/proc/PID/task/*/schedstat) is "
    "given per second of waiting. With --baseline BIN (another build's bin folder) its "
    "pheromesh-uav runs too, alternating with this build's, and the last column compares the medians.\n"
    "Example: pheromesh bench start scenarios/scale-100x100.textproto --runs 30 --baseline ../build-before/bin";

std::vector<StartCommand> start_commands(const std::string& uav, const BenchStartOptions& o) {
  std::vector<StartCommand> out{{"the UAV program loaded (--help)", {uav, "--help"}}};
  for (const auto& v : o.dds) {
    const std::string who = v == "fastdds" ? "a Fast DDS UAV" : "a Cyclone UAV";
    const auto argv = [&](const std::string& wait_for_start) {
      return std::vector<std::string>{uav,
                                      "--scenario",
                                      o.scenario,
                                      "--id",
                                      "0",
                                      "--dds",
                                      v,
                                      "--domain",
                                      std::to_string(o.domain),
                                      "--wait-for-places",
                                      "0",
                                      "--wait-for-start",
                                      wait_for_start,
                                      "--ticks",
                                      "1"};
    };
    StartCommand alone{who + " started alone for one tick", argv("0.1")};
    out.push_back(alone);
    if (o.wait_s <= 0) continue;
    char wait[32];
    std::snprintf(wait, sizeof wait, "%g", o.wait_s);
    StartCommand waiting{who + " waiting " + wait + " s for a start, then one tick", argv(wait)};
    waiting.argv.insert(waiting.argv.end(), {"--lease-ms", "5000"});
    // Any key will do: no ground station signs a start with it.
    waiting.env = {"PHEROMESH_CONTROL_KEY=" + std::string(64, '7')};
    waiting.waits_beside = alone.what;
    out.push_back(std::move(waiting));
  }
  return out;
}

ChildCost run_child(const std::vector<std::string>& argv, const std::vector<std::string>& env,
                    std::optional<Window> window) {
  ChildCost c;
  // This process's environment, less the names `env` sets (programs differ
  // in which of two of a name they take), then `env`.
  std::vector<char*> envp;
  const auto set_here = [&](std::string_view var) {
    const auto name = var.substr(0, var.find('=') + 1);
    return std::any_of(env.begin(), env.end(), [&](const std::string& e) { return e.rfind(name, 0) == 0; });
  };
  for (char** e = environ; *e != nullptr; ++e) {
    if (!set_here(*e)) envp.push_back(*e);
  }
  for (const auto& e : env) envp.push_back(const_cast<char*>(e.c_str()));  // NOLINT: envp of execve
  envp.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&fa, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  std::vector<char*> args;
  args.reserve(argv.size() + 1);
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));  // NOLINT: argv of execve
  args.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, args[0], &fa, nullptr, args.data(), envp.data());
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) return c;
  if (window) {
    // Read while it runs: it is reaped only below.
    const auto spawned = std::chrono::steady_clock::now();
    const auto at = [&](double s) { return spawned + std::chrono::microseconds(static_cast<int64_t>(s * 1e6)); };
    std::this_thread::sleep_until(at(window->from_s));
    const auto first = sample_cpu(pid);
    std::this_thread::sleep_until(at(window->to_s));
    const auto last = sample_cpu(pid);
    if (first && last) c.window_cpu_ms = static_cast<double>(last->cpu_ns - first->cpu_ns) / 1e6;
  }
  int status = 0;
  rusage ru{};
  if (wait4(pid, &status, 0, &ru) != pid) return c;
  c.cpu_ms = (ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) * 1e3 + (ru.ru_utime.tv_usec + ru.ru_stime.tv_usec) / 1e3;
  c.ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  return c;
}

std::optional<Window> waiting_window(double wait_s) {
  if (wait_s < 3) return std::nullopt;
  return Window{1.5, wait_s - 0.5};
}

namespace {

struct StartRow {
  StartCost cost;
  std::vector<double> cpu;
  std::string waits_beside;     // a waiting row: the `what` of its start without the wait
  std::vector<double> waiting;  // a waiting row: CPU ms per second of its window, per run
  core::SampleSummary waiting_ms;
};

std::string command_text(const std::vector<std::string>& argv) {
  std::string s = std::filesystem::path(argv[0]).filename().string();
  for (std::size_t i = 1; i < argv.size(); ++i) s += " " + argv[i];
  return s;
}

void measure_start(StartRow& row, const std::vector<std::string>& argv, const std::vector<std::string>& env,
                   std::optional<Window> window) {
  const ChildCost c = run_child(argv, env, window);
  if (!c.ok) ++row.cost.failed;
  row.cpu.push_back(c.cpu_ms);
  if (window && c.window_cpu_ms) row.waiting.push_back(*c.window_cpu_ms / (window->to_s - window->from_s));
}

void print_starts(const std::vector<StartRow>& rows, double bare_ms,
                  const std::map<std::string, double>& baseline_p50) {
  std::printf(
      "| start | build | CPU ms p50 | mean | p90 | × a process that does nothing | failed | × baseline build |\n"
      "|---|---|---|---|---|---|---|---|\n");
  for (const auto& r : rows) {
    const auto& c = r.cost;
    std::string vs = "";
    if (c.build == "this" && baseline_p50.count(c.what) != 0 && baseline_p50.at(c.what) > 0) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.2f", c.cpu_ms.p50 / baseline_p50.at(c.what));
      vs = buf;
    }
    std::printf("| %s | %s | %.1f | %.1f | %.1f | %.1f | %u | %s |\n", c.what.c_str(), c.build.c_str(), c.cpu_ms.p50,
                c.cpu_ms.mean, c.cpu_ms.p90, bare_ms > 0 ? c.cpu_ms.p50 / bare_ms : 0.0, c.failed, vs.c_str());
  }
  // Waiting: what a waiting row's UAV ran in its window, per second.
  std::map<std::string, double> baseline_waiting;
  for (const auto& r : rows) {
    if (!r.waiting.empty() && r.cost.build == "baseline") baseline_waiting[r.cost.what] = r.waiting_ms.p50;
  }
  bool header = false;
  for (const auto& r : rows) {
    if (r.waiting.empty()) continue;
    if (!header) {
      std::printf(
          "\n| waiting for the start | build | CPU ms per second of waiting: p50 | mean | p90 | × baseline build |\n"
          "|---|---|---|---|---|---|\n");
      header = true;
    }
    std::string vs;
    if (r.cost.build == "this" && baseline_waiting.count(r.cost.what) != 0 && baseline_waiting.at(r.cost.what) > 0) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.2f", r.waiting_ms.p50 / baseline_waiting.at(r.cost.what));
      vs = buf;
    }
    std::printf("| %s | %s | %.3f | %.3f | %.3f | %s |\n", r.cost.what.c_str(), r.cost.build.c_str(), r.waiting_ms.p50,
                r.waiting_ms.mean, r.waiting_ms.p90, vs.c_str());
  }
  std::printf("\ncommands (this build):\n");
  for (const auto& r : rows) {
    if (r.cost.build != "baseline") std::printf("  %s\n", r.cost.command.c_str());
  }
}

}  // namespace

int run_bench_start(const BenchStartOptions& o) {
  const std::string uav = o.programs_dir + "/pheromesh-uav";
  std::vector<std::string> builds{"this"};
  std::map<std::string, std::string> uav_of{{"this", uav}};
  if (!o.baseline.empty()) {
    const std::string other = o.baseline + "/pheromesh-uav";
    if (access(other.c_str(), X_OK) != 0) {
      std::fprintf(stderr, "bench start: --baseline %s has no pheromesh-uav to run (%s)\n", o.baseline.c_str(),
                   other.c_str());
      return 2;
    }
    builds.push_back("baseline");
    uav_of["baseline"] = other;
  }
  std::vector<StartRow> rows(1);
  rows[0].cost = {"a process that does nothing", "", "/bin/true", {}, 0};
  struct Planned {
    std::size_t row;
    std::vector<std::string> argv, env;
  };
  std::vector<Planned> plan;
  for (const auto& cmd : start_commands(uav, o)) {
    for (const auto& b : builds) {
      auto argv = cmd.argv;
      argv[0] = uav_of[b];
      std::string text = command_text(argv);
      for (const auto& e : cmd.env) text = e.substr(0, e.find('=') + 1) + "<a key> " + text;
      rows.push_back({{cmd.what, b, text, {}, 0}, {}, cmd.waits_beside});
      plan.push_back({rows.size() - 1, argv, cmd.env});
    }
  }
  std::printf("bench start: %u starts of each, one after another (%zu kinds)\n", o.runs, rows.size());
  std::fflush(stdout);
  // Round by round, so that a host that slows down mid-run slows every row alike.
  for (uint32_t i = 0; i < o.runs; ++i) {
    measure_start(rows[0], {"/bin/true"}, {}, std::nullopt);
    for (const auto& p : plan) {
      measure_start(rows[p.row], p.argv, p.env,
                    rows[p.row].waits_beside.empty() ? std::nullopt : waiting_window(o.wait_s));
    }
  }
  std::map<std::string, double> baseline_p50;
  for (auto& r : rows) {
    r.cost.cpu_ms = core::summarize(r.cpu);
    if (!r.waiting.empty()) r.waiting_ms = core::summarize(r.waiting);
    if (r.cost.build == "baseline") baseline_p50[r.cost.what] = r.cost.cpu_ms.p50;
  }
  print_starts(rows, rows[0].cost.cpu_ms.p50, baseline_p50);
  int rc = 0;
  for (const auto& r : rows) {
    if (r.cost.failed > 0) {
      std::fprintf(stderr, "bench start: %u of %u runs of `%s` did not exit 0 (run it by hand to see why)\n",
                   r.cost.failed, o.runs, r.cost.command.c_str());
      rc = 1;
    }
  }
  return rc;
}

}  // namespace pheromesh::cli
