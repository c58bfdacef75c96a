#include "metrics_merge.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

namespace pheromesh::cli {

namespace {

// Three decimals are plenty for seconds and MiB, and keep metrics.json readable.
double round3(double v) { return std::round(v * 1000.0) / 1000.0; }

nlohmann::json opt_json(const std::optional<double>& v) {
  return v ? nlohmann::json(round3(*v)) : nlohmann::json(nullptr);
}

std::optional<double> mean_of(const std::vector<double>& v) {
  if (v.empty()) return std::nullopt;
  double sum = 0;
  for (double x : v) sum += x;
  return sum / static_cast<double>(v.size());
}

std::optional<double> max_of(const std::vector<double>& v) {
  if (v.empty()) return std::nullopt;
  return *std::max_element(v.begin(), v.end());
}

nlohmann::json process_json(const ChildProcess& c) {
  nlohmann::json p = {
      {"name", c.name}, {"pid", c.pid}, {"dds", c.dds}, {"status", c.describe()}, {"crashed", c.crashed()}, {"killed_at_stop", c.killed_at_stop()}};
  p["cpu_user_s"] = c.reaped ? nlohmann::json(round3(c.cpu_user_s)) : nlohmann::json(nullptr);
  p["cpu_sys_s"] = c.reaped ? nlohmann::json(round3(c.cpu_sys_s)) : nlohmann::json(nullptr);
  p["max_rss_mib"] = c.reaped ? nlohmann::json(round3(c.max_rss_mib)) : nlohmann::json(nullptr);
  p["pss_mib"] = opt_json(c.sample ? c.sample->pss_mib : std::nullopt);
  p["rss_mib"] = opt_json(c.sample ? c.sample->rss_mib : std::nullopt);
  p["threads"] = c.sample && c.sample->threads ? nlohmann::json(*c.sample->threads) : nlohmann::json(nullptr);
  return p;
}

// Per role: sums of CPU, means over the processes sampled mid-flight.
struct RoleTotals {
  uint32_t count = 0, reaped = 0, sampled = 0;
  double user_s = 0, sys_s = 0, max_rss_sum = 0;
  std::vector<double> pss, rss, threads;

  void add(const ChildProcess& c) {
    ++count;
    if (c.reaped) {
      ++reaped;
      user_s += c.cpu_user_s;
      sys_s += c.cpu_sys_s;
      max_rss_sum += c.max_rss_mib;
    }
    if (!c.sample) return;
    ++sampled;
    if (c.sample->pss_mib) pss.push_back(*c.sample->pss_mib);
    if (c.sample->rss_mib) rss.push_back(*c.sample->rss_mib);
    if (c.sample->threads) threads.push_back(static_cast<double>(*c.sample->threads));
  }

  [[nodiscard]] nlohmann::json json() const {
    return {
        {"count", count},
        {"cpu_user_s", round3(user_s)},
        {"cpu_sys_s", round3(sys_s)},
        {"sampled", sampled},
        {"pss_mib_mean", opt_json(mean_of(pss))},
        {"pss_mib_max", opt_json(max_of(pss))},
        {"rss_mib_mean", opt_json(mean_of(rss))},
        {"max_rss_mib_mean", opt_json(reaped > 0 ? std::optional<double>(max_rss_sum / reaped) : std::nullopt)},
        {"threads_mean", opt_json(mean_of(threads))},
    };
  }
};

nlohmann::json resources_json(std::span<const ChildProcess> processes) {
  std::map<std::string, RoleTotals> roles{{"uav", {}}, {"place", {}}, {"ground", {}}};
  for (const auto& c : processes) roles[c.role].add(c);
  nlohmann::json resources = nlohmann::json::object();
  for (const auto& [role, t] : roles) resources[role] = t.json();
  return resources;
}

// /proc/net/snmp counts the IPv4 UDP datagrams of the whole host (its
// network namespace), not only this swarm's: anything else sending UDP
// meanwhile (another swarm, DNS, ...) is included. IPv6 is not counted
// (/proc/net/snmp6); the onehost profiles use IPv4 loopback.
void add_udp(nlohmann::json& m, const std::optional<UdpCounters>& start, const std::optional<UdpCounters>& end) {
  const bool udp =
      start && end && end->in_datagrams >= start->in_datagrams && end->out_datagrams >= start->out_datagrams;
  m["udp_in_datagrams"] = udp ? nlohmann::json(end->in_datagrams - start->in_datagrams) : nlohmann::json(nullptr);
  m["udp_out_datagrams"] = udp ? nlohmann::json(end->out_datagrams - start->out_datagrams) : nlohmann::json(nullptr);
}

// The steady window's per-role sums (the processes sampled at both ends).
struct SteadySums {
  std::map<std::string, double> cpu_ns, ctx_voluntary, ctx_involuntary, threads;
  uint32_t uavs = 0;
  uint32_t uavs_threads = 0;  // of them, those whose threads were read at both ends

  void add(const ChildProcess& c) {
    const auto& a = c.window_cpu[0];
    const auto& b = c.window_cpu[1];
    if (!a || !b || b->cpu_ns < a->cpu_ns) return;  // started, ended or restarted inside the window
    if (c.role == "uav") ++uavs;
    cpu_ns[c.role] += static_cast<double>(b->cpu_ns - a->cpu_ns);
    ctx_voluntary[c.role] += static_cast<double>(b->ctx_voluntary - std::min(a->ctx_voluntary, b->ctx_voluntary));
    ctx_involuntary[c.role] +=
        static_cast<double>(b->ctx_involuntary - std::min(a->ctx_involuntary, b->ctx_involuntary));
    if (!a->per_thread || !b->per_thread) return;
    if (c.role == "uav") ++uavs_threads;
    for (const auto& [group, ns] : b->thread_ns) {
      const auto it = a->thread_ns.find(group);
      const uint64_t before = it == a->thread_ns.end() ? 0 : it->second;
      if (ns > before) threads[c.role + "/" + group] += static_cast<double>(ns - before);
    }
  }
};

nlohmann::json per_tick(const std::map<std::string, double>& sums, double scale, bool with_all) {
  nlohmann::json j = nlohmann::json::object();
  double all = 0;
  for (const auto& [key, v] : sums) {
    j[key] = round3(v * scale);
    all += v;
  }
  if (with_all) j["all"] = round3(all * scale);
  return j;
}

}  // namespace

nlohmann::json steady_json(std::span<const ChildProcess> processes, const std::optional<SteadyWindow>& w) {
  if (!w || w->seconds <= 0 || w->rate_hz <= 0) return nullptr;
  SteadySums sums;
  for (const auto& c : processes) sums.add(c);
  // The UAV ticks due in the window: each UAV sampled at both ends flies one
  // per period (late ticks are reported beside, uav_late_share).
  const double uav_ticks = static_cast<double>(sums.uavs) * w->rate_hz * w->seconds;
  if (uav_ticks <= 0) return nullptr;
  const double ms = 1e-6 / uav_ticks;
  // The UAVs whose threads were read stand for all of them (every place
  // agent's and ground station's threads were read).
  if (sums.uavs_threads > 0 && sums.uavs_threads < sums.uavs) {
    const double all = static_cast<double>(sums.uavs) / static_cast<double>(sums.uavs_threads);
    for (auto& [key, ns] : sums.threads) {
      if (key.starts_with("uav/")) ns *= all;
    }
  }
  nlohmann::json j = {{"window_s", round3(w->seconds)},
                      {"uavs", sums.uavs},
                      {"uavs_threads_read", sums.uavs_threads},
                      {"uav_ticks", round3(uav_ticks)},
                      {"cpu_ms_per_uav_tick", per_tick(sums.cpu_ns, ms, true)},
                      {"ctx_voluntary_per_uav_tick", per_tick(sums.ctx_voluntary, 1.0 / uav_ticks, true)},
                      {"ctx_involuntary_per_uav_tick", per_tick(sums.ctx_involuntary, 1.0 / uav_ticks, true)},
                      {"threads_cpu_ms_per_uav_tick", per_tick(sums.threads, ms, false)}};
  const bool udp = w->udp_start && w->udp_end && w->udp_end->in_datagrams >= w->udp_start->in_datagrams;
  j["udp_in_per_uav_tick"] =
      udp ? nlohmann::json(
                round3(static_cast<double>(w->udp_end->in_datagrams - w->udp_start->in_datagrams) / uav_ticks))
          : nlohmann::json(nullptr);
  return j;
}

std::string metrics_path(const std::string& out_dir, const HostShare& share) {
  const bool ground_here = share.runs("ground", 0);
  return (std::filesystem::path(out_dir) /
          (ground_here ? std::string("metrics.json") : "host-" + std::to_string(share.host_index) + ".json"))
      .string();
}

std::optional<std::string> flight_shortfall(const nlohmann::json& m, std::span<const ChildProcess> processes,
                                            uint32_t ticks_asked) {
  if (ticks_asked == 0 || !m.contains("uavs_expected") || !m.contains("uav_status")) return std::nullopt;
  std::set<uint32_t> killed;
  for (const auto& c : processes) {
    if (c.role == "uav" && c.killed_on_purpose) killed.insert(c.index);
  }
  const auto expected = m["uavs_expected"].get<uint32_t>();
  const uint64_t ticks = ticks_asked;
  const nlohmann::json& status = m["uav_status"];
  uint64_t asked = 0, flown = 0;
  std::vector<uint32_t> unfinished;
  for (uint32_t u = 0; u < expected; ++u) {
    if (killed.contains(u)) continue;
    asked += ticks;
    const auto it = status.find(std::to_string(u));
    if (it == status.end()) {
      unfinished.push_back(u);  // never heard (merge_metrics says so too)
      continue;
    }
    const uint64_t heard = it->value("heard_tick", it->value("last_tick", uint64_t{0}));
    flown += std::min<uint64_t>(heard, ticks);
    // Heard at the run's last tick, it flew every tick: its final state
    // (finished) can be the one that did not arrive before the end (lockstep
    // under packet loss; a relay from another host). Measured in the fresh
    // clone's run: UAVs heard at tick 150 of 150 without a finished state.
    if (!it->value("finished", false) && heard < ticks) unfinished.push_back(u);
  }
  std::string why;
  if (asked > 0 && static_cast<double>(flown) < kFlownShareRequired * static_cast<double>(asked)) {
    char share[32];
    std::snprintf(share, sizeof share, "%.1f", 100.0 * static_cast<double>(flown) / static_cast<double>(asked));
    why = "the UAVs nobody killed flew " + std::to_string(flown) + " of the " + std::to_string(asked) +
          " UAV ticks asked for (" + share + " %, under the " +
          std::to_string(static_cast<int>(kFlownShareRequired * 100)) + " % a run must fly)";
  }
  if (!unfinished.empty()) {
    std::string ids;
    for (std::size_t i = 0; i < unfinished.size() && i < 10; ++i) ids += (i == 0 ? "" : ", ") + std::to_string(unfinished[i]);
    if (unfinished.size() > 10) ids += " and " + std::to_string(unfinished.size() - 10) + " more";
    why += (why.empty() ? "" : "; ") + std::string(unfinished.size() == 1 ? "uav " : "uavs ") + ids +
           " did not finish and nobody killed " + (unfinished.size() == 1 ? "it" : "them") +
           " (lost: liveliness, or its last states never reached the ground station)";
  }
  if (why.empty()) return std::nullopt;
  return "this run did not fly the swarm asked for: " + why + " (exit " +
         std::to_string(MergedMetrics::kExitShortfall) + ", docs/exit-codes.md)";
}

MergedMetrics merge_metrics(nlohmann::json ground, const RunRecord& run, const std::string& path) {
  MergedMetrics out;
  nlohmann::json& m = out.metrics;
  m = std::move(ground);
  if (m.is_null()) {
    if (run.share.runs("ground", 0)) out.errors.push_back("the ground station left no " + path);
    m = nlohmann::json::object();
  }
  if (run.share.multi_host()) {
    m["hosts"] = run.share.hosts;
    m["host_index"] = run.share.host_index;
    m["ground_host"] = run.share.ground_host;
  }
  for (const auto& [key, value] : run.faults.items()) m[key] = value;
  if (run.fault_failures > 0) {
    out.errors.push_back(std::to_string(run.fault_failures) +
                         " fault events could not be injected (metrics.json \"faults\")");
  }
  // Honest at the limit: a UAV the ground station never heard, nobody killed
  // on purpose, means the host did not bring up the swarm asked for; the
  // figures of the run are not those of that swarm.
  if (m.contains("uavs") && m.contains("uavs_expected")) {
    std::set<uint32_t> killed_uavs;
    for (const auto& c : run.processes) {
      if (c.role == "uav" && c.killed_on_purpose) killed_uavs.insert(c.index);
    }
    const auto heard = m["uavs"].get<uint64_t>(), expected = m["uavs_expected"].get<uint64_t>();
    if (heard + killed_uavs.size() < expected) {
      out.errors.push_back(std::to_string(expected - heard) + " of " + std::to_string(expected) +
                           " UAVs were never heard by the ground station: this run is not the swarm asked for. The "
                           "host may hold fewer processes (pheromesh bench scale), or they need longer to discover "
                           "each other (metrics.json discovery_s)");
    }
  }
  out.shortfall = flight_shortfall(m, run.processes, run.ticks_asked);
  if (run.ticks_asked > 0) m["uav_ticks_asked"] = uint64_t{run.ticks_asked} * m.value("uavs_expected", uint64_t{0});
  nlohmann::json procs = nlohmann::json::array();
  for (const auto& c : run.processes) {
    out.killed += c.killed_on_purpose ? 1 : 0;
    out.crashed += c.crashed() ? 1 : 0;
    out.killed_at_stop += c.killed_at_stop() ? 1 : 0;
    procs.push_back(process_json(c));
  }
  m["processes_killed"] = out.killed;
  // The launcher killed them, so it knows; the ground station's own count
  // (runtime/report.cpp) sees only what the lockstep clock lists absent, and
  // a realtime run's metrics said places_killed 0 after a place agent's kill.
  // Processes, as the simulator counts them (a standby is one more).
  const auto killed_as = [&](const std::string& role) {
    return std::count_if(run.processes.begin(), run.processes.end(),
                         [&](const auto& c) { return c.role == role && c.killed_on_purpose; });
  };
  if (out.killed > 0 || m.contains("uavs_killed")) {
    m["uavs_killed"] = killed_as("uav");
    m["places_killed"] = killed_as("place");
  }
  m["processes_crashed"] = out.crashed;
  m["processes_killed_at_stop"] = out.killed_at_stop;
  m["processes"] = std::move(procs);
  m["dds"] = run.dds;
  m["resources"] = resources_json(run.processes);
  // Left out where it does not apply: lockstep, or a flight that ended
  // before its window closed (docs/outputs.md).
  if (auto steady = steady_json(run.processes, run.steady); !steady.is_null()) m["steady"] = std::move(steady);
  m["resources_sampled_at_s"] = opt_json(run.resources_sampled_at_s);
  m["wall_s"] = opt_json(run.wall_s);
  m["run_t0_unix_ms"] = run.run_t0_unix_ms;
  add_udp(m, run.udp_start, run.udp_end);
  return out;
}

}  // namespace pheromesh::cli
