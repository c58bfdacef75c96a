// Does a requested swarm fit this host? The figures are what `pheromesh
// bench scale` measured on the 2-core CI machine (README, "Scale"); the
// launcher warns, with them, when a run asks for more.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <string_view>

namespace pheromesh::cli {

struct HostFit {
  // UAV processes whose discovery completed and whose ticks kept time
  // (< 1 % late) at 5 Hz on 2 cores, per vendor (bench scale, issue 12).
  static constexpr uint32_t kHeldOnTwoCores = 100;
  // The same in cells, the default profile, since issue 44 cut what a UAV
  // tick costs (bench scale --repeat 2, 150 ticks): Cyclone 2000 in each of
  // two runs (discovery 64-68 s, 0.08-0.34 % late; no larger size was run),
  // Fast DDS 1000 in each of two runs (discovery 138-164 s, none late).
  static constexpr uint32_t kCellsCycloneOnTwoCores = 2000;
  static constexpr uint32_t kCellsFastDdsOnTwoCores = 1000;
  static constexpr double kMeasuredRateHz = 5.0;
  static constexpr uint32_t kMeasuredCores = 2;
};

// A warning for `uavs` UAV processes at `rate_hz` on `cores` cores over
// `dds` (a DdsPlan spec), or nothing if the swarm is within what was
// measured (scaled by cores; the flight cost by the rate). Over several
// hosts `uavs` is this host's share. Header-only so
// that the unit tests use it without the CLI.
inline std::optional<std::string> host_fit_warning(uint32_t uavs, double rate_hz, unsigned cores, const std::string& dds,
                                            bool discovery_server, bool cells = false) {
  const double share = static_cast<double>(std::max(1U, cores)) / HostFit::kMeasuredCores;
  const uint32_t measured = !cells            ? HostFit::kHeldOnTwoCores
                            : dds == "cyclone" ? HostFit::kCellsCycloneOnTwoCores
                                               : HostFit::kCellsFastDdsOnTwoCores;
  const auto held = static_cast<uint32_t>(measured * share);
  // Discovery bounds the count whatever the rate; the flight cost grows
  // with UAVs x rate.
  const double flight_budget = measured * HostFit::kMeasuredRateHz * share;  // UAV ticks per second
  const auto fixed1 = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f", v);
    return std::string(buf);
  };
  std::string why;
  if (uavs > held && !discovery_server && cells) {
    // Discovery bounds the count: a lower rate would not help, more hosts do
    // (each host's cells discover only their own UAVs).
    why = std::to_string(uavs) + " UAV processes: on " + std::to_string(cores) +
          " cores `pheromesh bench scale` in cells held " + std::to_string(held) + " UAVs on time over " +
          (dds == "cyclone" ? "Cyclone (discovery 64-68 s at 2000; no larger swarm was measured)"
                            : "Fast DDS (discovery 2.3-2.7 min at 1000)") +
          "; split the swarm over more hosts (--hosts H --dds-peers A,B,..., docs/deployment.md): each holds as many";
  } else if (uavs > held && !discovery_server) {
    why = std::to_string(uavs) + " UAV processes: on " + std::to_string(cores) +
          " cores `pheromesh bench scale` saw flat discovery complete for " + std::to_string(held) +
          " UAVs (Cyclone 33.5 s, Fast DDS 20.8 s on 2 cores) and not for 150, where some UAVs never found their "
          "place agent; cells, the default profile (leave --dds-profile out), where each process discovers only "
          "those it talks to, held 2000 UAVs on Cyclone and 1000 on Fast DDS";
    if (dds == "fastdds") {
      why += "; with --dds fastdds, --discovery-server discovers through one server (250 UAVs on time in the benchmark)";
    }
  } else if (static_cast<double>(uavs) * rate_hz > flight_budget) {
    const double rate = std::floor(10.0 * flight_budget / uavs) / 10.0;
    why = std::to_string(uavs) + " UAVs at " + fixed1(rate_hz) + " Hz is more than the " +
          std::to_string(static_cast<int>(flight_budget)) + " UAV ticks per second held on time here; try --rate " +
          fixed1(std::max(rate, 0.1));
  }
  if (why.empty()) return std::nullopt;
  return why + " (README, \"Scale\")";
}

// Whether the kernel groups this process's session for the scheduler
// (autogroup), so that a place agent in a session of its own weighs as much
// as the herd of UAVs (launch/child_spawn.hpp, Scheduling): autogroup is on
// (`autogroup_enabled`, /proc/sys/kernel/sched_autogroup_enabled, "1") and
// the process is in the root CPU cgroup (`self_cgroup`, /proc/self/cgroup:
// the cgroup v1 hierarchy with the cpu controller, else the v2 one).
inline bool autogroup_applies(std::string_view autogroup_enabled, std::string_view self_cgroup) {
  if (autogroup_enabled.substr(0, 1) != "1") return false;
  std::optional<std::string_view> v1_cpu, v2;
  while (!self_cgroup.empty()) {
    const auto end = self_cgroup.find('\n');
    const std::string_view line = self_cgroup.substr(0, end);
    self_cgroup = end == std::string_view::npos ? std::string_view{} : self_cgroup.substr(end + 1);
    // ID:CONTROLLERS:PATH
    const auto a = line.find(':');
    const auto b = a == std::string_view::npos ? a : line.find(':', a + 1);
    if (b == std::string_view::npos) continue;
    const std::string_view controllers = line.substr(a + 1, b - a - 1);
    const std::string_view path = line.substr(b + 1);
    if (controllers.empty()) {
      v2 = path;
      continue;
    }
    for (std::string_view rest = controllers; !rest.empty();) {
      const auto comma = rest.find(',');
      if (rest.substr(0, comma) == "cpu") v1_cpu = path;
      rest = comma == std::string_view::npos ? std::string_view{} : rest.substr(comma + 1);
    }
  }
  const auto path = v1_cpu ? v1_cpu : v2;
  return path && *path == "/";
}

// Above this many UAV processes on one host the place agents' weight on the
// scheduler decided whether a realtime swarm flew at all (2000 Cyclone UAVs
// collapsed without sessions of their own; docs/benchmarks.md, "2000 UAV
// processes on two cores").
inline constexpr uint32_t kHubsStarveAbove = 1000;

// A warning for a realtime swarm of `uavs` UAV processes on this host when
// the place agents' sessions cannot lift them above the UAVs, or nothing.
inline std::optional<std::string> hub_weight_warning(uint32_t uavs, bool realtime, std::string_view autogroup_enabled,
                                                     std::string_view self_cgroup) {
  if (!realtime || uavs <= kHubsStarveAbove || autogroup_applies(autogroup_enabled, self_cgroup)) return std::nullopt;
  return std::to_string(uavs) +
         " UAV processes, and the kernel does not group sessions for this launcher (autogroup off, or a CPU cgroup "
         "other than the root, as a systemd login session's): the place agents compete with the UAVs as single "
         "processes and may stall while the UAVs are runnable; give them CPU of their own (docs/deployment.md, "
         "\"One host\")";
}

}  // namespace pheromesh::cli
