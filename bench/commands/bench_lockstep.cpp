#include "bench_lockstep.hpp"

#include "bench_floor.hpp"
#include "host_capacity.hpp"

#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "launch/child_spawn.hpp"
#include "experiments/flight.hpp"
#include "launch/launcher.hpp"
#include "pheromesh/bus/bus.hpp"
#include "pheromesh/core/atomic_file.hpp"
#include "pheromesh/core/conductor.hpp"
#include "pheromesh/core/sample_summary.hpp"
#include "pheromesh/core/simulator.hpp"
#include "pheromesh/runtime/process.hpp"
#include "pheromesh/cliutil/scenario_paths.hpp"

namespace pheromesh::cli {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

const char* const kBenchLockstepFooter =
    "\nWhat is measured, per swarm (SCENARIO:UAVS) and vendor:\n"
    "  sim      the in-process simulator flying the same scenario text (ms per tick, one core)\n"
    "  run      `pheromesh run FILE --clock lockstep --dds V` (FILE: the scenario with swarm.uavs and run.ticks set,\n"
    "           in OUT/<swarm>/scenario.textproto; its output in OUT/<swarm>/<V>/). ticks/s and the UAV and place\n"
    "           phase times come from the conductor (metrics.json \"lockstep\": from the clock it publishes to the\n"
    "           phase's completion); wall is the whole run, discovery and shutdown included\n"
    "  floor    the round trip of one pheromesh sample (clock -> PhaseDone) between this process and a child\n"
    "           process, per vendor pairing (mixed: cyclone -> fastdds), on loopback; a lockstep tick is at least\n"
    "           7 sequential hops (the lockstep tree: views and the UAV clock to the UAVs, their states to the\n"
    "           place agents and on with their reports to the conductor, the place clock to the place agents,\n"
    "           forwarded deposits, halo rings, tiles for the views; the place agents' reports travel while\n"
    "           the UAVs act), so floor = 7 x RTT/2\n"
    "  = sim    whether the run's numbers (ticks, coverage, targets, revisits, deposits, field summary) equal\n"
    "           the simulator's\n"
    "With --repeat N every run is flown N times (with --baseline the builds alternate, and every other round the\n"
    "baseline goes first); the report adds per build the median and range of ticks/s, and of this build's ratio\n"
    "to the baseline's run of the same round. One run moves by up to ±20 % on a busy 2-core host: a lever of\n"
    "10 % needs --repeat 5 or more.\n"
    "Results: OUT/lockstep.md and OUT/lockstep.json. Keep the host otherwise idle.\n";

namespace {

constexpr double kHopsPerTick = 7.0;

struct Swarm {
  std::string label;  // "small-test:10"
  core::ScenarioConfig scenario;
};

struct Row {
  std::string swarm, vendor;
  std::string build = "this";  // or "baseline" (--baseline)
  uint32_t round = 0;          // 0 .. --repeat - 1
  double sim_ms_per_tick = 0;
  double wall_s = 0;
  double ticks_per_s = 0;  // conducted
  core::SampleSummary uav_ms, place_ms;
  bool equal = false;
  bool flown = false;  // it ended and wrote metrics.json
  std::string error;  // the run failed, or how it differed
};

std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

core::Result<Swarm> load_swarm(const std::string& entry, uint32_t ticks) {
  const auto colon = entry.rfind(':');
  const std::string name = colon == std::string::npos ? entry : entry.substr(0, colon);
  auto path = resolve_scenario(name, default_scenario_dirs());
  if (!path) return path.error();
  auto base = core::load_scenario(path.value());
  if (!base) return base.error();
  uint32_t uavs = base->uavs;
  if (colon != std::string::npos) {
    try {
      std::size_t used = 0;
      const unsigned long n = std::stoul(entry.substr(colon + 1), &used);
      if (used != entry.size() - colon - 1 || n == 0 || n > 5000) throw std::invalid_argument("range");
      uavs = static_cast<uint32_t>(n);
    } catch (const std::exception&) {
      return core::Error{"--swarms entry '" + entry + "': UAVS after ':' must be a whole number from 1 to 5000"};
    }
  }
  const std::string patch = "swarm { uavs: " + std::to_string(uavs) + " } run { ticks: " + std::to_string(ticks) + " }";
  auto patched = core::patch_scenario(base.value(), patch, base->name);
  if (!patched) return core::Error{"--swarms entry '" + entry + "': " + patched.error().message};
  return Swarm{base->name + ":" + std::to_string(uavs), std::move(patched.value())};
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream o;
  o << f.rdbuf();
  return o.str();
}

Row fly_swarm(const Swarm& s, const std::string& vendor, double sim_ms, const experiments::RunNumbers& sim,
              const BenchLockstepOptions& o, const std::string& build, uint32_t round) {
  Row r;
  r.swarm = s.label;
  r.vendor = vendor;
  r.build = build;
  r.round = round;
  r.sim_ms_per_tick = sim_ms;
  const fs::path dir = fs::path(o.out_dir) / s.label.substr(0, s.label.find(':')) /
                       (std::to_string(s.scenario.uavs) + "-" + vendor + (build == "this" ? "" : "-" + build) +
                        (o.repeat > 1 ? "-r" + std::to_string(round + 1) : ""));
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir, ec);
  const fs::path file = dir / "scenario.textproto";
  if (auto w = core::write_file_atomically(file.string(), s.scenario.source_text); !w) {
    r.error = w.error().message;
    return r;
  }
  const std::string exe = build == "this" ? executable_dir() + "/pheromesh" : o.baseline;
  const std::vector<std::string> args{exe,
                                      "run",
                                      file.string(),
                                      "--clock",
                                      "lockstep",
                                      "--dds",
                                      vendor,
                                      "--domain",
                                      std::to_string(o.domain),
                                      "--out",
                                      (dir / "out").string(),
                                      "--no-record",
                                      "--progress",
                                      "10"};
  const double timeout_s = 300.0 + 0.5 * s.scenario.ticks * (1.0 + s.scenario.uavs / 10.0);
  bool timed_out = false;
  const auto t0 = Clock::now();
  const int status = run_bounded(args, (dir / "run.log").string(), timeout_s, timed_out);
  r.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  if (timed_out || status != 0) {
    r.error = timed_out ? "did not end within " + std::to_string(static_cast<int>(timeout_s)) + " s"
                        : "pheromesh run exited with " + std::to_string(status);
    r.error += " (" + (dir / "run.log").string() + ")";
    return r;
  }
  const std::string text = slurp(dir / "out" / "metrics.json");
  experiments::RunNumbers proc;
  std::string error;
  if (!experiments::numbers_from_metrics_json(text, proc, error)) {
    r.error = error;
    return r;
  }
  r.flown = true;
  r.error = experiments::differences(sim, proc);
  r.equal = r.error.empty();
  const auto j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_object() && j.contains("lockstep")) {
    const auto& l = j["lockstep"];
    r.ticks_per_s = l.value("ticks_per_s", 0.0);
    const auto read = [](const nlohmann::json& p) {
      core::SampleSummary m;
      m.n = p.value("n", std::size_t{0});
      m.mean = p.value("mean", 0.0);
      m.p50 = p.value("p50", 0.0);
      m.p90 = p.value("p90", 0.0);
      m.p99 = p.value("p99", 0.0);
      m.max = p.value("max", 0.0);
      return m;
    };
    r.uav_ms = read(l.value("uav_phase_ms", nlohmann::json::object()));
    r.place_ms = read(l.value("place_phase_ms", nlohmann::json::object()));
  }
  return r;
}

std::string fmt_ms(double v) { return fmt::format("{:.2f}", v); }

// Ticks/s from the conductor, or (a build whose ground station does not time
// its phases) the ticks over the whole run's wall time; 0 for a failed run.
double rate(const Row& r, uint32_t ticks) {
  if (!r.flown) return 0;
  if (r.ticks_per_s > 0) return r.ticks_per_s;
  return r.wall_s > 0 ? (ticks + 1) / r.wall_s : 0;
}

// What --repeat adds: per swarm, vendor and build the median (nearest rank)
// and range of ticks/s over its runs; with a baseline, the ratio of this
// build's ticks/s to the baseline's run of the same round (flown next to it).
struct Spread {
  std::string swarm, vendor, build;
  std::size_t runs = 0;
  double median = 0, min = 0, max = 0;
};

Spread spread_of(const std::string& swarm, const std::string& vendor, const std::string& build,
                 std::vector<double> values) {
  Spread s{swarm, vendor, build};
  if (values.empty()) return s;
  const auto sum = core::summarize(values);
  s.runs = sum.n;
  s.median = sum.p50;
  s.min = *std::min_element(values.begin(), values.end());
  s.max = sum.max;
  return s;
}

std::vector<Spread> spreads(const std::vector<Row>& rows, const BenchLockstepOptions& o) {
  std::vector<Spread> out;
  std::vector<std::pair<std::string, std::string>> seen;
  for (const auto& r : rows) {
    const std::pair<std::string, std::string> key{r.swarm, r.vendor};
    if (std::find(seen.begin(), seen.end(), key) != seen.end()) continue;
    seen.push_back(key);
    std::vector<double> mine, theirs, ratios;
    for (const auto& a : rows) {
      if (a.swarm != r.swarm || a.vendor != r.vendor || rate(a, o.ticks) <= 0) continue;
      (a.build == "this" ? mine : theirs).push_back(rate(a, o.ticks));
      if (a.build != "this") continue;
      for (const auto& b : rows) {
        if (b.build == "baseline" && b.swarm == a.swarm && b.vendor == a.vendor && b.round == a.round &&
            rate(b, o.ticks) > 0) {
          ratios.push_back(rate(a, o.ticks) / rate(b, o.ticks));
        }
      }
    }
    out.push_back(spread_of(r.swarm, r.vendor, "this", mine));
    if (!o.baseline.empty()) {
      out.push_back(spread_of(r.swarm, r.vendor, "baseline", theirs));
      out.push_back(spread_of(r.swarm, r.vendor, "this / baseline", ratios));
    }
  }
  return out;
}

std::string repeat_report(const std::vector<Row>& rows, const BenchLockstepOptions& o) {
  std::string md = fmt::format(
      "\n## Over {} runs each: median (nearest rank) and range\n\nticks/s from the conductor (a build without its "
      "phase times: ticks over the run's wall time); this / baseline: the ratio of the two runs of one round, "
      "flown one after the other, the order swapped every other round.\n\n"
      "| swarm | dds | build | runs | ticks/s median | min – max |\n|---|---|---|---|---|---|\n",
      o.repeat);
  for (const auto& s : spreads(rows, o)) {
    const bool ratio = s.build.find('/') != std::string::npos;
    const char* f = ratio ? "| {} | {} | {} | {} | {:.2f}× | {:.2f}× – {:.2f}× |\n"
                          : "| {} | {} | {} | {} | {:.1f} | {:.1f} – {:.1f} |\n";
    md += fmt::format(fmt::runtime(f), s.swarm, s.vendor, s.build, s.runs, s.median, s.min, s.max);
  }
  return md;
}

std::string report(const HostCapacity& host, const std::vector<Floor>& floors, const std::vector<Row>& rows,
                   const BenchLockstepOptions& o) {
  std::string md =
      fmt::format("# pheromesh bench lockstep\n\n{} ticks per run, {} round trips per pairing. Host: {}.\n\n", o.ticks,
                  o.pings, host.describe());
  md += "## Floor: one pheromesh sample there and back between two processes\n\n";
  md +=
      "| pairing | RTT p50 [ms] | RTT p99 [ms] | lost | floor per tick (7 hops) [ms] | floor [ticks/s] "
      "|\n|---|---|---|---|---|---|\n";
  for (const auto& f : floors) {
    if (!f.error.empty()) {
      md += fmt::format("| {} | – | – | – | – | {} |\n", f.pairing, f.error);
      continue;
    }
    const double floor_ms = kHopsPerTick * f.rtt_ms.p50 / 2.0;
    md += fmt::format("| {} | {} | {} | {} | {} | {:.0f} |\n", f.pairing, fmt_ms(f.rtt_ms.p50), fmt_ms(f.rtt_ms.p99),
                      f.lost, fmt_ms(floor_ms), floor_ms > 0 ? 1000.0 / floor_ms : 0.0);
  }
  md +=
      "\n## Lockstep runs\n\n| swarm | dds | build | run | ticks/s | ms/tick | UAV phase p50 / p99 [ms] | place phase "
      "p50 / p99 [ms] | sim [ms/tick] | × sim | × floor | wall [s] | = sim "
      "|\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    const double ms = r.ticks_per_s > 0 ? 1000.0 / r.ticks_per_s : 0.0;
    double floor_ms = 0;
    for (const auto& f : floors) {
      if (f.pairing == r.vendor && f.error.empty()) floor_ms = kHopsPerTick * f.rtt_ms.p50 / 2.0;
    }
    const std::string verdict = r.equal ? "yes" : "NO: " + r.error;
    if (ms == 0) {
      // A build whose ground station does not time its phases: the wall time
      // of the whole run (start-up and shutdown included) per tick.
      const double wall_ms = 1000.0 * r.wall_s / (o.ticks + 1);
      md += fmt::format("| {} | {} | {} | {} | {:.0f} (wall) | {} (wall) | – | – | {} | {:.0f} | {} | {:.1f} | {} |\n",
                        r.swarm, r.vendor, r.build, r.round + 1, 1000.0 / wall_ms, fmt_ms(wall_ms),
                        fmt_ms(r.sim_ms_per_tick), r.sim_ms_per_tick > 0 ? wall_ms / r.sim_ms_per_tick : 0.0,
                        floor_ms > 0 ? fmt::format("{:.1f}", wall_ms / floor_ms) : std::string("–"), r.wall_s, verdict);
      continue;
    }
    md += fmt::format("| {} | {} | {} | {} | {:.0f} | {} | {} / {} | {} / {} | {} | {:.0f} | {} | {:.1f} | {} |\n",
                      r.swarm, r.vendor, r.build, r.round + 1, r.ticks_per_s, fmt_ms(ms), fmt_ms(r.uav_ms.p50),
                      fmt_ms(r.uav_ms.p99), fmt_ms(r.place_ms.p50), fmt_ms(r.place_ms.p99), fmt_ms(r.sim_ms_per_tick),
                      r.sim_ms_per_tick > 0 ? ms / r.sim_ms_per_tick : 0.0,
                      floor_ms > 0 ? fmt::format("{:.1f}", ms / floor_ms) : std::string("–"), r.wall_s, verdict);
  }
  if (!o.baseline.empty()) {
    md += "\n## This build against the baseline (" + o.baseline + "): wall time of the same run\n\n";
    md += "| swarm | dds | run | baseline [s] | this build [s] | speed-up |\n|---|---|---|---|---|---|\n";
    for (const auto& b : rows) {
      if (b.build != "baseline") continue;
      for (const auto& r : rows) {
        if (r.build != "this" || r.swarm != b.swarm || r.vendor != b.vendor || r.round != b.round) continue;
        md += fmt::format("| {} | {} | {} | {:.1f} | {:.1f} | {:.1f}× |\n", r.swarm, r.vendor, r.round + 1, b.wall_s,
                          r.wall_s, r.wall_s > 0 ? b.wall_s / r.wall_s : 0.0);
      }
    }
  }
  if (o.repeat > 1) md += repeat_report(rows, o);
  return md;
}

nlohmann::json summary_json(const core::SampleSummary& s) {
  return {{"n", s.n}, {"mean", s.mean}, {"p50", s.p50}, {"p90", s.p90}, {"p99", s.p99}, {"max", s.max}};
}

nlohmann::json results_json(const HostCapacity& host, const std::vector<Floor>& floors, const std::vector<Row>& rows,
                            const BenchLockstepOptions& o) {
  nlohmann::json j{{"ticks", o.ticks},
                   {"pings", o.pings},
                   {"hops_per_tick", kHopsPerTick},
                   {"repeat", o.repeat},
                   {"host_capacity", host.to_json()}};
  for (const auto& f : floors) {
    j["floor"].push_back(
        {{"pairing", f.pairing}, {"rtt_ms", summary_json(f.rtt_ms)}, {"lost", f.lost}, {"error", f.error}});
  }
  for (const auto& r : rows) {
    j["runs"].push_back({{"swarm", r.swarm},
                         {"dds", r.vendor},
                         {"build", r.build},
                         {"round", r.round + 1},
                         {"ticks_per_s", r.ticks_per_s},
                         {"uav_phase_ms", summary_json(r.uav_ms)},
                         {"place_phase_ms", summary_json(r.place_ms)},
                         {"sim_ms_per_tick", r.sim_ms_per_tick},
                         {"wall_s", r.wall_s},
                         {"equal_to_sim", r.equal},
                         {"error", r.error}});
  }
  if (o.repeat > 1) {
    for (const auto& s : spreads(rows, o)) {
      j["medians"].push_back({{"swarm", s.swarm},
                              {"dds", s.vendor},
                              {"build", s.build},
                              {"runs", s.runs},
                              {"median", s.median},
                              {"min", s.min},
                              {"max", s.max}});
    }
  }
  return j;
}

// The floor of each vendor pairing, until a stop is asked for.
std::vector<Floor> measure_floors(const std::vector<std::string>& vendors, const BenchLockstepOptions& o) {
  std::vector<Floor> floors;
  for (const auto& v : vendors) {
    std::printf("floor %s: %u round trips ...\n", v.c_str(), o.pings);
    std::fflush(stdout);
    floors.push_back(measure_floor({v, o.domain + 1, o.pings, o.out_dir}));
    if (runtime::shutdown_requested()) break;
  }
  return floors;
}

}  // namespace

int run_bench_lockstep(const BenchLockstepOptions& o) {
  std::vector<Swarm> swarms;
  for (const auto& entry : split(o.swarms)) {
    auto s = load_swarm(entry, o.ticks);
    if (!s) {
      std::fprintf(stderr, "pheromesh bench lockstep: %s\n", s.error().message.c_str());
      return 2;
    }
    swarms.push_back(std::move(s.value()));
  }
  const auto vendors = split(o.dds);
  for (const auto& v : vendors) {
    if (v != "cyclone" && v != "fastdds" && v != "mixed") {
      std::fprintf(stderr, "pheromesh bench lockstep: --dds '%s': each vendor must be cyclone, fastdds or mixed\n",
                   v.c_str());
      return 2;
    }
  }
  if (!o.baseline.empty() && access(o.baseline.c_str(), X_OK) != 0) {
    std::fprintf(stderr, "pheromesh bench lockstep: --baseline '%s' is not an executable pheromesh\n",
                 o.baseline.c_str());
    return 2;
  }
  if (swarms.empty() || vendors.empty()) {
    std::fprintf(stderr, "pheromesh bench lockstep: --swarms and --dds must each name at least one\n");
    return 2;
  }
  std::error_code ec;
  fs::create_directories(o.out_dir, ec);
  // What the host's threads give together today (host_capacity.hpp): one
  // second alone, one all at once.
  const HostCapacity host = measure_host_capacity(std::chrono::seconds(1));
  std::printf("host: %s\n", host.describe().c_str());
  const std::vector<Floor> floors = measure_floors(vendors, o);
  if (runtime::shutdown_requested()) return 130;
  std::vector<Row> rows;
  bool all_equal = true;
  for (const auto& s : swarms) {
    const auto t0 = Clock::now();
    core::Simulator sim(s.scenario);
    sim.run();
    const double sim_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count() / (s.scenario.ticks + 1);
    const auto numbers = experiments::numbers_of(sim.recorder());
    for (const auto& v : vendors) {
      for (uint32_t round = 0; round < o.repeat; ++round) {
        // With a baseline, every other round flies it first.
        std::vector<std::string> builds{"this"};
        if (!o.baseline.empty()) builds.insert(round % 2 == 1 ? builds.begin() : builds.end(), "baseline");
        for (const auto& build : builds) {
          std::printf("%s over %s%s%s: %u lockstep ticks ...\n", s.label.c_str(), v.c_str(),
                      build == "this" ? "" : " with the baseline build",
                      o.repeat > 1 ? fmt::format(" (round {} of {})", round + 1, o.repeat).c_str() : "",
                      s.scenario.ticks);
          std::fflush(stdout);
          rows.push_back(fly_swarm(s, v, sim_ms, numbers, o, build, round));
          all_equal = all_equal && rows.back().equal;
          if (runtime::shutdown_requested()) return 130;
        }
      }
    }
  }
  const std::string md = report(host, floors, rows, o);
  std::printf("\n%s", md.c_str());
  const fs::path dir(o.out_dir);
  if (auto w = core::write_file_atomically((dir / "lockstep.md").string(), md); !w) {
    std::fprintf(stderr, "%s\n", w.error().message.c_str());
    return 5;
  }
  if (auto w = core::write_file_atomically((dir / "lockstep.json").string(),
                                           results_json(host, floors, rows, o).dump(2) + "\n");
      !w) {
    std::fprintf(stderr, "%s\n", w.error().message.c_str());
    return 5;
  }
  return all_equal ? 0 : 4;
}

}  // namespace pheromesh::cli
