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


}  // namespace pheromesh::cli
