#include "experiment_command.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <exception>

#include "experiments/experiment.hpp"
#include "experiments/flight.hpp"

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

int run_experiment_command(const ExperimentOptions& o) {
  const auto all = experiments::all_experiments();
  if (o.list || o.name.empty()) {
    std::printf("%-22s %-6s %s\n", "NAME", "RUNS", "WHAT / OUR VERDICT ON THE PAPER'S CLAIM");
    for (const auto& e : all) {
      std::printf("%-22s %-6u %s\n", e.name.c_str(), e.paper_runs, e.description.c_str());
      if (!e.verdict.empty()) std::printf("%-29s verdict: %s\n", "", e.verdict.c_str());
    }
    if (!o.list) {
      std::fprintf(stderr, "\nname an experiment: pheromesh experiment NAME [--runs N] [--out DIR]\n");
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
  const uint32_t runs = o.runs > 0 ? o.runs : chosen->paper_runs;
  const std::string out = o.out_dir.empty() ? "out/experiments/" + chosen->name : o.out_dir;
  experiments::DistributedOptions dist;
  dist.enabled = o.distributed;
  dist.dds = o.dds;
  dist.domain = o.domain;
  dist.work_dir = out + "/distributed";
  experiments::set_distributed(dist);
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  experiments::Report report;
  try {
    draw_progress(chosen->name, 0, runs, 0.0);
    report = chosen->run(runs, [&](uint32_t done, uint32_t total) { draw_progress(chosen->name, done, total, elapsed()); });
  } catch (const std::exception& e) {
    std::fprintf(stderr, "\nexperiment %s failed: %s\n", chosen->name.c_str(), e.what());
    return 1;
  }
  const double wall = elapsed();
  std::string error;
  if (!experiments::write_report(report, out, wall, error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 5;
  }
  std::printf("%s: %u runs in %.1f s -> %s/report.md\n", chosen->name.c_str(), runs, wall, out.c_str());
  std::printf("%-46s %10s %18s %8s  %s\n", "metric", "paper", "ours (mean ± sd)", "ratio", "verdict");
  for (const auto& r : report.rows) {
    const double m = experiments::mean(r.ours);
    char ours[64];
    std::snprintf(ours, sizeof ours, "%.2f ± %.2f", m, experiments::stddev(r.ours));
    const std::string verdict = r.verdict.empty() ? experiments::auto_verdict(r) : r.verdict;
    std::printf("%-46s %10s %18s %8s  %s\n", r.metric.c_str(), r.paper ? std::to_string(*r.paper).substr(0, 8).c_str() : "–",
                ours, r.paper && *r.paper != 0 ? std::to_string(m / *r.paper).substr(0, 5).c_str() : "–",
                verdict.empty() ? "–" : verdict.substr(0, 60).c_str());
  }
  for (const auto& c : report.comparisons) {
    const auto g = experiments::gain_of(c);
    std::printf("variant %s vs %s, %s: gain %.1f %% [%.1f, %.1f]\n", c.variant.c_str(), c.baseline.c_str(),
                c.metric.c_str(), 100 * g.gain, 100 * g.ci.lo, 100 * g.ci.hi);
  }
  if (o.distributed) {
    const auto& checks = experiments::distributed_checks();
    std::size_t equal = 0;
    for (const auto& c : checks) {
      equal += c.equal ? 1 : 0;
      if (!c.equal) std::fprintf(stderr, "distributed run %s differs from the simulator:\n%s\n", c.label.c_str(), c.differences.c_str());
    }
    std::printf("distributed: %zu of %zu runs on real processes equal the simulator\n", equal, checks.size());
    if (checks.empty()) {
      std::fprintf(stderr, "experiment %s flies no run that real processes can check (it is closed-form or runs a model of its own)\n",
                   chosen->name.c_str());
      return 3;
    }
    if (equal != checks.size()) return 4;
  }
  return 0;
}

}  // namespace pheromesh::cli
