#include "experiment_command.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cmath>
#include <exception>
#include <sstream>
#include <string>
#include <vector>

#include "experiments/experiment.hpp"
#include "experiments/flight.hpp"
#include "pheromesh/core/atomic_file.hpp"

namespace pheromesh::cli {

namespace {

void draw_progress(const std::string& name, uint32_t done, uint32_t total, double elapsed_s) {
  const int width = 30;
  const int filled = total > 0 ? static_cast<int>(width * done / total) : width;
  const bool tty = isatty(STDERR_FILENO) != 0;
  std::fprintf(stderr, "%s%s [%.*s%*s] %u/%u runs, %.1f s%s", tty ? "\r" : "", name.c_str(), filled,
               "##############################", width - filled, "", done, total, elapsed_s, tty ? "" : "\n");
  if (tty && done == total) std::fputc('\n', stderr);
  std::fflush(stderr);
}

}  // namespace

namespace {

// What one experiment run left for the summary of --all.
struct Outcome {
  const experiments::Experiment* experiment = nullptr;
  uint32_t runs = 0;
  int status = 0;  // the command's exit code for it
  double wall_s = 0;
  experiments::Report report;
  std::size_t checks = 0, checks_equal = 0;
};

std::string fmt(double v, int prec = 2) {
  if (!std::isfinite(v)) return "–";
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", prec, v);
  return b;
}

void configure_distributed(const ExperimentOptions& o, const std::string& out) {
  experiments::DistributedOptions dist;
  dist.enabled = o.distributed;
  dist.dds = o.dds;
  dist.domain = o.domain;
  dist.work_dir = out + "/distributed";
  experiments::set_distributed(dist);
}

// An experiment seeds its runs itself: false (and a message) for an override of run.seed.
bool overrides_leave_the_seed(const core::ScenarioOverrides& overrides) {
  for (const auto& ov : overrides) {
    if (ov.path == "run.seed") {
      std::fprintf(stderr, "%s: an experiment seeds its runs itself (1, 2, ... --runs); leave run.seed out\n",
                   ov.source.c_str());
      return false;
    }
  }
  return true;
}

// After the run: an override must have reached a scenario file; the report's setup names it.
bool note_overrides(Outcome& r, const core::ScenarioOverrides& overrides) {
  const experiments::Experiment& chosen = *r.experiment;
  if (experiments::overridden_loads() == 0) {
    std::fprintf(stderr,
                 "experiment %s builds its scenarios in code and reads no scenario file: %s cannot change "
                 "them\n",
                 chosen.name.c_str(), core::describe_overrides(overrides).c_str());
    return false;
  }
  r.report.setup += " Overrides applied to every scenario file it read: `" + core::describe_overrides(overrides) + "`.";
  std::printf("%s: overrides %s\n", chosen.name.c_str(), core::describe_overrides(overrides).c_str());
  return true;
}

// The console summary: one line per row and per comparison.
void print_summary(const Outcome& r, const std::string& out) {
  const experiments::Experiment& chosen = *r.experiment;
  std::printf("%s: %u runs in %.1f s -> %s/report.md\n", chosen.name.c_str(), r.runs, r.wall_s, out.c_str());
  std::printf("%-46s %10s %18s %8s  %s\n", "metric", "paper", "ours (mean ± sd)", "ratio", "verdict");
  for (const auto& row : r.report.rows) {
    const double m = experiments::mean(row.ours);
    char ours[64];
    std::snprintf(ours, sizeof ours, "%.2f ± %.2f", m, experiments::stddev(row.ours));
    const std::string verdict = row.verdict.empty() ? experiments::auto_verdict(row) : row.verdict;
    std::printf("%-46s %10s %18s %8s  %s\n", row.metric.c_str(),
                row.paper ? std::to_string(*row.paper).substr(0, 8).c_str() : "–", ours,
                row.paper && *row.paper != 0 ? std::to_string(m / *row.paper).substr(0, 5).c_str() : "–",
                verdict.empty() ? "–" : verdict.substr(0, 60).c_str());
  }
  for (const auto& c : r.report.comparisons) {
    const auto g = experiments::gain_of(c);
    std::printf("variant %s vs %s, %s: gain %.1f %% [%.1f, %.1f]\n", c.variant.c_str(), c.baseline.c_str(),
                c.metric.c_str(), 100 * g.gain, 100 * g.ci.lo, 100 * g.ci.hi);
  }
}

// --distributed: how many runs on real processes equal the simulator.
void check_distributed(Outcome& r) {
  const experiments::Experiment& chosen = *r.experiment;
  const auto& checks = experiments::distributed_checks();
  r.checks = checks.size();
  for (const auto& c : checks) {
    r.checks_equal += c.equal ? 1 : 0;
    if (!c.equal)
      std::fprintf(stderr, "distributed run %s differs from the simulator:\n%s\n", c.label.c_str(),
                   c.differences.c_str());
  }
  std::printf("distributed: %zu of %zu runs on real processes equal the simulator\n", r.checks_equal, r.checks);
  if (checks.empty()) {
    std::fprintf(
        stderr,
        "experiment %s flies no run that real processes can check (it is closed-form or runs a model of its own)\n",
        chosen.name.c_str());
    r.status = 3;
  } else if (r.checks_equal != r.checks) {
    r.status = 4;
  }
}

Outcome run_one(const experiments::Experiment& chosen, const ExperimentOptions& o, const std::string& out) {
  Outcome r;
  r.experiment = &chosen;
  r.runs = o.runs > 0 ? o.runs : chosen.paper_runs;
  configure_distributed(o, out);
  auto overrides = overrides_of(o.overrides);
  if (!overrides) {
    std::fprintf(stderr, "%s\n", overrides.error().message.c_str());
    r.status = 2;
    return r;
  }
  if (!overrides_leave_the_seed(overrides.value())) {
    r.status = 2;
    return r;
  }
  experiments::set_overrides(overrides.value());
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  try {
    draw_progress(chosen.name, 0, r.runs, 0.0);
    r.report = chosen.run(r.runs, [&](uint32_t done, uint32_t total) { draw_progress(chosen.name, done, total, elapsed()); });
  } catch (const std::exception& e) {
    std::fprintf(stderr, "\nexperiment %s failed: %s\n", chosen.name.c_str(), e.what());
    r.status = 1;
    return r;
  }
  r.wall_s = elapsed();
  if (!overrides->empty() && !note_overrides(r, overrides.value())) {
    r.status = 2;
    return r;
  }
  std::string error;
  if (!experiments::write_report(r.report, out, r.wall_s, error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    r.status = 5;
    return r;
  }
  print_summary(r, out);
  if (o.distributed) check_distributed(r);
  return r;
}

std::string cell(std::string s) {
  for (auto& c : s) c = c == '|' ? '/' : c == '\n' ? ' ' : c;
  return s;
}

// OUT/summary.md of --all: every experiment's paper figures, ours, verdicts,
// variants and wall time, in one table each.
std::string summary(const std::vector<Outcome>& outcomes, const ExperimentOptions& o) {
  std::ostringstream md;
  md << "# Every experiment" << (o.distributed ? ", with its runs on real processes (`--distributed --dds " + o.dds + "`)" : "")
     << "\n\nWritten by `pheromesh experiment --all" << (o.runs > 0 ? " --runs " + std::to_string(o.runs) : "")
     << (o.distributed ? " --distributed" : "") << "`. Each experiment's report.md has the notes, the readings used and the investigation.\n\n"
     << "| experiment | runs | wall time [s] | " << (o.distributed ? "runs on processes equal to the simulator | " : "")
     << "status | verdict |\n|---|---|---|" << (o.distributed ? "---|" : "") << "---|---|\n";
  for (const auto& r : outcomes) {
    md << "| [" << r.experiment->name << "](" << r.experiment->name << "/report.md) | " << r.runs << " | " << fmt(r.wall_s, 1)
       << " | ";
    if (o.distributed) md << r.checks_equal << " / " << r.checks << " | ";
    md << (r.status == 0 ? "ok" : "exit " + std::to_string(r.status)) << " | " << cell(r.experiment->verdict) << " |\n";
  }
  for (const auto& r : outcomes) {
    md << "\n## " << r.experiment->name << "\n\n| metric | paper | ours (mean ± sd) | runs | verdict |\n|---|---|---|---|---|\n";
    for (const auto& row : r.report.rows) {
      if (!row.paper) continue;
      const std::string v = row.verdict.empty() ? experiments::auto_verdict(row) : row.verdict;
      md << "| " << cell(row.metric) << (row.unit.empty() ? "" : " [" + row.unit + "]") << " | " << fmt(*row.paper) << " | "
         << fmt(experiments::mean(row.ours)) << " ± " << fmt(experiments::stddev(row.ours)) << " | " << row.ours.size()
         << " | " << cell(v) << " |\n";
    }
    if (!r.report.comparisons.empty()) {
      md << "\n| variant | against | metric | gain [95 % CI] |\n|---|---|---|---|\n";
      for (const auto& c : r.report.comparisons) {
        const auto g = experiments::gain_of(c);
        md << "| " << cell(c.variant) << " | " << cell(c.baseline) << " | " << cell(c.metric) << " | " << fmt(100 * g.gain, 1)
           << " % [" << fmt(100 * g.ci.lo, 1) << ", " << fmt(100 * g.ci.hi, 1) << "] |\n";
      }
    }
  }
  return md.str();
}

}  // namespace

int run_experiment_command(const ExperimentOptions& o) {
  const auto all = experiments::all_experiments();
  if (o.all) {
    const std::string root = o.out_dir.empty() ? "out/experiments" : o.out_dir;
    std::vector<Outcome> outcomes;
    int status = 0;
    for (const auto& e : all) {
      outcomes.push_back(run_one(e, o, root + "/" + e.name));
      // Closed-form experiments have nothing for --distributed to check: not a failure of --all.
      if (outcomes.back().status != 0 && outcomes.back().status != 3) status = outcomes.back().status;
      outcomes.back().report.plots.clear();  // the summary needs rows only
    }
    if (auto w = core::write_file_atomically(root + "/summary.md", summary(outcomes, o)); !w) {
      std::fprintf(stderr, "%s\n", w.error().message.c_str());
      return 5;
    }
    std::printf("every experiment -> %s/summary.md\n", root.c_str());
    return status;
  }
  if (o.list || o.name.empty()) {
    std::printf("%-22s %-6s %s\n", "NAME", "RUNS", "WHAT / OUR VERDICT ON THE PAPER'S CLAIM");
    for (const auto& e : all) {
      std::printf("%-22s %-6u %s\n", e.name.c_str(), e.paper_runs, e.description.c_str());
      if (!e.verdict.empty()) std::printf("%-29s verdict: %s\n", "", e.verdict.c_str());
    }
    if (!o.list) {
      std::fprintf(stderr, "\nname an experiment: pheromesh experiment NAME [--runs N] [--out DIR], or --all\n");
      return 2;
    }
    return 0;
  }
  const experiments::Experiment* chosen = nullptr;
  for (const auto& e : all) {
    if (e.name == o.name) chosen = &e;
  }
  if (chosen == nullptr) {
    std::fprintf(stderr, "unknown experiment '%s'; `pheromesh experiment --list` names them all\n", o.name.c_str());
    return 2;
  }
  return run_one(*chosen, o, o.out_dir.empty() ? "out/experiments/" + chosen->name : o.out_dir).status;
}

}  // namespace pheromesh::cli
