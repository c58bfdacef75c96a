// pheromesh bench start (bench_start.hpp).
#include "bench/commands/bench_start.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <map>

extern char** environ;  // NOLINT: posix_spawn's environment

namespace pheromesh::cli {

const char* const kBenchStartFooter =
    "Each row starts one program `--runs` times, one after another, and reads what the kernel counted for it "
    "(wait4: user + system CPU). `/bin/true`, a process that does nothing, is the "
    "baseline of the same run; the UAV program's `--help` is its load alone (mapping and relocating its "
    "libraries, its static initialisers); the vendor rows add a DDS participant, the scenario and one tick, "
    "with no place agent and no ground station. With --baseline BIN (another build's bin folder) its "
    "pheromesh-uav runs too, alternating with this build's, and the last column compares the medians.\n"
    "Example: pheromesh bench start scenarios/scale-100x100.textproto --runs 30 --baseline ../build-before/bin";

std::vector<StartCommand> start_commands(const std::string& uav, const BenchStartOptions& o) {
  std::vector<StartCommand> out{{"the UAV program loaded (--help)", {uav, "--help"}}};
  for (const auto& v : o.dds) {
    out.push_back({std::string(v == "fastdds" ? "a Fast DDS" : "a Cyclone") + " UAV started alone for one tick",
                   {uav, "--scenario", o.scenario, "--id", "0", "--dds", v, "--domain", std::to_string(o.domain),
                    "--wait-for-places", "0", "--wait-for-start", "0.1", "--ticks", "1"}});
  }
  return out;
}

ChildCost run_child(const std::vector<std::string>& argv) {
  ChildCost c;
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&fa, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  std::vector<char*> args;
  args.reserve(argv.size() + 1);
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));  // NOLINT: argv of execve
  args.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, args[0], &fa, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) return c;
  int status = 0;
  rusage ru{};
  if (wait4(pid, &status, 0, &ru) != pid) return c;
  c.cpu_ms = (ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) * 1e3 + (ru.ru_utime.tv_usec + ru.ru_stime.tv_usec) / 1e3;
  c.ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  return c;
}

namespace {

struct StartRow {
  StartCost cost;
  std::vector<double> cpu;
};

std::string command_text(const std::vector<std::string>& argv) {
  std::string s = std::filesystem::path(argv[0]).filename().string();
  for (std::size_t i = 1; i < argv.size(); ++i) s += " " + argv[i];
  return s;
}

void measure_start(StartRow& row, const std::vector<std::string>& argv) {
  const ChildCost c = run_child(argv);
  if (!c.ok) ++row.cost.failed;
  row.cpu.push_back(c.cpu_ms);
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
  std::vector<std::pair<std::size_t, std::vector<std::string>>> plan;  // row, argv
  for (const auto& cmd : start_commands(uav, o)) {
    for (const auto& b : builds) {
      auto argv = cmd.argv;
      argv[0] = uav_of[b];
      rows.push_back({{cmd.what, b, command_text(argv), {}, 0}, {}});
      plan.emplace_back(rows.size() - 1, argv);
    }
  }
  std::printf("bench start: %u starts of each, one after another (%zu kinds)\n", o.runs, rows.size());
  std::fflush(stdout);
  // Round by round, so that a host that slows down mid-run slows every row alike.
  for (uint32_t i = 0; i < o.runs; ++i) {
    measure_start(rows[0], {"/bin/true"});
    for (const auto& [row, argv] : plan) measure_start(rows[row], argv);
  }
  std::map<std::string, double> baseline_p50;
  for (auto& r : rows) {
    r.cost.cpu_ms = core::summarize(r.cpu);
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
