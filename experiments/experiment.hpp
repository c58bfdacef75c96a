// `pheromesh experiment`: the papers' experiments run as Monte Carlo, with our
// numbers beside the paper's. Each experiment returns a Report; the runner
// writes it as Markdown + CSV + SVG plots.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "pheromesh/core/scenario.hpp"

namespace pheromesh::cli::experiments {

// Called as runs complete, for the progress bar.
using Progress = std::function<void(uint32_t done, uint32_t total)>;

struct Row {
  std::string metric;          // "iterations to acquire target 1"
  std::optional<double> paper;  // the paper's number, if it gives one
  std::vector<double> ours;    // one sample per run (a single value for deterministic rows)
  std::string unit;            // "tick", "s", "km", ...
  std::string note;            // why we differ, where the number comes from, ...
  // Our verdict on the paper's figure, a column of its own: "reproduced",
  // "differs: WHY" or "reversed: WHY" (a comparison the paper wins one way
  // and we find the other way). Empty on a row with a paper figure: the
  // writer fills in auto_verdict(). Rows without a paper figure show "–".
  std::string verdict{};
};

// "reproduced" when the paper's figure lies in the 95 % confidence interval
// of our mean (from 5 runs on) or within 15 % of it, else "differs: ours is X % higher/lower"
// (the row's note says why).
std::string auto_verdict(const Row& r);

// Two-sided 95 % confidence interval of the mean (Student t; {m, m} for a
// single sample).
struct Interval {
  double lo = 0, hi = 0;
};
Interval ci95(const std::vector<double>& v);

// A named variant of ours against the paper's policy on one metric, measured
// in the same experiment run (Row-like: one sample per run each).
struct Comparison {
  std::string metric;     // "time to find all 5 targets"
  std::string unit;       // "tick"
  std::string baseline;   // "shao_search (the paper's policy)"
  std::string variant;    // "shao_search_sweep (ours, docs/policies/shao.md)"
  bool lower_is_better = true;
  std::vector<double> baseline_samples, variant_samples;
  std::string note;
};
// Gain of the variant over the baseline, as a share of the baseline mean
// (positive = better): (b - v) / b when lower is better, (v - b) / b
// otherwise; its 95 % interval is a percentile bootstrap over runs
// (10 000 resamples of each side, a fixed seed: the same data give the same
// interval).
struct Gain {
  double gain = 0;
  Interval ci;
};
Gain gain_of(const Comparison& c);

struct Series {
  std::string name;
  std::vector<std::pair<double, double>> points;  // (x, y)
};

struct Plot {
  std::string file;  // "fig4a.svg"
  std::string title, x_label, y_label;
  std::vector<Series> series;
};

struct Report {
  std::string title;     // "Shao 2020 Fig. 4a — target acquisition, 50x50"
  std::string source;    // where in the paper
  std::string setup;     // what we ran (scenario, runs, seeds)
  std::vector<Row> rows;
  std::vector<Plot> plots;
  std::vector<std::string> csv_header;               // raw per-run data
  std::vector<std::vector<std::string>> csv_rows;
  std::vector<std::string> notes;                    // choices and differences, one paragraph each
  std::string tables;  // optional Markdown after the rows (cross tables the rows cannot show)
  // The named variants against the paper's policy (a table of their gains).
  std::vector<Comparison> comparisons{};
  // The investigation of a reversed or unexplained result: Markdown, written
  // after the rows (second reading, unstated quantities, sensitivity study,
  // conclusion). docs/policies/ holds the same text for readers.
  std::string investigation{};
};

struct Experiment {
  std::string name;         // "shao-fig4a"
  std::string description;  // one line
  uint32_t paper_runs = 1;  // run count the paper used (the default)
  std::function<Report(uint32_t runs, const Progress& progress)> run;
  // Our verdict on the paper's claims this experiment reproduces, one line,
  // shown by `pheromesh experiment --list`; the report gives it row by row,
  // computed from its runs.
  std::string verdict{};
};

// The overrides of `pheromesh experiment --set`: applied to every scenario
// file an experiment reads through load_shipped(); set by the command before
// it runs an experiment (which then counts the files read with them).
void set_overrides(core::ScenarioOverrides overrides);
// Scenario files read with the overrides since set_overrides().
uint32_t overridden_loads();
// A shipped scenario file by name (shipped_scenario), with the overrides
// applied and validated like the file.
core::Result<core::ScenarioConfig> load_shipped(const std::string& file);

// Runs a scenario file of scenarios/ through the in-process simulator (the
// same code and schedule as `pheromesh run --clock lockstep`) for seeds
// 1..runs and returns each run's field summary (metrics.json "field").
// `patch` (textproto, core::patch_scenario) changes the scenario's text
// first, so --distributed hands the processes the same scenario; `name`
// names it in errors (default: file + patch).
std::vector<std::map<std::string, double>> simulate_scenario(const std::string& file, uint32_t runs,
                                                             const std::string& patch = "", const std::string& name = "");
// The samples of one field-summary key over those runs (runs without it left out).
std::vector<double> field_samples(const std::vector<std::map<std::string, double>>& runs, const std::string& key);

// Every experiment, by family.
std::vector<Experiment> shao_experiments();
std::vector<Experiment> shao_navigation_experiments();
std::vector<Experiment> duan_experiments();
std::vector<Experiment> liu_experiments();
std::vector<Experiment> ravankar_experiments();
std::vector<Experiment> shostak_experiments();
std::vector<Experiment> shao_robustness_experiments();
std::vector<Experiment> all_experiments();

// Writes OUT/report.md, OUT/results.csv and the plots. Returns false with a
// message on I/O failure.
bool write_report(const Report& r, const std::string& out_dir, double wall_seconds, std::string& error);

// The SVG line chart of one plot (also used by `pheromesh bench scale`).
// Points with a non-finite coordinate are left out.
std::string svg_plot(const Plot& p);

// mean and sample standard deviation
double mean(const std::vector<double>& v);
double stddev(const std::vector<double>& v);

}  // namespace pheromesh::cli::experiments
