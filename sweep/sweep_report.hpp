// What `pheromesh sweep` writes from its runs' metrics: runs.csv (one row
// per run), summary.csv (n, mean, sd and 95 % interval per grid cell and
// metric), one SVG plot per key metric and swept parameter (mean with its
// 95 % interval as error bars), and sweep.md. Pure: text in, text out.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pheromesh/frontdoor/intervals.hpp"
#include "pheromesh/frontdoor/metric_scalars.hpp"
#include "sweep_grid.hpp"

namespace pheromesh::cli::sweep {

// flatten_scalars and is_timing_metric are the front door's
// (pheromesh/frontdoor/metric_scalars.hpp), shared with the Python package.
using frontdoor::flatten_scalars;
using frontdoor::is_timing_metric;
using frontdoor::Scalars;

// "" when `a` and `b` hold the same metrics with the same values (NaN equal
// to NaN), timing metrics left out; else the first differences,
// "coverage: 0.5 vs 0.6; ...".
std::string scalar_differences(const Scalars& a, const Scalars& b);

struct RunResult {
  std::size_t cell = 0;
  uint64_t seed = 0;
  std::string id;  // "c003-s7"
  Scalars metrics;
};

// The metric columns of runs.csv: every name any run has, sorted.
std::vector<std::string> metric_columns(const std::vector<RunResult>& runs);

// A number as the shortest text that reads back as the same double; "" for
// NaN.
std::string number_text(double v);

// One CSV field (RFC 4180): quoted when it holds a comma, a quote or a line
// break, its quotes doubled.
std::string csv_field(const std::string& s);

// runs.csv: run, every parameter (swept and fixed) by path, seed, every
// metric column; one row per run in the order given.
std::string runs_csv(const std::vector<Parameter>& params, const std::vector<Cell>& cells,
                     const std::vector<RunResult>& runs, const std::vector<std::string>& columns);

// n, mean, sample standard deviation and the 95 % interval of the mean of
// the finite values of `v`, inside the measure's range
// (pheromesh/frontdoor/intervals.hpp): Wilson's for a `proportion` (a
// measure that is 0 or 1 in every run of the sweep, proportion_metric), else
// the percentile bootstrap. For n = 1 the sd is NaN and the interval
// {mean, mean}; for n = 0 all are NaN.
struct Stats {
  std::size_t n = 0;
  double mean = 0, sd = 0, lo = 0, hi = 0;
  frontdoor::IntervalMethod method = frontdoor::IntervalMethod::None;
};
Stats stats_of(const std::vector<double>& v, bool proportion = false);
// Every finite value of `metric` in `runs` is 0 or 1 (and there is one).
bool proportion_metric(const std::vector<RunResult>& runs, const std::string& metric);

// summary.csv: one row per grid cell and metric column: cell, every
// parameter, metric, n, mean, sd, ci95_lo, ci95_hi, interval (wilson,
// bootstrap or empty), missing (runs of the cell without a value: a time the
// run did not reach, censored at its last tick).
std::string summary_csv(const std::vector<Parameter>& params, const std::vector<Cell>& cells,
                        const std::vector<RunResult>& runs, const std::vector<std::string>& columns);

// The metrics plotted: the headline ones (coverage, targets found, covered
// cells, deposits sent) and the policy's field summary ("field.*"), leaving
// out those with the same value in every run (a flat line says nothing;
// sweep.md lists them) and timing metrics; at most `max` of them.
std::vector<std::string> plotted_metrics(const std::vector<RunResult>& runs, const std::vector<std::string>& columns,
                                         std::size_t max = 12);

// A line plot with error bars: one series per combination of the other
// swept parameters' values (pooled into one series when there are more
// than six), a point per value of the x parameter at the mean, its bar the
// 95 % interval.
struct BarPoint {
  double x = 0;  // the value, or its position for a categorical axis
  Stats stats;
};
struct BarSeries {
  std::string name;
  std::vector<BarPoint> points;
};
struct BarPlot {
  std::string title, x_label, y_label;
  // Labels of the x positions 0, 1, ... when the parameter's values are not
  // all numbers; empty for a numeric axis.
  std::vector<std::string> categories;
  std::vector<BarSeries> series;
};
std::string svg_error_bars(const BarPlot& p);

// The plot of `metric` against swept parameter `x` (an index into params).
BarPlot plot_of(const std::vector<Parameter>& params, const std::vector<Cell>& cells,
                const std::vector<RunResult>& runs, std::size_t x, const std::string& metric);

// "coverage-vs-shao.aco.alpha.svg": the plot's file name (characters other
// than letters, digits, '.', '-' and '_' become '_').
std::string plot_file(const std::string& metric, const std::string& param);

// One run of the sample of --distributed, flown as processes.
struct DistributedCheck {
  std::string id;    // "c003-s7"
  std::string cell;  // describe_cell()
  bool equal = false;
  std::string verdict;  // "yes", or what differs, or why the processes failed
  double seconds = 0;
};

struct MarkdownInput {
  std::string command;   // the command line as given
  std::string scenario;  // its name
  std::vector<Parameter> params;
  std::vector<uint64_t> seeds;
  std::vector<Cell> cells;
  std::vector<RunResult> runs;
  std::vector<std::string> plotted;   // plotted_metrics()
  std::vector<std::string> constant;  // metrics of the headline set with one value in every run
  std::size_t jobs = 1;
  std::size_t executed = 0, skipped = 0;
  double wall_s = 0;
  std::optional<std::vector<DistributedCheck>> distributed;  // with --distributed
  std::string dds;
};
std::string sweep_markdown(const MarkdownInput& in);

}  // namespace pheromesh::cli::sweep
