#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "experiment.hpp"
#include "pheromesh/core/atomic_file.hpp"

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

bool write_report(const Report& r, const std::string& out_dir, double wall_seconds, std::string& error) {
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  const std::filesystem::path dir(out_dir);
  // Built in memory and written atomically (core/atomic_file.hpp), so an
  // interrupted experiment leaves the previous report or none, never half.
  std::ostringstream md;
  md << "# " << r.title << "\n\n";
  md << "*Source:* " << r.source << "  \n*Setup:* " << r.setup << "  \n*Wall time:* " << num(wall_seconds, 1) << " s\n\n";
  md << "| metric | paper | ours (mean ± sd) | runs | ours / paper | note |\n|---|---|---|---|---|---|\n";
  for (const auto& row : r.rows) {
    const double m = mean(row.ours);
    md << "| " << row.metric << (row.unit.empty() ? "" : " [" + row.unit + "]") << " | "
       << (row.paper ? num(*row.paper) : "–") << " | " << num(m)
       << (row.ours.size() > 1 ? " ± " + num(stddev(row.ours)) : "") << " | " << row.ours.size() << " | "
       << (row.paper && *row.paper != 0 && std::isfinite(m) ? num(m / *row.paper, 3) : "–") << " | " << row.note << " |\n";
  }
  if (!r.tables.empty()) md << "\n" << r.tables << "\n";
  for (const auto& p : r.plots) md << "\n![" << p.title << "](" << p.file << ")\n";
  if (!r.notes.empty()) {
    md << "\n## Notes\n\n";
    for (const auto& n : r.notes) md << "* " << n << "\n";
  }
  md << "\nRaw per-run values: [results.csv](results.csv)\n";
  std::ostringstream csv;
  for (std::size_t i = 0; i < r.csv_header.size(); ++i) csv << (i ? "," : "") << csv_escape(r.csv_header[i]);
  csv << "\n";
  for (const auto& row : r.csv_rows) {
    for (std::size_t i = 0; i < row.size(); ++i) csv << (i ? "," : "") << csv_escape(row[i]);
    csv << "\n";
  }
  std::vector<std::pair<std::string, std::string>> files{{"report.md", md.str()}, {"results.csv", csv.str()}};
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
