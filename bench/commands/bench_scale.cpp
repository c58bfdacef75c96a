#include "bench_scale.hpp"

#include "bench_floor.hpp"
#include "host_capacity.hpp"

#include <fcntl.h>
#include <sys/utsname.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <thread>
#include <vector>

#include "launch/child_spawn.hpp"
#include "experiments/experiment.hpp"
#include "launch/launcher.hpp"
#include "pheromesh/bus/bus.hpp"
#include "pheromesh/core/atomic_file.hpp"
#include "pheromesh/runtime/process.hpp"
#include "pheromesh/report/report.hpp"

namespace pheromesh::cli {

const char* const kBenchScaleFooter =
    "What is measured, per vendor and swarm size N (each row is one `pheromesh run SCENARIO --uavs N --rate R\n"
    "--ticks T --lease-ms L --dds V --domain D --out OUT/V-N --progress 5`, whose output is in OUT/V-N/run.txt):\n"
    "  late %       share of UAV ticks that started more than one period late (ground station: uav_late_share,\n"
    "               and the worst UAV's, uav_late_share_max): the host no longer keeps the rate\n"
    "  discovery s  launch -> the ground station has heard every UAV and place agent (discovery_s)\n"
    "  CPU ms/tick  CPU time from wait4()'s rusage of every process (user and system separately for the UAVs,\n"
    "               user + system of all processes for the swarm) divided by the UAV ticks flown\n"
    "  PSS, RSS     MiB per process, mean per role, from /proc/PID/smaps_rollup read once, at 60 % of the\n"
    "               flight (PSS shares the pages of the DDS libraries among the processes that map them)\n"
    "  threads      per process (/proc/PID/status at the same moment), mean per role\n"
    "  UDP in/tick  IPv4 UDP datagrams received on the whole host (/proc/net/snmp, before the first spawn and\n"
    "               after the last process ended) per UAV tick: anything else on the host using UDP counts too\n"
    "  flying       the same while the swarm flies: from a fifth to four fifths of the flight after the ground\n"
    "               station's start (discovery and the end left out), per UAV tick due in that window (UAVs running\n"
    "               at both ends x rate x window); in scale.md's budget table also by role (UAV, place agent,\n"
    "               ground station), by thread (/proc/PID/task/*/schedstat, grouped by name: every place agent's\n"
    "               and the ground station's, and at most 200 UAVs' standing for all; the other UAVs from\n"
    "               /proc/PID/stat) and context switches (/proc/PID/status: waits and preemptions). Realtime only\n"
    "  host         before the runs: a CPU-bound loop for 1 s on one thread, then on every hardware thread at\n"
    "               once, and their work together as a multiple of one's: near 2 on two cores of their own, less\n"
    "               on hyper-threads or busy virtual CPUs, where a CPU-second does less work while all are busy;\n"
    "               and what a wake-up costs (a thread and another over two pipes, 20 000 round trips or 2 s)\n"
    "  floor        per vendor, before the runs: --floor-pings round trips between this process and a child\n"
    "               (`pheromesh bench lockstep-echo`) of a sample of --floor-view-bytes down and one of\n"
    "               --floor-uplink-bytes up, and the CPU both spent per round trip (/proc/PID/task/*/schedstat):\n"
    "               what one UAV tick (its view in, its state out) cannot cost less than; scale.md sets the\n"
    "               flying swarm CPU per UAV tick against it\n"
    "With --repeat K each size runs K times (a row each); a size holds only if every one of its runs held.\n"
    "A vendor's larger sizes are skipped once a size has more late ticks than --stop-late-share. Missing figures\n"
    "are printed as n/a. Results: OUT/scale.md (the table), OUT/scale.csv, OUT/scale.json and OUT/*.svg plots.\n"
    "Keep the host otherwise idle; on a small host stop early with --max.\n\n"
    "Example:\n"
    "  pheromesh bench scale scenarios/scale-100x100.textproto --max 400 --dds cyclone,fastdds\n"
    "  pheromesh bench scale scenarios/scale-100x100.textproto --sizes 50,100 --ticks 200 --extra \"--dds-profile "
    "default\"\n";

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using Value = std::optional<double>;

// The figures of one row, in table order. Shares are printed in percent.
struct Column {
  const char* key;     // CSV and JSON name
  const char* header;  // Markdown header
  int precision;
};
const std::vector<Column>& columns() {
  static const std::vector<Column> c{
      {"wall_s", "wall s", 1},
      {"discovery_s", "disc. s", 1},
      {"late_pct", "late %", 2},
      {"late_max_pct", "late max %", 1},
      {"uav_cpu_user_ms_per_tick", "UAV usr ms/tick", 2},
      {"uav_cpu_sys_ms_per_tick", "UAV sys ms/tick", 2},
      {"swarm_cpu_ms_per_tick", "swarm ms/tick", 2},
      {"flying_cpu_ms_per_tick", "flying ms/tick", 3},
      {"pss_uav_mib", "PSS uav MiB", 1},
      {"pss_place_mib", "PSS place MiB", 1},
      {"pss_ground_mib", "PSS ground MiB", 1},
      {"rss_uav_mib", "RSS uav MiB", 1},
      {"rss_place_mib", "RSS place MiB", 1},
      {"rss_ground_mib", "RSS ground MiB", 1},
      {"threads_uav", "thr uav", 1},
      {"threads_place", "thr place", 1},
      {"udp_in_per_tick", "UDP in/tick", 1},
      {"flying_udp_in_per_tick", "flying UDP/tick", 1},
      {"uav_ticks_flown", "ticks flown", 0},
      {"processes_crashed", "crashed", 0},
      {"uav_lost", "lost", 0},
  };
  return c;
}

struct ScaleRow {
  std::string vendor;
  uint32_t uavs = 0;
  uint32_t run = 1;  // 1 .. --repeat
  int exit_code = -1;
  std::string dir;
  std::map<std::string, Value> v;
  Json steady;  // metrics.json "steady": the flight's budget per UAV tick
  [[nodiscard]] Value get(const std::string& key) const {
    const auto it = v.find(key);
    return it == v.end() ? std::nullopt : it->second;
  }
};

std::vector<std::string> split(const std::string& s, const char* seps) {
  std::vector<std::string> out;
  std::size_t pos = 0;
  while (pos <= s.size()) {
    const std::size_t b = s.find_first_not_of(seps, pos);
    if (b == std::string::npos) break;
    const std::size_t e = s.find_first_of(seps, b);
    out.push_back(s.substr(b, e == std::string::npos ? std::string::npos : e - b));
    pos = e == std::string::npos ? s.size() + 1 : e;
  }
  return out;
}

std::optional<std::vector<uint32_t>> parse_sizes(const std::string& text, std::string& error) {
  std::vector<uint32_t> sizes;
  for (const auto& word : split(text, ", ")) {
    char* end = nullptr;
    errno = 0;
    const unsigned long n = std::strtoul(word.c_str(), &end, 10);
    if (end == word.c_str() || *end != '\0' || errno != 0 || n == 0 || n > 100000 || word[0] == '-') {
      error = "--sizes: '" + word + "' is not a UAV count (a whole number from 1)";
      return std::nullopt;
    }
    sizes.push_back(static_cast<uint32_t>(n));
  }
  if (sizes.empty()) {
    error = "--sizes: no size given";
    return std::nullopt;
  }
  std::sort(sizes.begin(), sizes.end());
  sizes.erase(std::unique(sizes.begin(), sizes.end()), sizes.end());
  return sizes;
}

// A number of metrics.json at a dotted path; nothing if absent, null or not a number.
Value number_at(const Json& j, const std::string& path) {
  const Json* node = &j;
  for (const auto& key : split(path, ".")) {
    if (!node->is_object()) return std::nullopt;
    const auto it = node->find(key);
    if (it == node->end()) return std::nullopt;
    node = &*it;
  }
  if (!node->is_number()) return std::nullopt;
  return node->get<double>();
}

Value times(Value a, double k) { return a ? Value(*a * k) : std::nullopt; }
Value per(Value a, Value b) { return a && b && *b > 0 ? Value(*a / *b) : std::nullopt; }
Value plus(Value a, Value b) { return a && b ? Value(*a + *b) : std::nullopt; }

// The row's figures from a run's metrics.json (as written by the ground
// station and completed by the launcher).
void fill_row(ScaleRow& row, const Json& m) {
  const Value ticks = number_at(m, "uav_ticks_flown");
  row.v["wall_s"] = number_at(m, "wall_s");
  row.v["discovery_s"] = number_at(m, "discovery_s");
  row.v["late_pct"] = times(number_at(m, "uav_late_share"), 100.0);
  row.v["late_max_pct"] = times(number_at(m, "uav_late_share_max"), 100.0);
  row.v["uav_cpu_user_ms_per_tick"] = times(per(number_at(m, "resources.uav.cpu_user_s"), ticks), 1000.0);
  row.v["uav_cpu_sys_ms_per_tick"] = times(per(number_at(m, "resources.uav.cpu_sys_s"), ticks), 1000.0);
  Value swarm_cpu = 0.0;
  for (const char* role : {"uav", "place", "ground"}) {
    const std::string r = std::string("resources.") + role;
    swarm_cpu = plus(swarm_cpu, plus(number_at(m, r + ".cpu_user_s"), number_at(m, r + ".cpu_sys_s")));
  }
  row.v["swarm_cpu_ms_per_tick"] = times(per(swarm_cpu, ticks), 1000.0);
  for (const char* role : {"uav", "place", "ground"}) {
    const std::string r = std::string("resources.") + role;
    row.v[std::string("pss_") + role + "_mib"] = number_at(m, r + ".pss_mib_mean");
    row.v[std::string("rss_") + role + "_mib"] = number_at(m, r + ".rss_mib_mean");
  }
  row.v["threads_uav"] = number_at(m, "resources.uav.threads_mean");
  row.v["threads_place"] = number_at(m, "resources.place.threads_mean");
  row.v["udp_in_per_tick"] = per(number_at(m, "udp_in_datagrams"), ticks);
  row.v["uav_ticks_flown"] = ticks;
  row.v["flying_cpu_ms_per_tick"] = number_at(m, "steady.cpu_ms_per_uav_tick.all");
  row.v["flying_udp_in_per_tick"] = number_at(m, "steady.udp_in_per_uav_tick");
  row.steady = m.value("steady", Json());
  row.v["processes_crashed"] = number_at(m, "processes_crashed");
  row.v["uav_lost"] = number_at(m, "uav_lost");
}

std::string fmt_value(Value v, int precision) {
  if (!v || !std::isfinite(*v)) return "n/a";
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", precision, *v);
  return b;
}

// For the CSV and JSON: whole numbers as such, the rest to four decimals
// (finer than any of these measurements).
Value rounded(Value v, int precision) {
  if (!v || !std::isfinite(*v)) return std::nullopt;
  const double scale = precision == 0 ? 1.0 : 1e4;
  return std::round(*v * scale) / scale;
}

std::string markdown_table(const std::vector<ScaleRow>& rows) {
  std::ostringstream o;
  o << "| vendor | N | exit |";
  for (const auto& c : columns()) o << " " << c.header << " |";
  o << "\n|---|--:|--:|";
  for (std::size_t i = 0; i < columns().size(); ++i) o << "--:|";
  o << "\n";
  for (const auto& r : rows) {
    o << "| " << r.vendor << (r.run > 1 ? " (run " + std::to_string(r.run) + ")" : std::string()) << " | " << r.uavs
      << " | " << r.exit_code << " |";
    for (const auto& c : columns()) o << " " << fmt_value(r.get(c.key), c.precision) << " |";
    o << "\n";
  }
  return o.str();
}

// The steady window's budget of one UAV tick, per row: CPU by role and by
// thread group, context switches, datagrams (metrics.json "steady").
std::string budget_table(const std::vector<ScaleRow>& rows) {
  std::ostringstream o;
  o << "| vendor | N | window s | CPU ms/tick: all | UAV | place | ground | ctx switches/tick (waits + preempted) | "
       "UDP in/tick | threads: CPU ms/tick |\n|---|--:|--:|--:|--:|--:|--:|--:|--:|---|\n";
  for (const auto& r : rows) {
    if (!r.steady.is_object()) continue;
    const auto at = [&](const std::string& path) { return number_at(r.steady, path); };
    o << "| " << r.vendor << (r.run > 1 ? " (run " + std::to_string(r.run) + ")" : std::string()) << " | " << r.uavs
      << " | " << fmt_value(at("window_s"), 1);
    for (const char* role : {"all", "uav", "place", "ground"}) {
      o << " | " << fmt_value(at(std::string("cpu_ms_per_uav_tick.") + role), 3);
    }
    o << " | " << fmt_value(at("ctx_voluntary_per_uav_tick.all"), 1) << " + "
      << fmt_value(at("ctx_involuntary_per_uav_tick.all"), 1) << " | " << fmt_value(at("udp_in_per_uav_tick"), 1)
      << " |";
    // The thread groups, costliest first.
    std::vector<std::pair<double, std::string>> groups;
    const Json threads = r.steady.value("threads_cpu_ms_per_uav_tick", Json::object());
    for (const auto& [name, ms] : threads.items()) {
      if (ms.is_number() && ms.get<double>() >= 0.001) groups.emplace_back(ms.get<double>(), name);
    }
    std::sort(groups.rbegin(), groups.rend());
    for (std::size_t i = 0; i < groups.size() && i < 8; ++i) {
      o << (i == 0 ? " " : ", ") << groups[i].second << " " << fmt_value(groups[i].first, 3);
    }
    o << " |\n";
  }
  return o.str();
}

// Per vendor: the largest N that held (exit 0, every UAV flew its ticks, at
// most 1 % late: why_not_held) and the first N that did not, with why. A run
// that exited non-zero or flew nothing never counts as holding its size.
std::vector<std::string> summary_lines(const std::vector<ScaleRow>& rows, const std::vector<std::string>& vendors,
                                       uint32_t ticks, Json& json) {
  std::vector<std::string> lines;
  for (const auto& vendor : vendors) {
    std::vector<ScaleRun> runs;
    for (const auto& r : rows) {  // rows are in ascending N
      if (r.vendor == vendor) runs.push_back({r.uavs, r.exit_code, r.get("late_pct"), r.get("uav_ticks_flown")});
    }
    const bool any = !runs.empty();
    const HeldVerdict v = held_verdict(runs, ticks);
    const std::optional<uint32_t> largest_held = v.largest_held, first_failed = v.first_not_held;
    const std::string& first_failed_why = v.why;
    std::string line = vendor + ": ";
    if (!any) {
      line += "no run";
    } else {
      line += "held up to N=" + (largest_held ? std::to_string(*largest_held) : std::string("none")) +
              " (exit 0, every UAV flew, <= 1 % of ticks late, in every run of the size)";
      line += first_failed ? "; first N that did not: " + std::to_string(*first_failed) + " (" + first_failed_why + ")"
                           : "; every size held";
    }
    lines.push_back(line);
    json[vendor] = {{"largest_n_held", largest_held ? Json(*largest_held) : Json(nullptr)},
                    {"first_n_not_held", first_failed ? Json(*first_failed) : Json(nullptr)},
                    {"first_n_not_held_why", first_failed ? Json(first_failed_why) : Json(nullptr)}};
  }
  return lines;
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string o = "\"";
  for (char c : s) o += c == '"' ? std::string("\"\"") : std::string(1, c);
  return o + "\"";
}

struct Plan {
  const BenchScaleOptions& o;
  std::vector<std::string> vendors;
  std::vector<uint32_t> sizes;
  std::vector<std::string> extra;
  std::string host;
  std::vector<Floor> floors;  // per vendor (--floor-pings)
  HostCapacity capacity;      // what the hardware threads give together (host_capacity.hpp)
};

// The floor per vendor, and each size's flying swarm CPU per UAV tick as a
// multiple of it.
std::string floor_table(const Plan& p, const std::vector<ScaleRow>& rows) {
  std::ostringstream o;
  o << "| vendor | view B down, uplink B up | RTT p50 / p99 ms | lost | floor: CPU ms per round trip | flying swarm "
       "CPU "
       "per UAV tick, x floor |\n|---|---|--:|--:|--:|---|\n";
  for (const auto& f : p.floors) {
    o << "| " << f.pairing << " | " << f.down_bytes << ", " << f.up_bytes << " | ";
    if (!f.error.empty()) {
      o << "n/a | n/a | n/a | " << f.error << " |\n";
      continue;
    }
    o << fmt_value(f.rtt_ms.p50, 3) << " / " << fmt_value(f.rtt_ms.p99, 3) << " | " << f.lost << " | "
      << fmt_value(f.cpu_ms, 4) << " |";
    std::string sep = " ";
    for (const auto& r : rows) {
      const Value flying = r.get("flying_cpu_ms_per_tick");
      if (r.vendor != f.pairing || !flying || !f.cpu_ms || *f.cpu_ms <= 0) continue;
      o << sep << "N=" << r.uavs << ": " << fmt_value(flying, 3) << " ms = " << fmt_value(*flying / *f.cpu_ms, 1)
        << "x";
      sep = "; ";
    }
    o << " |\n";
  }
  return o.str();
}

std::string host_description() {
  utsname u{};
  std::string kernel = uname(&u) == 0 ? std::string(u.sysname) + " " + u.release : "unknown kernel";
  return std::to_string(std::thread::hardware_concurrency()) + " hardware threads, " + kernel;
}

std::string scale_markdown(const Plan& p, const std::vector<ScaleRow>& rows, const std::vector<std::string>& lines,
                           const std::vector<std::string>& skipped) {
  std::ostringstream md;
  md << "# pheromesh bench scale\n\n"
     << "*Scenario:* " << p.o.scenario << "  \n*Per run:* " << p.o.ticks << " ticks at " << p.o.rate_hz << " Hz, lease "
     << p.o.lease_ms << " ms, domain " << p.o.domain
     << (p.extra.empty() ? std::string() : ", extra `" + p.o.extra + "`") << "  \n*Host:* " << p.host << "; "
     << p.capacity.describe() << "\n\n"
     << markdown_table(rows) << "\n";
  for (const auto& l : lines) md << "* " << l << "\n";
  for (const auto& s : skipped) md << "* " << s << "\n";
  md << "\n## Where a UAV tick goes, while the swarm flies\n\n"
     << "From a fifth to four fifths of the flight after the ground station's start (metrics.json \"steady\"), per UAV "
        "tick due in that window:\n\n"
     << budget_table(rows);
  if (!p.floors.empty()) {
    md << "\n## The floor: a view down and an uplink up between two processes\n\n" << floor_table(p, rows);
  }
  md << "\n![late share](late_share.svg)\n![CPU per UAV tick](cpu_per_uav_tick.svg)\n"
     << "![PSS per UAV](pss_per_uav.svg)\n![discovery](discovery.svg)\n\n"
     << "## How it is measured\n\n```\n"
     << kBenchScaleFooter << "```\n\n"
     << "Each run's own output: `V-N/run.txt`, its metrics: `V-N/metrics.json`, its processes' logs: `V-N/logs/`.\n";
  return md.str();
}

std::string scale_csv(const std::vector<ScaleRow>& rows) {
  std::ostringstream csv;
  csv << "vendor,uavs,exit_code";
  for (const auto& c : columns()) csv << "," << c.key;
  csv << "\n";
  for (const auto& r : rows) {
    csv << csv_field(r.vendor) << "," << r.uavs << "," << r.exit_code;
    for (const auto& c : columns()) {
      csv << "," << fmt_value(rounded(r.get(c.key), c.precision), c.precision == 0 ? 0 : 4);
    }
    csv << "\n";
  }
  return csv.str();
}

Json scale_rows_json(const std::vector<ScaleRow>& rows) {
  Json j_rows = Json::array();
  for (const auto& r : rows) {
    Json jr = {
        {"vendor", r.vendor}, {"uavs", r.uavs}, {"exit_code", r.exit_code}, {"dir", r.dir}, {"steady", r.steady}};
    for (const auto& c : columns()) {
      const Value v = rounded(r.get(c.key), c.precision);
      if (!v) {
        jr[c.key] = nullptr;
      } else if (c.precision == 0) {
        jr[c.key] = static_cast<int64_t>(*v);
      } else {
        jr[c.key] = *v;
      }
    }
    j_rows.push_back(std::move(jr));
  }
  return j_rows;
}

// The plots as data: file, title, y label and the row field they draw.
struct ScalePlot {
  const char* file;
  const char* title;
  const char* y_label;
  const char* key;
};

constexpr std::array<ScalePlot, 4> kScalePlots{{
    {"late_share.svg", "Late UAV ticks vs swarm size", "late ticks [%]", "late_pct"},
    {"cpu_per_uav_tick.svg", "CPU of the whole swarm per UAV tick", "CPU user+sys [ms / UAV tick]",
     "swarm_cpu_ms_per_tick"},
    {"pss_per_uav.svg", "Memory per UAV process (PSS, mean)", "PSS [MiB]", "pss_uav_mib"},
    {"discovery.svg", "Discovery: launch to every process heard", "discovery [s]", "discovery_s"},
}};

// One line per vendor; a missing figure leaves a gap (the SVG writer skips it).
std::string scale_plot_svg(const Plan& p, const std::vector<ScaleRow>& rows, const ScalePlot& sp) {
  const char* file = sp.file;
  const char* title = sp.title;
  const char* y_label = sp.y_label;
  const char* key = sp.key;
  experiments::Plot pl{file, title, "UAVs (N)", y_label, {}};
  for (const auto& vendor : p.vendors) {
    experiments::Series s{vendor, {}};
    for (const auto& r : rows) {
      if (r.vendor != vendor) continue;
      const Value v = r.get(key);
      s.points.emplace_back(static_cast<double>(r.uavs), v ? *v : std::nan(""));
    }
    pl.series.push_back(std::move(s));
  }
  return experiments::svg_plot(pl);
}

Json floors_json(const std::vector<Floor>& floors) {
  Json out = Json::array();
  for (const auto& f : floors) {
    out.push_back({{"vendor", f.pairing},
                   {"down_bytes", f.down_bytes},
                   {"up_bytes", f.up_bytes},
                   {"rtt_ms_p50", f.rtt_ms.p50},
                   {"rtt_ms_p99", f.rtt_ms.p99},
                   {"lost", f.lost},
                   {"cpu_ms_per_round_trip", f.cpu_ms ? Json(*f.cpu_ms) : Json(nullptr)},
                   {"error", f.error}});
  }
  return out;
}

// Rewritten after every run, so that an interrupted bench leaves what it measured.
bool write_results(const Plan& p, const std::vector<ScaleRow>& rows, const std::vector<std::string>& skipped,
                   std::string& error) {
  const fs::path dir(p.o.out_dir);
  Json summary = Json::object();
  const auto lines = summary_lines(rows, p.vendors, p.o.ticks, summary);

  // Built in memory, written atomically (core/atomic_file.hpp): a bench
  // killed while writing leaves the previous run's results whole.
  std::vector<std::pair<std::string, std::string>> files;
  files.emplace_back("scale.md", scale_markdown(p, rows, lines, skipped));
  files.emplace_back("scale.csv", scale_csv(rows));
  const Json j_rows = scale_rows_json(rows);
  Json j = {{"scenario", p.o.scenario},
            {"ticks", p.o.ticks},
            {"rate_hz", p.o.rate_hz},
            {"lease_ms", p.o.lease_ms},
            {"domain", p.o.domain},
            {"extra", p.o.extra},
            {"host", p.host},
            {"rows", j_rows},
            {"summary", summary},
            {"skipped", skipped},
            {"floors", floors_json(p.floors)}};
  j["host_capacity"] = p.capacity.to_json();
  files.emplace_back("scale.json", report::json_text(j, 2) + "\n");
  for (const ScalePlot& sp : kScalePlots) files.emplace_back(sp.file, scale_plot_svg(p, rows, sp));
  for (const auto& [name, text] : files) {
    if (auto written = core::write_file_atomically((dir / name).string(), text); !written) {
      error = written.error().message;
      return false;
    }
  }
  return true;
}

// Runs one swarm; returns its exit code (128 + signal if signalled, -1 if it
// could not be started).
int run_swarm(const Plan& p, const std::string& vendor, uint32_t uavs, const fs::path& dir) {
  const std::string exe = executable_dir() + "/pheromesh";
  std::vector<std::string> args{exe,
                                "run",
                                p.o.scenario,
                                "--uavs",
                                std::to_string(uavs),
                                "--rate",
                                std::to_string(p.o.rate_hz),
                                "--ticks",
                                std::to_string(p.o.ticks),
                                "--lease-ms",
                                std::to_string(p.o.lease_ms),
                                "--dds",
                                vendor,
                                "--domain",
                                std::to_string(p.o.domain),
                                "--out",
                                dir.string(),
                                "--progress",
                                "5"};
  args.insert(args.end(), p.extra.begin(), p.extra.end());
  const std::string log = (dir / "run.txt").string();
  const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    std::fprintf(stderr, "cannot write %s: %s\n", log.c_str(), std::strerror(errno));
    return -1;
  }
  {
    std::string cmd;
    for (const auto& a : args) cmd += (cmd.empty() ? "" : " ") + a;
    cmd += "\n";
    if (write(fd, cmd.data(), cmd.size()) < 0) { /* the command line is only a courtesy */
    }
  }
  // Stays in our process group, so a Ctrl-C at the terminal reaches the
  // launcher, which stops its swarm in order; dies with us otherwise.
  const pid_t pid = spawn_logged_child(exe, args, fd, /*default_signals=*/false);
  if (pid < 0) {
    std::fprintf(stderr, "fork failed: %s\n", std::strerror(errno));
    close(fd);
    return -1;
  }
  close(fd);
  // The launcher bounds its own run; this only guards against a hung one:
  // three flights, 0.4 s per process, and five minutes.
  const double budget_s = 3.0 * p.o.ticks / p.o.rate_hz + 0.4 * (uavs + 20) + 300.0;
  const auto start = std::chrono::steady_clock::now();
  bool forwarded = false, timed_out = false;
  auto sigkill_at = std::chrono::steady_clock::time_point::max();  // none pending
  for (;;) {
    int status = 0;
    const pid_t r = waitpid(pid, &status, WNOHANG);
    if (r == pid) {
      if (WIFEXITED(status)) return WEXITSTATUS(status);
      if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
    } else if (r < 0 && errno != EINTR) {
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    const auto now = std::chrono::steady_clock::now();
    if (runtime::shutdown_requested() && !forwarded) {
      forwarded = true;  // the launcher stops its swarm in order on SIGINT
      kill(pid, SIGINT);
      sigkill_at = now + std::chrono::seconds(60);
    }
    if (!timed_out && std::chrono::duration<double>(now - start).count() > budget_s) {
      timed_out = true;
      std::fprintf(stderr, "  %s N=%u still running after %.0f s; interrupting it\n", vendor.c_str(), uavs, budget_s);
      kill(pid, SIGINT);
      sigkill_at = now + std::chrono::seconds(60);
    }
    if (now > sigkill_at) {
      kill(pid, SIGKILL);  // its processes die with it (PR_SET_PDEATHSIG)
      sigkill_at = std::chrono::steady_clock::time_point::max();
    }
  }
}

// The sizes and vendors of the bench, or the exit code of a refusal (said on
// stderr).
std::optional<int> plan_bench(const BenchScaleOptions& o, Plan& p) {
  std::string error;
  auto sizes = parse_sizes(o.sizes, error);
  if (!sizes) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 2;
  }
  if (o.max_uavs > 0)
    sizes->erase(std::remove_if(sizes->begin(), sizes->end(), [&](uint32_t n) { return n > o.max_uavs; }),
                 sizes->end());
  if (sizes->empty()) {
    std::fprintf(stderr, "no size left with --max %u\n", o.max_uavs);
    return 2;
  }
  p.sizes = *sizes;
  const auto available = bus::available_vendors();
  auto built = [&](const std::string& v) {
    return std::find(available.begin(), available.end(), v) != available.end();
  };
  for (const auto& v : split(o.dds, ", ")) {
    if (v != "cyclone" && v != "fastdds" && v != "mixed") {
      std::fprintf(stderr, "--dds: unknown vendor '%s' (cyclone, fastdds or mixed)\n", v.c_str());
      return 2;
    }
    if ((v == "mixed" && !(built("cyclone") && built("fastdds"))) || (v != "mixed" && !built(v))) {
      std::fprintf(stderr, "--dds: %s is not built into this pheromesh\n", v.c_str());
      return 2;
    }
    if (std::find(p.vendors.begin(), p.vendors.end(), v) == p.vendors.end()) p.vendors.push_back(v);
  }
  if (p.vendors.empty()) {
    std::fprintf(stderr, "--dds: no vendor given\n");
    return 2;
  }
  return std::nullopt;
}

// Run k of size n on `vendor`: its row, from its metrics.json (n/a without).
ScaleRow run_row(const Plan& p, const std::string& vendor, uint32_t n, uint32_t k, const std::string& progress) {
  const BenchScaleOptions& o = p.o;
  const std::string tag = vendor + "-" + std::to_string(n) + (o.repeat > 1 ? "-run" + std::to_string(k) : "");
  const fs::path dir = fs::path(o.out_dir) / tag;
  std::error_code ec;
  fs::create_directories(dir, ec);
  fs::remove(dir / "metrics.json", ec);  // never read an earlier bench's
  std::fprintf(stderr, "[%s] %s N=%u run %u of %u: running (output in %s) ...\n", progress.c_str(), vendor.c_str(), n,
               k, std::max(1U, o.repeat), (dir / "run.txt").c_str());
  ScaleRow row;
  row.vendor = vendor;
  row.run = k;
  row.uavs = n;
  row.dir = dir.string();
  row.exit_code = run_swarm(p, vendor, n, dir);
  Json m;
  if (std::ifstream in(dir / "metrics.json"); in) {
    try {
      in >> m;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "  %s: not valid JSON: %s\n", (dir / "metrics.json").c_str(), e.what());
      m = Json();
    }
  }
  if (m.is_object()) {
    fill_row(row, m);
    if (const Value u = number_at(m, "uavs"); u && *u != n) {
      std::fprintf(stderr, "  note: metrics.json says %.0f uavs, %u were asked for\n", *u, n);
    }
  } else {
    std::fprintf(stderr, "  no metrics.json: every figure of this row is n/a (see %s)\n", (dir / "run.txt").c_str());
  }
  std::fprintf(stderr, "  exit %d, wall %s s, discovery %s s, late %s %% (max %s %%), swarm CPU %s ms per UAV tick\n",
               row.exit_code, fmt_value(row.get("wall_s"), 1).c_str(), fmt_value(row.get("discovery_s"), 1).c_str(),
               fmt_value(row.get("late_pct"), 2).c_str(), fmt_value(row.get("late_max_pct"), 1).c_str(),
               fmt_value(row.get("swarm_cpu_ms_per_tick"), 2).c_str());
  return row;
}

// The table, the verdicts and where the results are, on stdout.
void print_results(const Plan& p, const std::vector<ScaleRow>& rows, const std::vector<std::string>& skipped) {
  std::printf("%s\n", markdown_table(rows).c_str());
  Json summary;
  for (const auto& l : summary_lines(rows, p.vendors, p.o.ticks, summary)) std::printf("%s\n", l.c_str());
  for (const auto& s : skipped) std::printf("%s\n", s.c_str());
  std::printf(
      "\n-> %s/scale.md, scale.csv, scale.json, late_share.svg, cpu_per_uav_tick.svg, pss_per_uav.svg, "
      "discovery.svg\n",
      p.o.out_dir.c_str());
}

}  // namespace

int run_bench_scale(const BenchScaleOptions& o) {
  Plan p{o, {}, {}, split(o.extra, " \t"), host_description(), {}, {}};
  if (const auto refused = plan_bench(o, p)) return *refused;
  std::error_code ec;
  fs::create_directories(o.out_dir, ec);
  if (ec) {
    std::fprintf(stderr, "cannot create %s: %s\n", o.out_dir.c_str(), ec.message().c_str());
    return 5;
  }
  runtime::install_shutdown_handlers();
  const std::size_t total = p.sizes.size() * p.vendors.size() * std::max(1U, o.repeat);
  std::fprintf(stderr, "bench scale: %s, sizes", o.scenario.c_str());
  for (auto n : p.sizes) std::fprintf(stderr, " %u", n);
  std::fprintf(stderr, ", vendors %s, %u ticks at %.1f Hz (%.0f s of flight per run); results in %s\n", o.dds.c_str(),
               o.ticks, o.rate_hz, o.ticks / o.rate_hz, o.out_dir.c_str());
  p.capacity = measure_host_capacity(std::chrono::seconds(1));
  std::fprintf(stderr, "host: %s\n", p.capacity.describe().c_str());
  for (const auto& vendor : p.vendors) {
    if (o.floor_pings == 0 || runtime::shutdown_requested()) break;
    std::fprintf(stderr, "floor %s: %u round trips of %u B down and %u B up ...\n", vendor.c_str(), o.floor_pings,
                 o.floor_view_bytes, o.floor_uplink_bytes);
    p.floors.push_back(
        measure_floor({vendor, o.domain + 1, o.floor_pings, o.out_dir, o.floor_view_bytes, o.floor_uplink_bytes}));
    const Floor& f = p.floors.back();
    if (!f.error.empty()) std::fprintf(stderr, "  floor %s: %s\n", vendor.c_str(), f.error.c_str());
  }
  std::vector<ScaleRow> rows;
  std::vector<std::string> skipped;
  std::map<std::string, uint32_t> stopped_at;  // vendor -> the size that exceeded --stop-late-share
  std::size_t done = 0;
  bool interrupted = false;
  std::string error;
  for (const uint32_t n : p.sizes) {
    for (const auto& vendor : p.vendors) {
      if (interrupted) break;
      if (const auto s = stopped_at.find(vendor); s != stopped_at.end()) {
        skipped.push_back(vendor + " N=" + std::to_string(n) + " skipped: late share above " +
                          fmt_value(o.stop_late_share * 100.0, 1) + " % at N=" + std::to_string(s->second));
        continue;
      }
      for (uint32_t k = 1; k <= std::max(1U, o.repeat) && !interrupted; ++k) {
        rows.push_back(run_row(p, vendor, n, k, std::to_string(++done) + "/" + std::to_string(total)));
        if (const Value late = rows.back().get("late_pct"); late && *late > 100.0 * o.stop_late_share) {
          stopped_at[vendor] = n;
          std::fprintf(stderr, "  late share above %.1f %%: no larger sizes for %s\n", 100.0 * o.stop_late_share,
                       vendor.c_str());
        }
        if (!write_results(p, rows, skipped, error)) {
          std::fprintf(stderr, "%s\n", error.c_str());
          return 5;
        }
        interrupted = runtime::shutdown_requested();
      }
    }
  }
  if (!write_results(p, rows, skipped, error)) {  // the sizes skipped after the last run
    std::fprintf(stderr, "%s\n", error.c_str());
    return 5;
  }
  print_results(p, rows, skipped);
  if (interrupted) {
    std::fprintf(stderr, "interrupted: the table holds the runs made so far\n");
    return 130;
  }
  return 0;
}

}  // namespace pheromesh::cli
