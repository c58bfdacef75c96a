#include "sweep_report.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>
#include <sstream>


namespace pheromesh::cli::sweep {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Whole text as a finite double ("2", "0.5", "1e-3"); false for "frontier".
bool as_number(const std::string& s, double& out) {
  if (s.empty()) return false;
  const auto* end = s.data() + s.size();
  const auto [p, ec] = std::from_chars(s.data(), end, out);
  return ec == std::errc{} && p == end && std::isfinite(out);
}

std::string xml_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&':
        o += "&amp;";
        break;
      case '<':
        o += "&lt;";
        break;
      case '>':
        o += "&gt;";
        break;
      case '"':
        o += "&quot;";
        break;
      default:
        o += c;
    }
  }
  return o;
}

// A tick label: few digits, no trailing zeros.
std::string tick_text(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", std::fabs(v) < 1e-12 ? 0.0 : v);
  return b;
}

// The parameter columns' values of a cell, in order.
std::vector<std::string> cell_values(const std::vector<Parameter>& params, const Cell& c) {
  std::vector<std::string> v;
  for (std::size_t k = 0; k < params.size(); ++k) v.push_back(params[k].values.at(c.choice.at(k)));
  return v;
}

std::string md_cell(std::string s) {
  for (auto& c : s) c = c == '|' ? '/' : c == '\n' ? ' ' : c;
  return s;
}

std::string fixed_text(double v, int prec) {
  if (!std::isfinite(v)) return "–";
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", prec, v);
  return b;
}

// Four significant digits for the table of sweep.md, never an exponent for
// a count such as 1798 (runs.csv and summary.csv hold every digit).
std::string short_text(double v) {
  if (!std::isfinite(v)) return "–";
  char b[64];
  std::snprintf(b, sizeof b, std::fabs(v) >= 1e4 ? "%.0f" : "%.4g", v);
  return b;
}

}  // namespace

std::string scalar_differences(const Scalars& a, const Scalars& b) {
  std::string d;
  int shown = 0;
  auto add = [&](const std::string& name, const std::string& x, const std::string& y) {
    if (shown++ < 5) d += (d.empty() ? "" : "; ") + name + ": " + x + " vs " + y;
  };
  for (const auto& [k, v] : a) {
    if (is_timing_metric(k)) continue;
    auto it = b.find(k);
    if (it == b.end()) {
      add(k, number_text(v), "missing");
    } else if (v != it->second && !(std::isnan(v) && std::isnan(it->second))) {
      add(k, number_text(v), number_text(it->second));
    }
  }
  for (const auto& [k, v] : b) {
    if (!is_timing_metric(k) && !a.contains(k)) add(k, "missing", number_text(v));
  }
  if (shown > 5) d += "; and " + std::to_string(shown - 5) + " more";
  return d;
}

std::vector<std::string> metric_columns(const std::vector<RunResult>& runs) {
  std::set<std::string> names;
  for (const auto& r : runs) {
    for (const auto& [k, v] : r.metrics) names.insert(k);
  }
  return {names.begin(), names.end()};
}

std::string number_text(double v) {
  if (std::isnan(v)) return "";
  char b[64];
  const auto [p, ec] = std::to_chars(b, b + sizeof b, v);
  return ec == std::errc{} ? std::string(b, p) : "";
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string o = "\"";
  for (char c : s) o += c == '"' ? std::string("\"\"") : std::string(1, c);
  return o + "\"";
}

std::string runs_csv(const std::vector<Parameter>& params, const std::vector<Cell>& cells,
                     const std::vector<RunResult>& runs, const std::vector<std::string>& columns) {
  std::ostringstream o;
  o << "run";
  for (const auto& p : params) o << "," << csv_field(p.path);
  o << ",seed";
  for (const auto& c : columns) o << "," << csv_field(c);
  o << "\n";
  for (const auto& r : runs) {
    o << csv_field(r.id);
    for (const auto& v : cell_values(params, cells.at(r.cell))) o << "," << csv_field(v);
    o << "," << r.seed;
    for (const auto& c : columns) {
      auto it = r.metrics.find(c);
      o << "," << (it == r.metrics.end() ? "" : number_text(it->second));
    }
    o << "\n";
  }
  return o.str();
}

Stats stats_of(const std::vector<double>& v, bool proportion) {
  const frontdoor::MeanInterval m = frontdoor::mean_interval(v, proportion);
  Stats s;
  s.n = m.n;
  s.mean = m.mean;
  s.sd = m.sd;
  s.lo = m.lo;
  s.hi = m.hi;
  s.method = m.method;
  return s;
}

bool proportion_metric(const std::vector<RunResult>& runs, const std::string& metric) {
  std::vector<double> v;
  for (const auto& r : runs) {
    if (auto it = r.metrics.find(metric); it != r.metrics.end()) v.push_back(it->second);
  }
  return frontdoor::zero_or_one(v);
}

std::string summary_csv(const std::vector<Parameter>& params, const std::vector<Cell>& cells,
                        const std::vector<RunResult>& runs, const std::vector<std::string>& columns) {
  std::ostringstream o;
  o << "cell";
  for (const auto& p : params) o << "," << csv_field(p.path);
  o << ",metric,n,mean,sd,ci95_lo,ci95_hi,interval,missing\n";
  std::map<std::string, bool> proportion;
  for (const auto& m : columns) proportion[m] = proportion_metric(runs, m);
  for (const auto& c : cells) {
    const auto values = cell_values(params, c);
    std::size_t in_cell = 0;
    for (const auto& r : runs) in_cell += r.cell == c.index ? 1 : 0;
    for (const auto& m : columns) {
      std::vector<double> v;
      for (const auto& r : runs) {
        if (r.cell != c.index) continue;
        auto it = r.metrics.find(m);
        if (it != r.metrics.end()) v.push_back(it->second);
      }
      const Stats s = stats_of(v, proportion.at(m));
      o << c.index;
      for (const auto& x : values) o << "," << csv_field(x);
      o << "," << csv_field(m) << "," << s.n << "," << number_text(s.mean) << "," << number_text(s.sd) << ","
        << number_text(s.lo) << "," << number_text(s.hi) << "," << frontdoor::to_string(s.method) << ","
        << in_cell - s.n << "\n";
    }
  }
  return o.str();
}

std::vector<std::string> plotted_metrics(const std::vector<RunResult>& runs, const std::vector<std::string>& columns,
                                         std::size_t max) {
  std::vector<std::string> wanted = {"coverage", "targets_found", "covered_cells", "deposits_sent"};
  for (const auto& c : columns) {
    if (c.starts_with("field.")) wanted.push_back(c);
  }
  std::vector<std::string> out;
  for (const auto& m : wanted) {
    if (out.size() >= max) break;
    if (is_timing_metric(m) || std::find(columns.begin(), columns.end(), m) == columns.end()) continue;
    std::set<double> seen;
    bool has_nan = false;
    for (const auto& r : runs) {
      auto it = r.metrics.find(m);
      if (it == r.metrics.end() || std::isnan(it->second)) {
        has_nan = true;
      } else {
        seen.insert(it->second);
      }
    }
    if (seen.size() + (has_nan ? 1 : 0) > 1) out.push_back(m);
  }
  return out;
}

BarPlot plot_of(const std::vector<Parameter>& params, const std::vector<Cell>& cells,
                const std::vector<RunResult>& runs, std::size_t x, const std::string& metric) {
  const Parameter& px = params.at(x);
  BarPlot p;
  p.title = metric + " against " + px.path;
  p.x_label = px.path;
  p.y_label = metric + " (mean, 95 % interval)";
  std::vector<double> xs(px.values.size());
  bool numeric = true;
  for (std::size_t i = 0; i < px.values.size(); ++i) numeric = numeric && as_number(px.values[i], xs[i]);
  if (!numeric) {
    p.categories = px.values;
    for (std::size_t i = 0; i < xs.size(); ++i) xs[i] = static_cast<double>(i);
  }
  // The other swept parameters: one series per combination of their values,
  // unless there are more than six, when the plot pools them.
  std::vector<std::size_t> others;
  std::size_t combos = 1;
  for (std::size_t k = 0; k < params.size(); ++k) {
    if (k != x && params[k].swept()) {
      others.push_back(k);
      combos *= params[k].values.size();
    }
  }
  const bool pooled = combos > 6;
  const bool proportion = proportion_metric(runs, metric);
  auto series_key = [&](const Cell& c) {
    std::string key;
    if (pooled) return key;
    for (std::size_t k : others)
      key += (key.empty() ? "" : ", ") + params[k].path + "=" + params[k].values[c.choice[k]];
    return key;
  };
  // Series in grid order.
  std::vector<std::string> keys;
  for (const auto& c : cells) {
    const auto key = series_key(c);
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
  }
  for (const auto& key : keys) {
    BarSeries s;
    s.name = key.empty()
                 ? (pooled ? "every value of " + std::to_string(others.size()) + " other parameters, pooled" : metric)
                 : key;
    for (std::size_t i = 0; i < px.values.size(); ++i) {
      std::vector<double> v;
      for (const auto& r : runs) {
        const Cell& c = cells.at(r.cell);
        if (c.choice[x] != i || series_key(c) != key) continue;
        auto it = r.metrics.find(metric);
        if (it != r.metrics.end()) v.push_back(it->second);
      }
      const Stats st = stats_of(v, proportion);
      if (st.n > 0) s.points.push_back({xs[i], st});
    }
    std::sort(s.points.begin(), s.points.end(), [](const BarPoint& a, const BarPoint& b) { return a.x < b.x; });
    p.series.push_back(std::move(s));
  }
  if (pooled) p.title += " (other parameters pooled)";
  return p;
}

namespace {

// The plot's frame [px] and its axes: the ranges and the step between y ticks.
struct BarFrame {
  double W = 760, H = 460, L = 80, R = 230, T = 44, B = 64;
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  double step = 1;
  [[nodiscard]] double sx(double x) const { return L + (x - x0) / (x1 - x0) * (W - L - R); }
  [[nodiscard]] double sy(double y) const { return H - B - (y - y0) / (y1 - y0) * (H - T - B); }
};

BarFrame bar_frame(const BarPlot& p) {
  BarFrame f;
  double x0 = std::numeric_limits<double>::max(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const auto& s : p.series) {
    for (const auto& pt : s.points) {
      x0 = std::min(x0, pt.x), x1 = std::max(x1, pt.x);
      for (double y : {pt.stats.mean, pt.stats.lo, pt.stats.hi}) {
        if (std::isfinite(y)) y0 = std::min(y0, y), y1 = std::max(y1, y);
      }
    }
  }
  if (x0 > x1) x0 = 0, x1 = 1;
  if (y0 > y1) y0 = 0, y1 = 1;
  if (x1 == x0) x0 -= 1, x1 += 1;
  if (y1 == y0) y0 -= 1, y1 += 1;
  // Room beside the outermost points, so that no bar sits on an axis.
  const double xpad = 0.06 * (x1 - x0);
  x0 -= xpad, x1 += xpad;
  if (!p.categories.empty()) x0 = -0.5, x1 = static_cast<double>(p.categories.size()) - 0.5;
  // y ticks at a round step (1, 2 or 5 times a power of ten), about five of
  // them, the axis widened to whole steps.
  const double raw = (y1 - y0) / 5.0;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double step = raw / mag <= 1 ? mag : raw / mag <= 2 ? 2 * mag : raw / mag <= 5 ? 5 * mag : 10 * mag;
  y0 = std::floor(y0 / step) * step, y1 = std::ceil(y1 / step) * step;
  f.x0 = x0, f.x1 = x1, f.y0 = y0, f.y1 = y1, f.step = step;
  return f;
}

// The header, the title, the axes and the y ticks with grid lines.
void write_bar_frame(std::ostringstream& o, const BarPlot& p, const BarFrame& f) {
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << f.W << "\" height=\"" << f.H
    << "\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  o << "<text x=\"" << (f.L + f.W - f.R) / 2 << "\" y=\"24\" text-anchor=\"middle\" font-size=\"15\">"
    << xml_escape(p.title) << "</text>\n";
  o << "<line x1=\"" << f.L << "\" y1=\"" << f.H - f.B << "\" x2=\"" << f.W - f.R << "\" y2=\"" << f.H - f.B
    << "\" stroke=\"black\"/>\n<line x1=\"" << f.L << "\" y1=\"" << f.T << "\" x2=\"" << f.L << "\" y2=\"" << f.H - f.B
    << "\" stroke=\"black\"/>\n";
  // y ticks with grid lines.
  const auto y_steps = static_cast<int>(std::lround((f.y1 - f.y0) / f.step));
  for (int i = 0; i <= y_steps; ++i) {
    const double yv = f.y0 + f.step * i;
    o << "<line x1=\"" << f.L << "\" y1=\"" << f.sy(yv) << "\" x2=\"" << f.W - f.R << "\" y2=\"" << f.sy(yv)
      << "\" stroke=\"#e4e4e4\"/>\n<text x=\"" << f.L - 6 << "\" y=\"" << f.sy(yv) + 4 << "\" text-anchor=\"end\">"
      << tick_text(yv) << "</text>\n";
  }
}

// x ticks: every category, or every value a series has when there are at
// most ten, else six evenly spaced.
std::vector<std::pair<double, std::string>> bar_xticks(const BarPlot& p, const BarFrame& f) {
  std::vector<std::pair<double, std::string>> xticks;
  if (!p.categories.empty()) {
    for (std::size_t i = 0; i < p.categories.size(); ++i) xticks.emplace_back(static_cast<double>(i), p.categories[i]);
  } else {
    std::set<double> values;
    for (const auto& s : p.series) {
      for (const auto& pt : s.points) values.insert(pt.x);
    }
    if (values.size() <= 10) {
      for (double v : values) xticks.emplace_back(v, tick_text(v));
    } else {
      for (int i = 0; i <= 5; ++i)
        xticks.emplace_back(f.x0 + (f.x1 - f.x0) * i / 5.0, tick_text(f.x0 + (f.x1 - f.x0) * i / 5.0));
    }
  }
  return xticks;
}

void write_x_axis(std::ostringstream& o, const BarPlot& p, const BarFrame& f,
                  const std::vector<std::pair<double, std::string>>& xticks) {
  for (const auto& [v, label] : xticks) {
    o << "<line x1=\"" << f.sx(v) << "\" y1=\"" << f.H - f.B << "\" x2=\"" << f.sx(v) << "\" y2=\"" << f.H - f.B + 5
      << "\" stroke=\"black\"/>\n<text x=\"" << f.sx(v) << "\" y=\"" << f.H - f.B + 19 << "\" text-anchor=\"middle\">"
      << xml_escape(label) << "</text>\n";
  }
  o << "<text x=\"" << (f.L + f.W - f.R) / 2 << "\" y=\"" << f.H - 18 << "\" text-anchor=\"middle\">"
    << xml_escape(p.x_label) << "</text>\n";
  o << "<text transform=\"translate(18," << (f.T + f.H - f.B) / 2 << ") rotate(-90)\" text-anchor=\"middle\">"
    << xml_escape(p.y_label) << "</text>\n";
}

// Series si: its line, its points with their intervals, its legend entry.
void write_bar_series(std::ostringstream& o, const BarPlot& p, const BarFrame& f, std::size_t si) {
  const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#17becf"};
  const auto& s = p.series[si];
  const char* colour = colours[si % 7];
  // Series side by side at one x, a few pixels apart, so that their bars
  // do not hide each other.
  const double dodge = 6.0 * (static_cast<double>(si) - static_cast<double>(p.series.size() - 1) / 2.0);
  auto sx = [&](double x) { return f.L + (x - f.x0) / (f.x1 - f.x0) * (f.W - f.L - f.R) + dodge; };
  std::string line;
  for (const auto& pt : s.points) {
    if (!std::isfinite(pt.stats.mean)) continue;
    line += std::to_string(sx(pt.x)) + "," + std::to_string(f.sy(pt.stats.mean)) + " ";
  }
  if (!line.empty()) {
    o << "<polyline fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"2\" points=\"" << line << "\"/>\n";
  }
  for (const auto& pt : s.points) {
    if (!std::isfinite(pt.stats.mean)) continue;
    const double cx = sx(pt.x);
    if (pt.stats.n > 1 && pt.stats.hi > pt.stats.lo) {
      o << "<path d=\"M" << cx << "," << f.sy(pt.stats.lo) << "V" << f.sy(pt.stats.hi) << "M" << cx - 5 << ","
        << f.sy(pt.stats.lo) << "h10M" << cx - 5 << "," << f.sy(pt.stats.hi) << "h10\" stroke=\"" << colour
        << "\" stroke-opacity=\"0.7\" fill=\"none\"/>\n";
    }
    o << "<circle cx=\"" << cx << "\" cy=\"" << f.sy(pt.stats.mean) << "\" r=\"3.5\" fill=\"" << colour
      << "\"><title>mean " << tick_text(pt.stats.mean) << ", 95 % interval " << tick_text(pt.stats.lo) << " – "
      << tick_text(pt.stats.hi) << ", n " << pt.stats.n << "</title></circle>\n";
  }
  const double ly = f.T + 10 + 20.0 * static_cast<double>(si);
  o << "<line x1=\"" << f.W - f.R + 16 << "\" y1=\"" << ly << "\" x2=\"" << f.W - f.R + 40 << "\" y2=\"" << ly
    << "\" stroke=\"" << colour << "\" stroke-width=\"2\"/>\n<text x=\"" << f.W - f.R + 46 << "\" y=\"" << ly + 4
    << "\">" << xml_escape(s.name) << "</text>\n";
}

}  // namespace

std::string svg_error_bars(const BarPlot& p) {
  const BarFrame f = bar_frame(p);
  std::ostringstream o;
  write_bar_frame(o, p, f);
  write_x_axis(o, p, f, bar_xticks(p, f));
  for (std::size_t si = 0; si < p.series.size(); ++si) write_bar_series(o, p, f, si);
  o << "</svg>\n";
  return o.str();
}

std::string plot_file(const std::string& metric, const std::string& param) {
  std::string name = metric + "-vs-" + param;
  for (auto& c : name) {
    const bool ok =
        (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '_';
    if (!ok) c = '_';
  }
  return name + ".svg";
}

namespace {

// The title, the command and how many runs this invocation made.
void write_sweep_intro(std::ostringstream& md, const MarkdownInput& in) {
  md << "# Sweep of " << in.scenario << "\n\n```sh\n" << in.command << "\n```\n\n";
  md << in.cells.size() << " combination" << (in.cells.size() == 1 ? "" : "s") << " × " << in.seeds.size() << " seed"
     << (in.seeds.size() == 1 ? "" : "s") << " = " << in.runs.size() << " runs on the in-process simulator (the "
     << "same code and schedule as `pheromesh sim`; every run folder in `runs/` holds its `metrics.json`). This "
     << "invocation ran " << in.executed << " of them on " << in.jobs << " job" << (in.jobs == 1 ? "" : "s") << " in "
     << fixed_text(in.wall_s, 1) << " s";
  if (in.executed > 0 && in.wall_s > 0)
    md << " (" << fixed_text(static_cast<double>(in.executed) / in.wall_s, 1) << " runs/s)";
  md << "; " << in.skipped << " had finished before and were kept.\n\n";
}

// The grid's parameters and seeds, and what the files hold.
void write_sweep_grid(std::ostringstream& md, const MarkdownInput& in) {
  md << "## Grid\n\n| parameter | values | given as |\n|---|---|---|\n";
  for (const auto& p : in.params) {
    std::string values;
    for (const auto& v : p.values) values += (values.empty() ? "" : ", ") + v;
    md << "| `" << p.path << "` | " << md_cell(values) << (p.swept() ? "" : " (fixed)") << " | `" << md_cell(p.source())
       << "` |\n";
  }
  md << "| seed | " << describe_seeds(in.seeds) << " | `--seeds` |\n\n";
  md << "Files: [runs.csv](runs.csv) (one row per run: every parameter, the seed and every scalar metric of "
        "`metrics.json`, nested ones with dotted names), [summary.csv](summary.csv) (per combination and metric: "
        "n, mean, sd, 95 % interval of the mean, the interval's method, runs without a value).\n\n"
        "Intervals stay inside what a measure can take: for a measure that is 0 or 1 in every run, the share of "
        "runs with Wilson's score interval; for any other, the percentile bootstrap of the mean (4000 resamples), "
        "which lies between the smallest and the largest value. With few seeds the bootstrap's interval is "
        "narrower than it should be.\n\n"
        "`ticks_to_coverage_50`, `ticks_to_coverage_90` and `ticks_to_all_targets` are censored at the run's last "
        "tick: a run that did not get there within it has no value (an empty cell of runs.csv), its mean is over "
        "the runs that did, and summary.csv's `missing` counts the others.\n\n";
}

// The summary table's row of combination c.
void write_summary_row(std::ostringstream& md, const MarkdownInput& in, const Cell& c) {
  md << "| " << c.index << " |";
  for (std::size_t k = 0; k < in.params.size(); ++k) {
    if (in.params[k].swept()) md << " " << md_cell(in.params[k].values[c.choice[k]]) << " |";
  }
  std::size_t n = 0;
  for (const auto& r : in.runs) n += r.cell == c.index ? 1 : 0;
  md << " " << n << " |";
  for (const auto& m : in.plotted) {
    std::vector<double> v;
    for (const auto& r : in.runs) {
      if (r.cell != c.index) continue;
      auto it = r.metrics.find(m);
      if (it != r.metrics.end()) v.push_back(it->second);
    }
    const Stats s = stats_of(v, proportion_metric(in.runs, m));
    md << " " << short_text(s.mean);
    if (s.n > 1) md << " [" << short_text(s.lo) << ", " << short_text(s.hi) << "]";
    md << " |";
  }
  md << "\n";
}

void write_summary_table(std::ostringstream& md, const MarkdownInput& in, std::size_t swept) {
  md << ".\n\n| cell |";
  for (const auto& p : in.params) {
    if (p.swept()) md << " `" << p.path << "` |";
  }
  md << " n |";
  for (const auto& m : in.plotted) md << " " << md_cell(m) << " |";
  md << "\n|---|";
  for (std::size_t i = 0; i < swept + 1 + in.plotted.size(); ++i) md << "---|";
  md << "\n";
  for (const auto& c : in.cells) write_summary_row(md, in, c);
  md << "\n";
}

void write_plots_section(std::ostringstream& md, const MarkdownInput& in, std::size_t swept) {
  md << "## Plots\n\n";
  if (swept == 0 || in.plotted.empty()) {
    md << "None: " << (swept == 0 ? "no parameter takes more than one value" : "no plotted metric differs between runs")
       << ".\n\n";
  } else {
    md << "Each metric above against each swept parameter: the mean over the seeds, its bar the 95 % interval; one "
          "line per combination of the other swept parameters (pooled when there are more than six). Plotted: the "
          "headline metrics (coverage, targets_found, covered_cells, deposits_sent) and the policy's field summary "
          "(`field.*`), those that differ between runs.\n\n";
    for (const auto& p : in.params) {
      if (!p.swept()) continue;
      md << "- `" << p.path << "`:";
      for (const auto& m : in.plotted) md << " [" << m << "](plots/" << plot_file(m, p.path) << ")";
      md << "\n";
    }
    md << "\n";
  }
}

void write_distributed_section(std::ostringstream& md, const MarkdownInput& in) {
  std::size_t equal = 0;
  for (const auto& c : *in.distributed) equal += c.equal ? 1 : 0;
  md << "## On real processes (`--distributed`)\n\n"
     << equal << " of " << in.distributed->size() << " sampled runs flown as `pheromesh run --clock lockstep --dds "
     << in.dds
     << "` gave the simulator's numbers (metrics.json) and a byte-identical final_field.txt.\n\n"
        "| run | combination | lockstep == sim | wall [s] |\n|---|---|---|---|\n";
  for (const auto& c : *in.distributed) {
    md << "| " << c.id << " | " << md_cell(c.cell) << " | " << md_cell(c.equal ? "yes" : "**no**: " + c.verdict)
       << " | " << fixed_text(c.seconds, 1) << " |\n";
  }
  md << "\n";
}

}  // namespace

std::string sweep_markdown(const MarkdownInput& in) {
  std::ostringstream md;
  std::size_t swept = 0;
  for (const auto& p : in.params) swept += p.swept() ? 1 : 0;
  write_sweep_intro(md, in);
  write_sweep_grid(md, in);
  md << "## Summary\n\nMean [95 % interval] over the seeds of each combination";
  if (in.plotted.empty()) {
    md << ": no metric differs between runs.\n\n";
  } else {
    write_summary_table(md, in, swept);
  }
  if (!in.constant.empty()) {
    md << "The same in every run (not plotted):";
    for (const auto& m : in.constant) md << " `" << m << "`";
    md << ".\n\n";
  }
  write_plots_section(md, in, swept);
  if (in.distributed) write_distributed_section(md, in);
  return md.str();
}

}  // namespace pheromesh::cli::sweep
