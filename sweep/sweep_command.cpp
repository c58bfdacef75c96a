#include "sweep_command.hpp"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>
#include <vector>

#include "launch/child_spawn.hpp"
#include "experiments/flight.hpp"
#include "pheromesh/core/atomic_file.hpp"
#include "pheromesh/core/simulator.hpp"
#include "pheromesh/report/report.hpp"
#include "cli/sim_command.hpp"
#include "sweep_grid.hpp"
#include "sweep_report.hpp"

namespace pheromesh::cli {

const char* const kSweepFooter = R"(GRID
  --set PATH=V1,V2,...   the values one field takes (a single value is a fixed override);
                         repeatable: every combination of the lists is run. A comma inside
                         double quotes belongs to the value: --set 'name="a,b",c' is two values
  --seeds 1-20           seeds and ranges, comma-separated: 1-20, 1,5,9, 1-3,10
  Every combination is loaded and validated like a file before any run starts;
  a refused one is named with its --set PATH=VALUE. run.seed comes from --seeds.

OUTPUT (OUT, default out/sweeps/<scenario name>)
  sweep.json, scenario.textproto   the sweep's definition (a re-run must match it)
  runs/<cNNN-sSEED>/metrics.json   one per run, as `pheromesh sim` writes it
  runs.csv      one row per run: every parameter, the seed, every scalar metric
  summary.csv   per combination and metric: n, mean, sd, 95 % interval (Student t)
  plots/*.svg   each key metric against each swept parameter, mean with its interval
  sweep.md      the command, the grid, the summary table, links to the plots
  Running the same command again in the same OUT skips the runs that finished (an
  interrupted sweep resumes); a different grid, seed list or scenario file is refused.

Examples:
  pheromesh sweep small-test --set shao.aco.alpha=0.5,1,2 --seeds 1-20 --ticks 200
  pheromesh sweep small-test --set shao.aco.alpha=1,2 --set swarm.uavs=2,4,8 --seeds 1-10 --jobs 2
  pheromesh sweep small-test --set shao.aco.beta=1,3 --seeds 1-5 --distributed --distributed-sample 2
                                       also fly 2 of the runs as processes (lockstep) and check them
  docs/sweeps.md has the details.
)";

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream o;
  o << f.rdbuf();
  return o.str();
}

// The run's metrics.json, or a discarded value when it is absent or not a
// JSON object (a run whose folder has none has not finished).
nlohmann::json finished_metrics(const fs::path& run_dir) {
  std::error_code ec;
  if (!fs::is_regular_file(run_dir / "metrics.json", ec)) return nlohmann::json::value_t::discarded;
  auto j = nlohmann::json::parse(slurp(run_dir / "metrics.json"), nullptr, false);
  if (!j.is_object()) return nlohmann::json::value_t::discarded;
  return j;
}

// A progress bar on a terminal; a plain line every tenth of the runs
// otherwise (logs, CI).
class Progress {
 public:
  Progress(std::size_t total, bool quiet)
      : total_(total), quiet_(quiet), tty_(isatty(STDERR_FILENO) != 0), t0_(Clock::now()) {}

  void done_one() {
    std::lock_guard lock(mutex_);
    ++done_;
    if (quiet_) return;
    const std::size_t every = std::max<std::size_t>(1, total_ / 10);
    if (!tty_ && done_ % every != 0 && done_ != total_) return;
    // A terminal is redrawn ten times a second at most: short runs finish
    // by the thousand.
    const auto now = Clock::now();
    if (tty_ && done_ != total_ && now - last_draw_ < std::chrono::milliseconds(100)) return;
    last_draw_ = now;
    const double s = seconds_since(t0_);
    const double rate = s > 0 ? static_cast<double>(done_) / s : 0.0;
    const int width = 30;
    const int filled = total_ > 0 ? static_cast<int>(width * done_ / total_) : width;
    char eta[32] = "";
    if (rate > 0 && done_ < total_)
      std::snprintf(eta, sizeof eta, ", %.0f s left", static_cast<double>(total_ - done_) / rate);
    std::fprintf(stderr, "%ssweep [%.*s%*s] %zu/%zu runs, %.1f runs/s%s%s", tty_ ? "\r" : "", filled,
                 "##############################", width - filled, "", done_, total_, rate, eta,
                 tty_ ? "\x1b[K" : "\n");
    if (tty_ && done_ == total_) std::fputc('\n', stderr);
    std::fflush(stderr);
  }

 private:
  std::mutex mutex_;
  std::size_t total_, done_ = 0;
  bool quiet_, tty_;
  Clock::time_point t0_, last_draw_{};
};

struct Plan {
  std::string scenario_path;
  std::string scenario_name;
  std::vector<sweep::Parameter> params;
  std::vector<uint64_t> seeds;
  std::vector<sweep::Cell> cells;
  std::vector<sweep::Run> runs;
  fs::path out;
};

// Loads one run's scenario (the cell's overrides and the seed), validated.
core::Result<core::ScenarioConfig> load_run(const Plan& p, const sweep::Cell& cell, uint64_t seed) {
  return load_overridden(p.scenario_path, sweep::cell_flags(p.params, cell, seed));
}

// One simulation of a loaded run, with the scenario's own fault lines.
struct Simulated {
  std::unique_ptr<core::Simulator> sim;
  nlohmann::json metrics;
};
core::Result<Simulated> simulate_run(const core::ScenarioConfig& s) {
  Simulated out;
  out.sim = std::make_unique<core::Simulator>(s);
  if (!s.faults.empty()) {
    if (auto notes = out.sim->set_faults(s.faults, s.standby); !notes) return notes.error();
  }
  const auto t0 = Clock::now();
  out.sim->run();
  out.metrics = sim_metrics(*out.sim, seconds_since(t0));
  return out;
}

// Every combination is loaded before any run starts: a refused value is
// named now, not after an hour of runs.
int check_cells(const Plan& p) {
  for (const auto& c : p.cells) {
    auto s = load_run(p, c, p.seeds.front());
    const std::string which = "combination " + std::to_string(c.index) + " (" + sweep::describe_cell(p.params, c) + ")";
    if (!s) {
      std::fprintf(stderr, "%s is refused:\n%s\n", which.c_str(), s.error().message.c_str());
      return 2;
    }
    if (!s->faults.empty()) {
      core::Simulator probe(s.value());
      if (auto notes = probe.set_faults(s->faults, s->standby); !notes) {
        std::fprintf(stderr, "%s: the scenario's faults: %s\n", which.c_str(), notes.error().message.c_str());
        return 2;
      }
    }
  }
  return 0;
}

// OUT: new, or the folder of the same sweep (then its finished runs are
// kept). Writes the definition before any run.
int prepare_out(const Plan& p) {
  const auto wanted = sweep::definition_json(p.scenario_name, p.params, p.seeds);
  const std::string text = slurp(p.scenario_path);
  std::error_code ec;
  const fs::path def = p.out / "sweep.json";
  if (fs::exists(def, ec)) {
    const auto stored = nlohmann::json::parse(slurp(def), nullptr, false);
    std::string change =
        stored.is_object() ? sweep::definition_change(stored, wanted) : std::string("its sweep.json is not JSON");
    if (change.empty() && slurp(p.out / "scenario.textproto") != text) {
      change = "the scenario file " + p.scenario_path + " changed since (OUT/scenario.textproto is the one it ran)";
    }
    if (!change.empty()) {
      std::fprintf(stderr, "%s holds another sweep: %s.\nGive another --out, or remove %s to start this one over.\n",
                   p.out.string().c_str(), change.c_str(), p.out.string().c_str());
      return 2;
    }
    return 0;
  }
  if (fs::exists(p.out, ec) && !fs::is_empty(p.out, ec)) {
    std::fprintf(stderr, "%s exists and holds no sweep (no sweep.json): give an empty or new --out\n",
                 p.out.string().c_str());
    return 2;
  }
  fs::create_directories(p.out, ec);
  // The scenario first: a folder with sweep.json always has it.
  if (auto w = core::write_file_atomically((p.out / "scenario.textproto").string(), text); !w) {
    std::fprintf(stderr, "%s\n", w.error().message.c_str());
    return 5;
  }
  if (auto w = core::write_file_atomically(def.string(), report::json_text(wanted) + "\n"); !w) {
    std::fprintf(stderr, "%s\n", w.error().message.c_str());
    return 5;
  }
  return 0;
}

// Runs `todo` (indices into p.runs) on `jobs` threads; each finished run's
// metrics are stored in results[i]. Returns 0, or 1/5 after the first failed
// run (the others stop taking runs).
int run_all(const Plan& p, const std::vector<std::size_t>& todo, unsigned jobs, bool quiet,
            std::vector<nlohmann::json>& results) {
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::mutex error_mutex;
  std::string error;
  int status = 0;
  Progress progress(todo.size(), quiet);
  auto fail = [&](int code, const std::string& why) {
    std::lock_guard lock(error_mutex);
    if (!failed.exchange(true)) {
      error = why;
      status = code;
    }
  };
  auto worker = [&] {
    while (!failed.load()) {
      const std::size_t k = next.fetch_add(1);
      if (k >= todo.size()) return;
      const sweep::Run& run = p.runs[todo[k]];
      try {
        auto s = load_run(p, p.cells[run.cell], run.seed);
        if (!s) return fail(1, "run " + run.id + ": " + s.error().message);
        auto sim = simulate_run(s.value());
        if (!sim) return fail(1, "run " + run.id + ": " + sim.error().message);
        std::string why;
        if (!report::write_json((p.out / "runs" / run.id).string(), "metrics.json", sim->metrics, why)) {
          return fail(5, why);
        }
        results[todo[k]] = std::move(sim->metrics);
      } catch (const std::exception& e) {
        return fail(1, "run " + run.id + " failed: " + e.what());
      }
      progress.done_one();
    }
  };
  std::vector<std::thread> threads;
  for (unsigned i = 0; i < std::min<std::size_t>(jobs, todo.size()); ++i) threads.emplace_back(worker);
  for (auto& t : threads) t.join();
  if (status != 0) std::fprintf(stderr, "\n%s\n", error.c_str());
  return status;
}

// Flies run `run` as processes in lockstep and compares them with the
// simulator: metrics.json numbers, final_field.txt bytes, and the sweep's
// own stored metrics of that run (the same seed must give the same numbers
// in any thread).
sweep::DistributedCheck fly_and_compare(const Plan& p, const sweep::Run& run, const nlohmann::json& stored,
                                        const SweepOptions& o) {
  sweep::DistributedCheck c;
  c.id = run.id;
  c.cell = sweep::describe_cell(p.params, p.cells[run.cell]) + ", seed " + std::to_string(run.seed);
  const auto t0 = Clock::now();
  auto done = [&](std::string verdict) {
    c.verdict = std::move(verdict);
    c.equal = c.verdict == "yes";
    c.seconds = seconds_since(t0);
    return c;
  };
  auto s = load_run(p, p.cells[run.cell], run.seed);
  if (!s) return done(s.error().message);
  const fs::path dir = p.out / "distributed" / run.id;
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir / "sim", ec);
  if (ec) return done("cannot create " + dir.string() + ": " + ec.message());
  auto sim = simulate_run(s.value());
  if (!sim) return done(sim.error().message);
  std::string why;
  if (!report::write_json((dir / "sim").string(), "metrics.json", sim->metrics, why)) return done(why);
  if (!write_sim_field(*sim->sim, (dir / "sim" / "final_field.txt").string()))
    return done("cannot write the sim's field");
  // The same run in the sweep (another thread, maybe another invocation):
  // equal but for the timing metrics.
  if (const auto d = sweep::scalar_differences(sweep::flatten_scalars(stored), sweep::flatten_scalars(sim->metrics));
      !d.empty()) {
    return done("the sweep's run " + (p.out / "runs" / run.id).string() +
                " and a second simulation of it differ: " + d);
  }
  // The processes get the changed scenario as text, seed included.
  const std::string scenario = (dir / "scenario.textproto").string();
  if (auto w = core::write_file_atomically(scenario, s->source_text); !w) return done(w.error().message);
  std::string program = o.program.empty() ? fs::read_symlink("/proc/self/exe", ec).string() : o.program;
  if (program.ends_with(" (deleted)"))
    return done("this pheromesh binary was replaced while the sweep ran: " + program);
  std::vector<std::string> args{
      program, "run", scenario,      "--clock",    "lockstep", "--out", (dir / "lockstep").string(),
      "--dds", o.dds, "--no-record", "--progress", "10"};
  if (o.domain != 0) {
    args.emplace_back("--domain");
    args.push_back(std::to_string(o.domain));
  }
  // Bounded: a stalled lockstep run is a failed check, not a hung sweep.
  const double timeout_s = 120.0 + 0.2 * s->ticks * (1.0 + s->uavs / 10.0);
  bool timed_out = false;
  const int status = run_bounded(args, (dir / "run.log").string(), timeout_s, timed_out);
  if (timed_out) {
    return done("the processes did not end within " + std::to_string(static_cast<int>(timeout_s)) + " s (" +
                (dir / "run.log").string() + ")");
  }
  if (status != 0)
    return done("pheromesh run exited with " + std::to_string(status) + " (" + (dir / "run.log").string() + ")");
  experiments::RunNumbers proc;
  if (!experiments::numbers_from_metrics_json(slurp(dir / "lockstep" / "metrics.json"), proc, why)) return done(why);
  std::string d = experiments::differences(experiments::numbers_of(sim->sim->recorder()), proc);
  if (slurp(dir / "sim" / "final_field.txt") != slurp(dir / "lockstep" / "final_field.txt")) {
    d += "final_field.txt differs (" + dir.string() + "/{sim,lockstep}/final_field.txt)\n";
  }
  while (!d.empty() && d.back() == '\n') d.pop_back();
  for (auto& ch : d) ch = ch == '\n' ? ';' : ch;
  return done(d.empty() ? "yes" : d);
}

int write_outputs(const Plan& p, const sweep::MarkdownInput& md, const std::vector<std::string>& columns) {
  std::vector<std::pair<std::string, std::string>> files{
      {"runs.csv", sweep::runs_csv(p.params, p.cells, md.runs, columns)},
      {"summary.csv", sweep::summary_csv(p.params, p.cells, md.runs, columns)},
      {"sweep.md", sweep::sweep_markdown(md)}};
  for (std::size_t k = 0; k < p.params.size(); ++k) {
    if (!p.params[k].swept()) continue;
    for (const auto& m : md.plotted) {
      files.emplace_back("plots/" + sweep::plot_file(m, p.params[k].path),
                         sweep::svg_error_bars(sweep::plot_of(p.params, p.cells, md.runs, k, m)));
    }
  }
  for (const auto& [name, text] : files) {
    if (auto w = core::write_file_atomically((p.out / name).string(), text); !w) {
      std::fprintf(stderr, "%s\n", w.error().message.c_str());
      return 5;
    }
  }
  return 0;
}

}  // namespace

std::string command_line(int argc, const char* const* argv) {
  std::string line;
  for (int i = 0; i < argc; ++i) {
    const std::string a = argv[i];
    const bool plain = !a.empty() && a.find_first_not_of(
                                         "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                         "0123456789-_./=,:@+%") == std::string::npos;
    std::string quoted = "'";
    for (char c : a) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    line += (i == 0 ? "" : " ") + (plain ? a : quoted + "'");
  }
  return line;
}

namespace {

// The plan from the options: parameters, seeds, grid, runs, scenario name and
// output folder (prepared); 0, or the exit status of the first refusal.
int plan_sweep(const SweepOptions& o, Plan& p) {
  p.scenario_path = o.scenario;
  auto params = sweep::parameters_of(o.overrides);
  if (!params) {
    std::fprintf(stderr, "%s\n", params.error().message.c_str());
    return 2;
  }
  p.params = std::move(params).value();
  auto seeds = sweep::parse_seeds(o.seeds);
  if (!seeds) {
    std::fprintf(stderr, "%s\n", seeds.error().message.c_str());
    return 2;
  }
  p.seeds = std::move(seeds).value();
  p.cells = sweep::grid(p.params);
  auto runs = sweep::runs_of(p.cells, p.seeds);
  if (!runs) {
    std::fprintf(stderr, "%s\n", runs.error().message.c_str());
    return 2;
  }
  p.runs = std::move(runs).value();
  if (const int st = check_cells(p); st != 0) return st;
  {
    auto base = core::load_scenario(p.scenario_path);
    if (!base) {
      std::fprintf(stderr, "%s\n", base.error().message.c_str());
      return 2;
    }
    p.scenario_name = base->name;
  }
  p.out = o.out_dir.empty() ? fs::path("out/sweeps") / p.scenario_name : fs::path(o.out_dir);
  if (const int st = prepare_out(p); st != 0) return st;
  return 0;
}

// The metrics of the runs that finished before, in `results`; the indices of the others.
std::vector<std::size_t> pending_runs(const Plan& p, std::vector<nlohmann::json>& results) {
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < p.runs.size(); ++i) {
    results[i] = finished_metrics(p.out / "runs" / p.runs[i].id);
    if (results[i].is_discarded()) todo.push_back(i);
  }
  return todo;
}

void announce_sweep(const Plan& p, std::size_t skipped, std::size_t todo, std::size_t swept) {
  std::printf("sweep %s: %zu combination%s of %zu swept parameter%s x %zu seed%s = %zu runs -> %s\n",
              p.scenario_name.c_str(), p.cells.size(), p.cells.size() == 1 ? "" : "s", swept, swept == 1 ? "" : "s",
              p.seeds.size(), p.seeds.size() == 1 ? "" : "s", p.runs.size(), p.out.string().c_str());
  if (skipped > 0) {
    std::printf("sweep: %zu of %zu runs finished before (%s/runs), skipped; %zu left\n", skipped, p.runs.size(),
                p.out.string().c_str(), todo);
  }
  std::fflush(stdout);
}

sweep::MarkdownInput markdown_input(const SweepOptions& o, const Plan& p, const std::vector<nlohmann::json>& results,
                                    std::size_t executed, std::size_t skipped, unsigned jobs, double wall_s) {
  sweep::MarkdownInput md;
  md.command = o.command;
  md.scenario = p.scenario_name;
  md.params = p.params;
  md.seeds = p.seeds;
  md.cells = p.cells;
  md.jobs = jobs;
  md.executed = executed;
  md.skipped = skipped;
  md.wall_s = wall_s;
  md.dds = o.dds;
  for (std::size_t i = 0; i < p.runs.size(); ++i) {
    md.runs.push_back({p.runs[i].cell, p.runs[i].seed, p.runs[i].id, sweep::flatten_scalars(results[i])});
  }
  return md;
}

// The plotted metrics, and the headline ones that are the same in every run.
void pick_plotted(sweep::MarkdownInput& md, const std::vector<std::string>& columns) {
  md.plotted = sweep::plotted_metrics(md.runs, columns);
  for (const char* m : {"coverage", "targets_found", "covered_cells", "deposits_sent"}) {
    if (std::find(md.plotted.begin(), md.plotted.end(), m) == md.plotted.end() &&
        std::find(columns.begin(), columns.end(), m) != columns.end()) {
      md.constant.emplace_back(m);
    }
  }
}

// --distributed: a sample of the runs flown as processes; 4 if one differs from the simulator.
int fly_distributed_sample(const SweepOptions& o, const Plan& p, const std::vector<nlohmann::json>& results,
                           sweep::MarkdownInput& md) {
  int status = 0;
  md.distributed.emplace();
  const auto sample = sweep::sample_runs(p.runs.size(), o.distributed_sample);
  std::printf("distributed: flying %zu of the runs as processes (pheromesh run --clock lockstep --dds %s)\n",
              sample.size(), o.dds.c_str());
  std::fflush(stdout);
  for (std::size_t i : sample) {
    auto c = fly_and_compare(p, p.runs[i], results[i], o);
    std::printf("distributed %s (%s): lockstep == sim: %s (%.1f s)\n", c.id.c_str(), c.cell.c_str(),
                c.equal ? "yes" : ("no: " + c.verdict).c_str(), c.seconds);
    std::fflush(stdout);
    if (!c.equal) status = 4;
    md.distributed->push_back(std::move(c));
  }
  return status;
}

void report_sweep(const Plan& p, const sweep::MarkdownInput& md, std::size_t executed, double wall_s, unsigned jobs,
                  std::size_t swept) {
  if (executed == 0) {
    std::printf("sweep: every run had finished before; nothing to run (runs/s: none measured)\n");
  } else {
    std::printf("sweep: %zu runs in %.2f s on %u job%s: %.1f runs/s\n", executed, wall_s, jobs, jobs == 1 ? "" : "s",
                static_cast<double>(executed) / wall_s);
  }
  std::printf("sweep: %s/sweep.md, runs.csv (%zu rows), summary.csv, %zu plots\n", p.out.string().c_str(),
              md.runs.size(), md.plotted.size() * swept);
}

}  // namespace

int run_sweep(const SweepOptions& o) {
  Plan p;
  if (const int st = plan_sweep(o, p); st != 0) return st;

  std::vector<nlohmann::json> results(p.runs.size());
  const std::vector<std::size_t> todo = pending_runs(p, results);
  const unsigned hw = std::max(1U, std::thread::hardware_concurrency());
  const unsigned jobs = o.jobs > 0 ? o.jobs : hw;
  const std::size_t skipped = p.runs.size() - todo.size();
  std::size_t swept = 0;
  for (const auto& prm : p.params) swept += prm.swept() ? 1 : 0;
  announce_sweep(p, skipped, todo.size(), swept);
  const auto t0 = Clock::now();
  if (const int st = run_all(p, todo, jobs, o.quiet, results); st != 0) return st;
  const double wall_s = seconds_since(t0);

  sweep::MarkdownInput md = markdown_input(o, p, results, todo.size(), skipped, jobs, wall_s);
  const auto columns = sweep::metric_columns(md.runs);
  pick_plotted(md, columns);
  const int status = o.distributed ? fly_distributed_sample(o, p, results, md) : 0;
  if (const int st = write_outputs(p, md, columns); st != 0) return st;
  report_sweep(p, md, todo.size(), wall_s, jobs, swept);
  return status;
}

}  // namespace pheromesh::cli
