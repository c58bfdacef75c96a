#include "launcher.hpp"

#include <spdlog/spdlog.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>
#include <variant>

#include "cli/scenario_overrides.hpp"
#include "cli/sim_command.hpp"
#include "host_fit.hpp"
#include "hosts_file.hpp"
#include "metrics_merge.hpp"
#include "netns.hpp"
#include "pheromesh/auth/control.hpp"
#include "pheromesh/bus/bus.hpp"
#include "pheromesh/bus/security.hpp"
#include "pheromesh/core/atomic_file.hpp"
#include "pheromesh/core/plugin_loader.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/scenario_warnings.hpp"
#include "pheromesh/report/report.hpp"
#include "pheromesh/runtime/process.hpp"
#include "proc_stats.hpp"
#include "supervisor.hpp"

namespace pheromesh::cli {

namespace fs = std::filesystem;

namespace {

// A run that ends before anything starts: its exit code and why.
struct Refusal {
  int exit_code = 2;
  std::string message;
};

void raise_fd_limit() {
  // Each DDS participant holds a dozen sockets and each child a log file;
  // children inherit the raised limit. The thread limit (RLIMIT_NPROC counts
  // every thread of the user) is raised alike, for a thousand DDS processes.
  for (const auto& [resource, name] :
       {std::pair{RLIMIT_NOFILE, "RLIMIT_NOFILE"}, std::pair{RLIMIT_NPROC, "RLIMIT_NPROC"}}) {
    rlimit rl{};
    if (getrlimit(resource, &rl) != 0) continue;
    if (rl.rlim_cur == rl.rlim_max) {
      spdlog::debug("{}: soft limit already at the hard limit ({})", name, rl.rlim_max);
      continue;
    }
    const rlim_t before = rl.rlim_cur;
    rl.rlim_cur = rl.rlim_max;
    if (setrlimit(resource, &rl) == 0) {
      spdlog::debug("{}: soft limit raised from {} to the hard limit {}", name, before, rl.rlim_max);
    } else {
      spdlog::debug("{}: cannot raise the soft limit {} to {}: {}", name, before, rl.rlim_max, std::strerror(errno));
    }
  }
}

// Whether `exe --help` mentions `flag`: the launcher passes flags that
// other parts of issue 14 add to the processes only when they are there.
bool takes_flag(const std::string& exe, const std::string& flag) {
  const ToolResult r = run_tool({exe, "--help"});
  return r.output.find(flag) != std::string::npos;
}

std::optional<Refusal> check_executables(const std::string& bin_dir) {
  for (const char* exe : {"pheromesh-uav", "pheromesh-place", "pheromesh-ground"}) {
    if (access((bin_dir + "/" + exe).c_str(), X_OK) != 0) {
      return Refusal{3, "cannot find " + std::string(exe) + " next to pheromesh in " + bin_dir};
    }
  }
  return std::nullopt;
}

// The plan's notes and its fault schedule, with what this build's ground
// station cannot do.
std::optional<Refusal> announce_faults(const RunPlan& plan) {
  for (const auto& note : plan.notes) {
    if (note.level == PlanNote::Level::Warn) {
      spdlog::warn("{}", note.text);
    } else {
      spdlog::info("{}", note.text);
    }
  }
  if (!plan.faults) return std::nullopt;
  if (plan.lockstep() && !takes_flag(plan.bin_dir + "/pheromesh-ground", "--fault-ticks")) {
    return Refusal{2,
                   "fault schedule: a lockstep run injects faults between ticks conducted by the ground station "
                   "(--fault-ticks), which this build's pheromesh-ground does not take yet"};
  }
  std::string items;
  for (const auto& e : plan.faults->events) items += (items.empty() ? "" : "; ") + e.text;
  spdlog::info("fault schedule ({} events): {}", plan.faults->events.size(), items);
  return std::nullopt;
}

// With --secure: an error naming the first process of this host without its
// identity, said before starting any (a missing one would stop that process
// at start).
std::optional<std::string> check_secure(const RunPlan& plan) {
  if (plan.options.secure.empty()) return std::nullopt;
  if (!plan.dds.single_vendor()) {
    // Measured (docs/security.md, "Mixed vendors"): Fast DDS 2.9.1 sends its
    // PKI-DH key-agreement value as raw bytes where Cyclone 0.10.2 expects an
    // ASN.1 integer, and no handshake between the two completes.
    return "--secure needs every process on one DDS vendor (--dds cyclone or --dds fastdds): the DDS Security "
           "handshakes of Cyclone DDS 0.10.2 and Fast DDS 2.9.1 do not interoperate (docs/security.md)";
  }
  if (auto e = bus::check_secure_profile(plan.dds.ground, plan.options.dds_profile, plan.cells.has_value())) return e;
  for (const auto& n : plan.identities()) {
    auto f = bus::find_security_files(plan.options.secure, n);
    if (!f) return f.error().message;
  }
  return std::nullopt;
}

std::optional<std::string> check_hosts(const RunPlan& plan) {
  auto key = auth::control_key_from_env();
  if (!key) return check_multi_host(plan, ControlKey::Malformed, key.error().message);
  return check_multi_host(plan, key.value() ? ControlKey::Set : ControlKey::Unset);
}

// A plugin's code is loaded on every host: over several hosts only a pin in
// the scenario file, which each host's copy carries, makes every process
// refuse a host with another build (the launcher's pin holds for its own host).
std::optional<std::string> check_plugin_pin(const RunPlan& plan, const core::ScenarioConfig& s) {
  if (!plan.multi_host() || !s.plugin || s.plugin->pinned_by == "the scenario") return std::nullopt;
  return "the policy " + s.policy + " is a plugin (" + s.plugin->library + ") and the swarm runs over " +
         std::to_string(plan.options.hosts) + " hosts: pin the library in the scenario, `policy { plugin { sha256: \"" +
         s.plugin->sha256 + "\" } }`, so that every host refuses another build (docs/writing-a-policy.md)";
}

// --hosts-file: --hosts, --dds-peers and this host's index from the file.
std::optional<std::string> apply_hosts_file(RunOptions& o) {
  if (o.hosts_file.empty()) return std::nullopt;
  auto file = read_hosts_file(o.hosts_file);
  if (!file) return file.error().message;
  HostsFlags flags;
  if (o.hosts_given) flags.hosts = o.hosts;
  if (o.host_index_given) flags.host_index = o.host_index;
  flags.dds_peers = o.dds_peers;
  flags.dds_peers_from = o.dds_peers_from;
  auto chosen = choose_host(file.value(), flags, is_local_address);
  if (!chosen) return chosen.error().message;
  o.hosts = chosen->hosts;
  o.host_index = chosen->host_index;
  o.dds_peers = chosen->dds_peers;
  spdlog::info("--hosts-file {}: {} hosts, this is host {} (line {}, {})", o.hosts_file, o.hosts, o.host_index,
               file->hosts[o.host_index].line, file->hosts[o.host_index].name);
  return std::nullopt;
}

// Cells over several hosts: --dds-peers as one IPv4 address per host, in
// host order, this host's among this host's addresses.
std::optional<std::string> resolve_host_addresses(RunOptions& o) {
  const bool cells = o.dds_profile.empty() || o.dds_profile == "cells";  // none given: cells
  if (!cells || o.hosts <= 1 || o.dds_peers.empty()) return std::nullopt;
  std::size_t start = 0;
  while (start <= o.dds_peers.size()) {
    const std::size_t comma = std::min(o.dds_peers.find(',', start), o.dds_peers.size());
    const std::string entry = o.dds_peers.substr(start, comma - start);
    start = comma + 1;
    auto resolved = bus::resolve_peers(entry);
    if (!resolved) return resolved.error().message;
    if (resolved->addresses.size() != 1) {
      return "--dds-peers: host " + std::to_string(o.host_addresses.size()) + " '" + entry + "' " +
             (resolved->addresses.empty() ? "does not resolve"
                                          : "resolves to " + std::to_string(resolved->addresses.size()) +
                                                " addresses; in cells each entry names one host, in host-index order");
    }
    o.host_addresses.push_back(resolved->addresses.front());
  }
  if (o.host_index < o.host_addresses.size() && !is_local_address(o.host_addresses[o.host_index])) {
    return "--dds-peers: entry " + std::to_string(o.host_index) + " (" + o.host_addresses[o.host_index] +
           ") is this host's (--host-index " + std::to_string(o.host_index) +
           "), but no interface of this host has that address";
  }
  return std::nullopt;
}

// The checks and the plan, in the order their errors are reported.
std::variant<RunPlan, Refusal> plan_run(RunOptions o, const core::ScenarioConfig& s) {
  auto dds = parse_dds_plan(o.dds, bus::available_vendors());
  if (!dds) return Refusal{2, dds.error().message};
  const std::string bin_dir = executable_dir();
  if (auto refused = check_executables(bin_dir)) return *refused;
  if (auto err = apply_hosts_file(o)) return Refusal{2, *err};
  if (auto err = resolve_host_addresses(o)) return Refusal{2, *err};
  auto plan = make_run_plan(o, s, dds.value(), bin_dir);
  if (!plan) return Refusal{2, plan.error().message};
  if (auto refused = announce_faults(plan.value())) return *refused;
  if (auto err = check_secure(plan.value())) return Refusal{2, *err};
  if (auto err = check_hosts(plan.value())) return Refusal{2, *err};
  if (auto err = check_plugin_pin(plan.value(), s)) return Refusal{2, *err};
  return std::move(plan).value();
}

void announce(const RunPlan& plan, const core::ScenarioConfig& s) {
  const RunOptions& o = plan.options;
  uint32_t places_here = 0, uavs_here = 0;
  for (const auto& p : plan.processes) {
    places_here += p.role == "place" ? 1 : 0;
    uavs_here += p.role == "uav" ? 1 : 0;
  }
  if (!plan.lockstep()) {
    if (auto w = host_fit_warning(uavs_here, plan.rate_hz, std::thread::hardware_concurrency(), o.dds,
                                  o.discovery_server, o.dds_profile == "cells")) {
      spdlog::warn("this swarm may not keep time on this host: {}", *w);
    }
  }
  if (auto w = hub_weight_warning(uavs_here, !plan.lockstep(),
                                  read_small_file("/proc/sys/kernel/sched_autogroup_enabled").value_or(""),
                                  read_small_file("/proc/self/cgroup").value_or(""))) {
    spdlog::warn("{}", *w);
  }
  spdlog::info(
      "run '{}' ({}): {} place agents, {} uavs, {} ticks, {} clock{}, over {} (domain {}, profile {}{}); logs in "
      "{}/logs",
      s.name, o.scenario, plan.regions, plan.uavs, plan.ticks, o.clock,
      plan.lockstep() ? "" : fmt::format(" at {:.1f} Hz", plan.rate_hz), plan.dds.describe(), o.domain, o.dds_profile,
      o.secure.empty() ? "" : ", DDS Security: identities in " + o.secure, o.out_dir);
  if (s.plugin || s.python) spdlog::info("policy {}", policy_summary(s));
  if (const auto attach = cells_attach_command(plan)) spdlog::info("watch it with: {}", *attach);
  if (!plan.multi_host()) return;
  spdlog::info("host {} of {}: {} place agents, {} uavs{} here; the ground station {}", o.host_index, o.hosts,
               places_here, uavs_here,
               plan.cells ? fmt::format(" (in cells, this host {})", plan.cells->address_of(o.host_index))
               : o.dds_peers.empty() ? ""
                                     : fmt::format(" (DDS peers {})", o.dds_peers),
               plan.share.runs("ground", 0) ? "too (it ends the run)" : fmt::format("on host {}", o.ground_host));
}

nlohmann::json read_ground_metrics(const std::string& path) {
  nlohmann::json m;
  std::ifstream in(path);
  if (in) {
    try {
      in >> m;
    } catch (const std::exception& e) {
      spdlog::error("{} is not valid JSON: {}", path, e.what());
    }
  }
  return m;
}

// OUT/metrics.json: the ground station's merged with what the supervisor saw
// (host-I.json on a host without the ground station). Returns the exit code.
// `interrupted`: stopped by SIGINT/SIGTERM (exit 130), which flies fewer
// ticks than asked by design: no shortfall error then.
int finish_metrics(const RunPlan& plan, const RunRecord& run, bool interrupted) {
  const bool ground_here = plan.share.runs("ground", 0);
  const std::string path = metrics_path(plan.options.out_dir, plan.share);
  const MergedMetrics merged = merge_metrics(ground_here ? read_ground_metrics(path) : nlohmann::json(), run, path);
  for (const auto& e : merged.errors) spdlog::error("{}", e);
  int exit_code = merged.exit_code();
  // Written over the ground station's file atomically: a launcher killed here
  // leaves the ground station's metrics.json, not half of the merged one.
  if (auto written = core::write_file_atomically(path, report::json_text(merged.metrics, 2) + "\n"); !written) {
    spdlog::error("{}", written.error().message);
    exit_code = 1;
  }
  const RunOptions& o = plan.options;
  if (!ground_here) {
    spdlog::info(
        "done on host {}: {} processes, killed {}, crashed {}, killed at the stop {} -> {} (the swarm's metrics.json is "
        "on host {})",
        o.host_index, run.processes.size(), merged.killed, merged.crashed, merged.killed_at_stop, path, o.ground_host);
    return exit_code;
  }
  const nlohmann::json& m = merged.metrics;
  spdlog::info(
      "done: coverage {:.1f}%, targets {}/{}, deposits sent {} applied {} rejected {}, killed {}, crashed {}{} -> {}",
      100.0 * m.value("coverage", 0.0), m.value("targets_found", 0), m.value("targets_total", 0),
      m.value("deposits_sent", 0), m.value("deposits_applied", 0), m.value("deposits_rejected", 0), merged.killed,
      merged.crashed,
      merged.killed_at_stop == 0
          ? std::string()
          : ", killed at the stop (SIGTERM ignored) " + std::to_string(merged.killed_at_stop),
      path);
  if (merged.shortfall && !interrupted) spdlog::error("{}", *merged.shortfall);
  const int verdict = refused_states_verdict(m, o.strict);
  return exit_code != 0 ? exit_code : verdict;
}

}  // namespace

std::string executable_dir() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(".") : self.parent_path().string();
}

int Launcher::run() {
  raise_fd_limit();
  auto scenario = load_overridden(o_.scenario, o_.overrides);
  if (!scenario) {
    spdlog::error("invalid scenario:\n{}", scenario.error().message);
    return 2;
  }
  for (const auto& o : scenario->overrides) spdlog::info("override: {}", describe_override(o));
  for (const auto& w : core::scenario_warnings(scenario.value())) spdlog::warn("{}", w);
  auto planned = plan_run(o_, scenario.value());
  if (const auto* refused = std::get_if<Refusal>(&planned)) {
    spdlog::error("{}", refused->message);
    return refused->exit_code;
  }
  const RunPlan& plan = std::get<RunPlan>(planned);
  if (scenario->plugin) {
    // Every process this launcher starts loads the plugin and refuses a
    // library other than the one loaded here (plugin_loader.hpp).
    setenv(core::kPluginPinEnv, scenario->plugin->sha256.c_str(), 1);
  }
  if (scenario->python) {
    // Every process this launcher starts imports the module this one
    // imported, even when it reads the scenario from another folder (the
    // overridden copy): its package root goes first on $PHEROMESH_PYTHONPATH.
    fs::path root = fs::path(scenario->python->file).parent_path();
    for (std::size_t dots = std::count(scenario->python->module.begin(), scenario->python->module.end(), '.');
         dots > 0; --dots) {
      root = root.parent_path();
    }
    const char* before = std::getenv("PHEROMESH_PYTHONPATH");
    const std::string path = root.string() + (before != nullptr && *before != '\0' ? ":" + std::string(before) : "");
    setenv("PHEROMESH_PYTHONPATH", path.c_str(), 1);
  }
  fs::create_directories(fs::path(plan.options.out_dir) / "logs");
  // Never leave an earlier run's files beside this one's (docs/outputs.md).
  for (const char* f : {"metrics.json", "series.csv", "tracks.csv", "final_field.txt", "final_field.csv",
                        "mavlink.json", "mavlink.key"}) {
    fs::remove(fs::path(plan.options.out_dir) / f);
  }
  if (plan.process_scenario != o_.scenario) {
    // The processes read the scenario as changed by the overrides.
    if (auto w = core::write_file_atomically(plan.process_scenario, scenario->source_text); !w) {
      spdlog::error("{}", w.error().message);
      return 5;
    }
  }
  announce(plan, scenario.value());
  runtime::install_shutdown_handlers();
  Supervisor supervisor(plan);
  if (auto err = supervisor.prepare_netns()) {
    spdlog::error("{}", *err);
    return 2;
  }
  if (!supervisor.start()) return 3;
  const FlightEnd end = supervisor.fly();
  supervisor.land();
  const int exit_code = finish_metrics(plan, supervisor.record(), end == FlightEnd::Interrupted);
  supervisor.clean_up();
  if (end == FlightEnd::Interrupted) return 130;
  // A failed run's last line names the process, its code and its log's
  // first error (docs/exit-codes.md).
  if (exit_code != 0 && supervisor.first_failure()) spdlog::error("{}", *supervisor.first_failure());
  return exit_code;
}

}  // namespace pheromesh::cli
