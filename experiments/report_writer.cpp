#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "experiment.hpp"
#include "flight.hpp"
#include "pheromesh/core/atomic_file.hpp"
#include "pheromesh/core/rng.hpp"

namespace pheromesh::cli::experiments {

double mean(const std::vector<double>& v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  double s = 0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

double stddev(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  const double m = mean(v);
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size() - 1));
}

namespace {

// Two-sided 97.5 % quantile of Student's t with `df` degrees of freedom.
double t975(std::size_t df) {
  static const double table[] = {12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
                                 2.201,  2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
                                 2.080,  2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042};
  if (df == 0) return std::numeric_limits<double>::quiet_NaN();
  if (df <= 30) return table[df - 1];
  if (df <= 60) return 2.042 + (2.000 - 2.042) * static_cast<double>(df - 30) / 30.0;
  if (df <= 120) return 2.000 + (1.980 - 2.000) * static_cast<double>(df - 60) / 60.0;
  return 1.960;
}

}  // namespace

Interval ci95(const std::vector<double>& v) {
  const double m = mean(v);
  if (v.size() < 2) return {m, m};
  const double h = t975(v.size() - 1) * stddev(v) / std::sqrt(static_cast<double>(v.size()));
  return {m - h, m + h};
}

std::string auto_verdict(const Row& r) {
  if (!r.paper) return "";
  const double m = mean(r.ours);
  if (!std::isfinite(m)) return "differs: no run produced it";
  const Interval ci = ci95(r.ours);
  const double p = *r.paper;
  // The interval only counts from 5 runs on: with 2 or 3 it is so wide it
  // would call almost anything reproduced.
  const bool in_ci = r.ours.size() >= 5 && p >= ci.lo && p <= ci.hi;
  if (in_ci || (p != 0 && std::fabs(m / p - 1) <= 0.15) || (p == 0 && m == 0)) return "reproduced";
  char b[96];
  if (p != 0) {
    std::snprintf(b, sizeof b, "differs: ours is %.0f %% %s", std::fabs(m / p - 1) * 100, m > p ? "higher" : "lower");
  } else {
    std::snprintf(b, sizeof b, "differs: ours is %.3g, the paper's 0", m);
  }
  return b;
}

Gain gain_of(const Comparison& c) {
  auto g = [&](double b, double v) { return b == 0 ? std::numeric_limits<double>::quiet_NaN() : (c.lower_is_better ? (b - v) / b : (v - b) / b); };
  Gain out;
  out.gain = g(mean(c.baseline_samples), mean(c.variant_samples));
  if (c.baseline_samples.size() < 2 || c.variant_samples.size() < 2) {
    out.ci = {out.gain, out.gain};
    return out;
  }
  core::Rng rng(0x5eed'9a1f'c0ffeeULL);
  constexpr int kResamples = 10000;
  std::vector<double> gains;
  gains.reserve(kResamples);
  auto resample_mean = [&](const std::vector<double>& v) {
    double s = 0;
    for (std::size_t i = 0; i < v.size(); ++i) s += v[rng.uniform_below(static_cast<uint32_t>(v.size()))];
    return s / static_cast<double>(v.size());
  };
  for (int i = 0; i < kResamples; ++i) {
    const double x = g(resample_mean(c.baseline_samples), resample_mean(c.variant_samples));
    if (std::isfinite(x)) gains.push_back(x);
  }
  std::sort(gains.begin(), gains.end());
  if (gains.empty()) return out;
  out.ci = {gains[static_cast<std::size_t>(0.025 * static_cast<double>(gains.size() - 1))],
            gains[static_cast<std::size_t>(0.975 * static_cast<double>(gains.size() - 1))]};
  return out;
}

namespace {

std::string num(double v, int prec = 2) {
  if (!std::isfinite(v)) return "–";
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", prec, v);
  return b;
}

std::string csv_escape(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string o = "\"";
  for (char c : s) o += c == '"' ? std::string("\"\"") : std::string(1, c);
  return o + "\"";
}

std::string xml_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '&': o += "&amp;"; break;
      default: o += c;
    }
  }
  return o;
}

}  // namespace

// A plain line chart: axes with ticks, one polyline per series, a legend.
std::string svg_plot(const Plot& p) {
  const double W = 720, H = 440, L = 70, R = 190, T = 40, B = 60;
  double x0 = std::numeric_limits<double>::max(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const auto& s : p.series) {
    for (const auto& [x, y] : s.points) {
      if (!std::isfinite(x) || !std::isfinite(y)) continue;
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  }
  if (x0 > x1) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  y0 = std::min(y0, 0.0);
  if (x1 == x0) x1 = x0 + 1;
  if (y1 == y0) y1 = y0 + 1;
  auto sx = [&](double x) { return L + (x - x0) / (x1 - x0) * (W - L - R); };
  auto sy = [&](double y) { return H - B - (y - y0) / (y1 - y0) * (H - T - B); };
  const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#17becf"};
  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
    << "\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  o << "<text x=\"" << W / 2 << "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">" << xml_escape(p.title) << "</text>\n";
  o << "<line x1=\"" << L << "\" y1=\"" << H - B << "\" x2=\"" << W - R << "\" y2=\"" << H - B << "\" stroke=\"black\"/>\n";
  o << "<line x1=\"" << L << "\" y1=\"" << T << "\" x2=\"" << L << "\" y2=\"" << H - B << "\" stroke=\"black\"/>\n";
  for (int i = 0; i <= 5; ++i) {
    const double xv = x0 + (x1 - x0) * i / 5.0, yv = y0 + (y1 - y0) * i / 5.0;
    o << "<text x=\"" << sx(xv) << "\" y=\"" << H - B + 18 << "\" text-anchor=\"middle\">" << num(xv, xv == std::round(xv) ? 0 : 2)
      << "</text>\n";
    o << "<text x=\"" << L - 6 << "\" y=\"" << sy(yv) + 4 << "\" text-anchor=\"end\">" << num(yv, std::fabs(y1 - y0) < 5 ? 2 : 0)
      << "</text>\n";
    o << "<line x1=\"" << L << "\" y1=\"" << sy(yv) << "\" x2=\"" << W - R << "\" y2=\"" << sy(yv)
      << "\" stroke=\"#ddd\"/>\n";
  }
  o << "<text x=\"" << (L + W - R) / 2 << "\" y=\"" << H - 15 << "\" text-anchor=\"middle\">" << xml_escape(p.x_label)
    << "</text>\n";
  o << "<text transform=\"translate(18," << (T + H - B) / 2 << ") rotate(-90)\" text-anchor=\"middle\">"
    << xml_escape(p.y_label) << "</text>\n";
  for (std::size_t i = 0; i < p.series.size(); ++i) {
    const auto& s = p.series[i];
    const char* c = colours[i % 7];
    o << "<polyline fill=\"none\" stroke=\"" << c << "\" stroke-width=\"2\" points=\"";
    for (const auto& [x, y] : s.points) {
      if (std::isfinite(x) && std::isfinite(y)) o << sx(x) << "," << sy(y) << " ";
    }
    o << "\"/>\n";
    for (const auto& [x, y] : s.points) {
      if (s.points.size() <= 30 && std::isfinite(x) && std::isfinite(y)) {
        o << "<circle cx=\"" << sx(x) << "\" cy=\"" << sy(y) << "\" r=\"3\" fill=\"" << c << "\"/>\n";
      }
    }
    const double ly = T + 10 + 20.0 * static_cast<double>(i);
    o << "<line x1=\"" << W - R + 15 << "\" y1=\"" << ly << "\" x2=\"" << W - R + 40 << "\" y2=\"" << ly << "\" stroke=\"" << c
      << "\" stroke-width=\"2\"/>\n<text x=\"" << W - R + 46 << "\" y=\"" << ly + 4 << "\">" << xml_escape(s.name)
      << "</text>\n";
  }
  o << "</svg>\n";
  return o.str();
}

namespace {

void write_rows_table(std::ostringstream& md, const Report& r) {
  md << "| metric | paper | ours (mean ± sd) | 95 % CI | runs | ours / paper | verdict | note |\n"
        "|---|---|---|---|---|---|---|---|\n";
  for (const auto& row : r.rows) {
    const double m = mean(row.ours);
    const Interval ci = ci95(row.ours);
    std::string verdict = row.verdict.empty() ? auto_verdict(row) : row.verdict;
    if (verdict.empty()) verdict = "–";
    md << "| " << row.metric << (row.unit.empty() ? "" : " [" + row.unit + "]") << " | "
       << (row.paper ? num(*row.paper) : "–") << " | " << num(m)
       << (row.ours.size() > 1 ? " ± " + num(stddev(row.ours)) : "") << " | "
       << (row.ours.size() > 1 ? num(ci.lo) + " – " + num(ci.hi) : "–") << " | " << row.ours.size() << " | "
       << (row.paper && *row.paper != 0 && std::isfinite(m) ? num(m / *row.paper, 3) : "–") << " | " << verdict << " | "
       << row.note << " |\n";
  }
}

void write_comparisons(std::ostringstream& md, const Report& r) {
  md << "\n## Our variants against the paper's policy\n\n"
        "Gain = improvement on the paper's policy as a share of its mean; its 95 % interval is a percentile "
        "bootstrap over the runs (10 000 resamples).\n\n"
        "| metric | paper's policy: mean [95 % CI] | variant: mean [95 % CI] | runs | gain [95 % CI] | ≥ 20 %? | note "
        "|\n"
        "|---|---|---|---|---|---|---|\n";
  for (const auto& c : r.comparisons) {
    const Interval cb = ci95(c.baseline_samples), cv = ci95(c.variant_samples);
    const Gain g = gain_of(c);
    const std::string meets = g.ci.lo >= 0.2 ? "yes (whole interval)" : g.gain >= 0.2 ? "mean only" : "no";
    md << "| " << c.metric << (c.unit.empty() ? "" : " [" + c.unit + "]") << " | " << c.baseline << ": "
       << num(mean(c.baseline_samples)) << " [" << num(cb.lo) << ", " << num(cb.hi) << "] | " << c.variant << ": "
       << num(mean(c.variant_samples)) << " [" << num(cv.lo) << ", " << num(cv.hi) << "] | "
       << c.baseline_samples.size() << " / " << c.variant_samples.size() << " | " << num(100 * g.gain, 1) << " % ["
       << num(100 * g.ci.lo, 1) << ", " << num(100 * g.ci.hi, 1) << "] | " << meets << " | " << c.note << " |\n";
  }
}

// The runs flown again by real processes (--distributed) against the simulator.
void write_distributed_checks(std::ostringstream& md, const std::vector<DistributedCheck>& checks) {
  std::size_t equal = 0;
  for (const auto& c : checks) equal += c.equal ? 1 : 0;
  md << "\n## The same runs on real processes (`--distributed`)\n\n"
     << equal << " of " << checks.size() << " runs flown by real processes (`pheromesh run --clock lockstep --dds "
     << distributed_options().dds
     << "`) gave exactly the simulator's numbers for the same scenario text and seed (metrics.json: ticks, "
        "coverage, covered cells, targets found, acquisition ticks, revisit responses, leader arrival, deposits "
        "sent, and every field summary).\n\n| run | equal | simulator [s] | processes [s] | differences |\n"
        "|---|---|---|---|---|\n";
  for (const auto& c : checks) {
    std::string d = c.differences;
    for (auto& ch : d) ch = ch == '\n' ? ';' : ch == '|' ? '/' : ch;
    const std::string dir = c.run_dir.empty() ? "" : std::filesystem::path(c.run_dir).filename().string() + ": ";
    md << "| " << dir << c.label << " | " << (c.equal ? "yes" : "**no**") << " | " << num(c.sim_seconds, 2) << " | "
       << num(c.process_seconds, 1) << " | " << (d.empty() ? "–" : d) << " |\n";
  }
}

std::string report_markdown(const Report& r, double wall_seconds) {
  std::ostringstream md;
  md << "# " << r.title << "\n\n";
  md << "*Source:* " << r.source << "  \n*Setup:* " << r.setup << "  \n*Wall time:* " << num(wall_seconds, 1) << " s"
     << (distributed_checks().empty() ? "" : " (with the runs on real processes)") << "\n\n";
  write_rows_table(md, r);
  if (!r.comparisons.empty()) write_comparisons(md, r);
  if (!r.tables.empty()) md << "\n" << r.tables << "\n";
  if (!r.investigation.empty()) md << "\n" << r.investigation << "\n";
  if (const auto& checks = distributed_checks(); !checks.empty()) write_distributed_checks(md, checks);
  for (const auto& p : r.plots) md << "\n![" << p.title << "](" << p.file << ")\n";
  if (!r.notes.empty()) {
    md << "\n## Notes\n\n";
    for (const auto& n : r.notes) md << "* " << n << "\n";
  }
  md << "\nRaw per-run values: [results.csv](results.csv)\n";
  return md.str();
}

std::string results_csv(const Report& r) {
  std::ostringstream csv;
  for (std::size_t i = 0; i < r.csv_header.size(); ++i) csv << (i ? "," : "") << csv_escape(r.csv_header[i]);
  csv << "\n";
  for (const auto& row : r.csv_rows) {
    for (std::size_t i = 0; i < row.size(); ++i) csv << (i ? "," : "") << csv_escape(row[i]);
    csv << "\n";
  }
  return csv.str();
}

}  // namespace

bool write_report(const Report& r, const std::string& out_dir, double wall_seconds, std::string& error) {
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  const std::filesystem::path dir(out_dir);
  // Built in memory and written atomically (core/atomic_file.hpp), so an
  // interrupted experiment leaves the previous report or none, never half.
  std::vector<std::pair<std::string, std::string>> files{{"report.md", report_markdown(r, wall_seconds)},
                                                         {"results.csv", results_csv(r)}};
  for (const auto& p : r.plots) files.emplace_back(p.file, svg_plot(p));
  for (const auto& [name, text] : files) {
    if (auto written = core::write_file_atomically((dir / name).string(), text); !written) {
      error = written.error().message;
      return false;
    }
  }
  return true;
}

}  // namespace pheromesh::cli::experiments
