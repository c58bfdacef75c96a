#include "run_plan.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "pheromesh/auth/control.hpp"
#include "pheromesh/bus/bus.hpp"
#include "pheromesh/bus/cell_discovery.hpp"
#include "pheromesh/core/conductor.hpp"
#include "pheromesh/core/fault_plan.hpp"

namespace pheromesh::cli {

namespace fs = std::filesystem;
using std::chrono::milliseconds;
using std::chrono::seconds;

namespace {

// Above this many processes the UAVs start at --start-rate per second: every
// new participant is discovered by every other one (SPDP/SEDP), and when a
// few hundred arrive at once on a small host the discovery traffic starves
// the processes that must acknowledge it, their peers repeat it, and the
// storm lasts (measured, docs/dds.md "Scale").
constexpr std::size_t kStaggerAbove = 64;
// Each process adds discovery and shutdown work; the UAV deadline grows by
// this much per process.
constexpr milliseconds kDeadlinePerProcess{200};
// --secure over Fast DDS: start the processes apart. Their PKI-DH handshakes
// all at once swamp 2 cores: 117 secure processes in cells were discovered
// in 35.6 s with the gap, in 113.6 s without it, and 5 625 deposits were
// lost (2026-11-29, docs/security.md). The vendor race this gap was first
// for is gone with unicast discovery (bus::check_secure_profile).
constexpr milliseconds kSecureFastDdsSpawnGap{300};

bool onehost_profile(const std::string& profile) { return profile == "onehost" || profile == "onehost-unicast"; }

uint32_t max_replicas(const RunPlan& p) { return p.standby != Standby::Off ? 2U : 1U; }

// --dds-profile cells (docs/dds.md, "Cell discovery"; cell_layout.hpp): the
// layout of this swarm's cells, or why it cannot have them.
core::Result<CellLayout> cell_layout(const RunPlan& p) {
  const RunOptions& o = p.options;
  if (p.multi_host() && o.host_addresses.size() != o.hosts) {
    return core::Error{"--hosts " + std::to_string(o.hosts) + " in cells (the default profile) needs --dds-peers " +
                       "with every host's address in host-index order (" + std::to_string(o.hosts) +
                       " of them, the same list on every host; this host's is entry " + std::to_string(o.host_index) +
                       ")" + (o.host_addresses.empty() ? "" : "; got " + std::to_string(o.host_addresses.size())) +
                       ", or --dds-profile lan for multicast discovery (docs/deployment.md)"};
  }
  SwarmShape shape;
  shape.regions = p.regions;
  shape.uavs = p.uavs;
  shape.replicas = max_replicas(p);
  shape.lockstep = p.lockstep();
  shape.domain = o.domain;
  shape.hosts = o.hosts;
  shape.ground_host = o.ground_host;
  shape.uav_hosts = p.share.uav_hosts;
  if (p.multi_host()) shape.addresses = o.host_addresses;
  CellLayout layout(std::move(shape));
  if (auto err = layout.check(p.dds.uav != "cyclone")) return core::Error{*err};
  return layout;
}

// The profile a run takes when none is given: cells, or on one host the flat
// one that a discovery server needs, or that cells that cannot be fall back
// to, with a note (network faults chose theirs already: settle_faults).
// Over several hosts there is no flat profile to fall back to: the cells'
// error is the run's.
std::optional<std::string> settle_profile(RunPlan& p) {
  RunOptions& o = p.options;
  const bool chosen = !o.dds_profile.empty();
  if (!chosen) o.dds_profile = kDefaultDdsProfile;
  if (o.dds_profile != "cells") return std::nullopt;
  if (o.discovery_server) {
    o.dds_profile = "onehost";
    p.notes.push_back({PlanNote::Level::Info,
                       "--discovery-server: every process discovers through the server (profile onehost), not in cells"});
    return std::nullopt;
  }
  auto layout = cell_layout(p);
  if (layout) {
    p.cells = std::move(layout).value();
    return std::nullopt;
  }
  if (chosen || p.multi_host()) return layout.error().message;
  o.dds_profile = "onehost";
  p.notes.push_back({PlanNote::Level::Warn, "this run cannot have cells, the default profile (" +
                                                layout.error().message +
                                                "): it flies with flat discovery (profile onehost), which holds about "
                                                "100 UAV processes"});
  return std::nullopt;
}

// The arguments every process gets, before its role's own.
std::vector<std::string> common_args(const RunPlan& p, const PlannedProcess& c, const std::string& exe) {
  const RunOptions& o = p.options;
  std::vector<std::string> args{exe};
  const auto flag = [&](const char* name, std::string value) {
    args.emplace_back(name);
    args.push_back(std::move(value));
  };
  flag("--scenario", p.process_scenario);
  flag("--dds", c.dds);
  flag("--dds-profile", o.dds_profile);
  flag("--domain", std::to_string(o.domain));
  flag("--log-level", o.log_level);
  flag("--clock", o.clock);
  flag("--lease-ms", std::to_string(o.lease_ms));
  // In cells a process's peers are its cell's.
  if (!o.dds_peers.empty() && !p.cells) flag("--dds-peers", o.dds_peers);
  if (!o.secure.empty()) flag("--secure", o.secure);
  const bool standby = p.standby != Standby::Off;
  if (standby) args.emplace_back("--standby");
  // Fast DDS 2.9 keeps an instance with its dead owner (docs/faults.md):
  // exclusive ownership only in all-Cyclone swarms.
  if (standby && !(p.dds.single_vendor() && p.dds.ground == "cyclone")) args.emplace_back("--shared-ownership");
  if (c.replica > 0) args.insert(args.end(), {"--replica", std::to_string(c.replica)});
  return args;
}

PlannedProcess planned(const RunPlan& p, const std::string& role, uint32_t index, uint32_t replica,
                       const std::vector<std::string>& role_args, uint32_t participant_id) {
  PlannedProcess c;
  c.role = role;
  c.index = index;
  c.replica = replica;
  c.name = process_name(role, index, replica);
  c.dds = p.dds.vendor_of(role, index);
  c.argv = common_args(p, c, p.bin_dir + "/pheromesh-" + role);
  c.argv.insert(c.argv.end(), role_args.begin(), role_args.end());
  c.participant_id = participant_id;
  if (p.cells) {
    // A UAV's Fast DDS ports past every hub's, whatever starts later.
    const uint32_t id = role == "uav" ? CellLayout::member_id(index) : p.cells->hub(role, index, replica).index;
    c.env = {"PHEROMESH_PARTICIPANT_ID=" + std::to_string(id),
             std::string(bus::kCellEnv) + "=" + bus::format_cell(p.cells->cell_of(role, index, replica))};
  } else {
    c.env = {"PHEROMESH_PARTICIPANT_ID=" + std::to_string(participant_id)};
  }
  c.env.push_back(std::string(bus::kSwarmProcessesEnv) + "=" + std::to_string(p.host_processes));
  c.log_path = (fs::path(p.options.out_dir) / "logs" / (c.name + ".log")).string();
  // Realtime only: in lockstep the UAVs and the place agents take turns (the
  // phases), so the herd never holds up a hub, and a session of its own
  // made the UAV phase slower (measured: docs/benchmarks.md, "2000 UAV
  // processes on two cores").
  c.scheduling = role != "uav" && !p.lockstep() ? Scheduling::OwnSession : Scheduling::LauncherSession;
  return c;
}

PlannedProcess uav(const RunPlan& p, uint32_t index, uint32_t participant_id) {
  return planned(p, "uav", index, 0, {"--id", std::to_string(index), "--ticks", std::to_string(p.ticks)},
                 participant_id);
}

PlannedProcess ground(const RunPlan& p, uint32_t participant_id) {
  const RunOptions& o = p.options;
  std::vector<std::string> args{"--out",      o.out_dir,
                                "--progress", std::to_string(o.progress_s),
                                "--ticks",    std::to_string(p.ticks),
                                "--uavs",     std::to_string(p.uavs)};
  // No launcher sees every process: the ground station ends the run.
  if (p.multi_host()) args.emplace_back("--until-done");
  if (o.start_timeout_s > 0) args.insert(args.end(), {"--start-timeout", std::to_string(o.start_timeout_s)});
  if (o.tracks) args.emplace_back("--tracks");
  if (!o.mavlink.empty()) {
    args.insert(args.end(), {"--mavlink", o.mavlink, "--mavlink-rate-hz", std::to_string(o.mavlink_rate_hz)});
  }
  // The ground station's line to us: the console's kill / restart requests,
  // the lockstep conductor's `faults K`, and pause / stop from a console or
  // a MAVLink station (a pause extends the deadline; docs/mavlink.md), and
  // in realtime the swarm's start, from which the launcher measures the
  // steady flight (metrics.json "steady").
  const bool control = o.http_port || p.lockstep_faults() || !o.mavlink.empty() || !p.lockstep();
  if (control) args.insert(args.end(), {"--launcher-fd", "3"});
  if (p.lockstep_faults()) {
    std::string list;
    for (const uint32_t k : core::FaultPlan(*p.faults).fault_ticks())
      list += (list.empty() ? "" : ",") + std::to_string(k);
    args.insert(args.end(), {"--fault-ticks", list});
  }
  if (o.http_port) {
    const std::string record = o.no_record         ? ""
                               : !o.record.empty() ? o.record
                                                   : (fs::path(o.out_dir) / "console.phrec").string();
    args.insert(args.end(), {"--http", std::to_string(*o.http_port), "--http-bind", o.http_bind});
    if (!record.empty()) args.insert(args.end(), {"--record", record});
  }
  PlannedProcess c = planned(p, "ground", 0, 0, args, participant_id);
  c.stderr_to = StderrTo::Launcher;
  c.control = control ? ControlLine::Fd3 : ControlLine::None;
  return c;
}

// How many processes this host starts: those of start_order.
uint32_t count_host_processes(const RunPlan& p) {
  uint32_t n = p.share.runs("ground", 0) ? 1 : 0;
  for (uint32_t k = 0; k < p.replicas_at_start(); ++k) {
    for (uint32_t r = 0; r < p.regions; ++r) n += p.share.runs("place", r, k) ? 1 : 0;
  }
  for (uint32_t u = 0; u < p.uavs; ++u) n += p.share.runs("uav", u) ? 1 : 0;
  return n;
}

// Numbered in the order this host starts them, so that a host's
// participant ids stay below the 120 that unicast discovery probes
// (lan-unicast); standbys and restarts started later continue the numbering
// (Supervisor::participant_for).
std::vector<PlannedProcess> start_order(const RunPlan& p) {
  std::vector<PlannedProcess> list;
  const auto next_id = [&] { return static_cast<uint32_t>(list.size()); };
  if (p.share.runs("ground", 0)) list.push_back(ground(p, next_id()));
  for (uint32_t k = 0; k < p.replicas_at_start(); ++k) {
    for (uint32_t r = 0; r < p.regions; ++r) {
      if (p.share.runs("place", r, k)) list.push_back(p.place(r, k, next_id()));
    }
  }
  for (uint32_t u = 0; u < p.uavs; ++u) {
    if (p.share.runs("uav", u)) list.push_back(uav(p, u, next_id()));
  }
  return list;
}

std::optional<Stagger> stagger(const RunPlan& p) {
  const double rate = p.options.start_rate;
  if (1 + std::size_t{p.regions} + p.uavs <= kStaggerAbove || rate <= 0) return std::nullopt;
  Stagger s;
  s.batch = std::max<uint32_t>(1, static_cast<uint32_t>(rate / 10.0));
  s.pause = milliseconds(static_cast<int64_t>(1000.0 * s.batch / std::max(rate, 1e-3)));
  return s;
}

RunDeadlines deadlines(const RunPlan& p) {
  // Generous bound on the UAV phase: the run itself, discovery, and slack
  // for a loaded machine, growing with the swarm. A lockstep run has no such
  // bound: it goes as fast as its slowest process (under packet loss,
  // seconds per tick), the conductor bounds each phase (--phase-timeout) and
  // every UAV and place agent ends when the conductor's clock falls silent
  // (core::ConductorWatch).
  const double flight_s = p.lockstep() ? 365.0 * 24 * 3600 : p.ticks / p.rate_hz * 2.0;
  RunDeadlines d;
  d.uavs_end = milliseconds(static_cast<int64_t>(1000.0 * flight_s)) + seconds(45) +
               kDeadlinePerProcess * static_cast<int64_t>(p.processes.size());
  d.other_hosts = p.multi_host() ? seconds(60) : seconds(0);
  d.resource_sample = milliseconds(static_cast<int64_t>(600.0 * p.ticks / p.rate_hz));
  d.conductor_grace = milliseconds(int64_t{p.options.lease_ms} * core::ConductorWatch::kLeases) + seconds(15);
  return d;
}

// The lease of a run that gave none (RunOptions::lease_ms).
void settle_lease(RunPlan& p) {
  if (p.options.lease_ms != 0) return;
  const bool large = p.host_processes > kLongLeaseAbove;
  p.options.lease_ms = large ? kLongLeaseMs : kShortLeaseMs;
  if (large) {
    p.notes.push_back({PlanNote::Level::Info, std::to_string(p.host_processes) +
                                                  " processes on this host: liveliness lease " +
                                                  std::to_string(kLongLeaseMs) +
                                                  " ms (a dead process is noticed in 5-10 s; --lease-ms sets it)"});
  }
}

// --faults, --kill and the scenario's schedule, each checked on its own so
// that an error names it.
core::Result<core::FaultSchedule> merged_faults(const RunOptions& o, const core::ScenarioConfig& s, const RunSize& n) {
  const bool lockstep = o.clock == "lockstep";
  core::FaultSchedule schedule;
  if (auto err = core::check_fault_schedule(s.faults, n.uavs, n.regions, lockstep)) {
    return core::Error{o.scenario + ": fault: " + *err};
  }
  core::merge_fault_schedules(schedule, s.faults);
  for (const auto& [spec, where] : {std::pair{o.kill_spec, "--kill"}, std::pair{o.faults_spec, "--faults"}}) {
    if (spec.empty()) continue;
    auto parsed = core::parse_fault_schedule(spec, where);
    if (!parsed) return parsed.error();
    if (auto err = core::check_fault_schedule(parsed.value(), n.uavs, n.regions, lockstep)) {
      return core::Error{std::string(where) + ": " + *err};
    }
    core::merge_fault_schedules(schedule, parsed.value());
  }
  return schedule;
}

// What a non-empty schedule asks of the run: network namespaces (and their
// DDS profile), standbys; an error if the run cannot give it.
std::optional<std::string> settle_faults(RunPlan& p, core::FaultSchedule schedule) {
  using core::FaultAction;
  bool standby = false;
  for (const auto& e : schedule.events) {
    standby = standby || e.action == FaultAction::Standby;
    const bool ends_it = e.action == FaultAction::Kill || e.action == FaultAction::Restart;
    for (const auto& t : e.targets) {
      if (t.role == "ground" && ends_it) {
        return "fault schedule: '" + e.text +
               "': the ground station cannot be killed or restarted (it conducts the "
               "run and writes metrics.json); stop, partition and loss may target it";
      }
    }
  }
  RunOptions& o = p.options;
  if (schedule.has_network()) {
    if (o.http_port) {
      return "fault schedule: partition and loss run the ground station in a network namespace of its own, where "
             "the web console (--http) cannot be reached from this host; leave out --http or the network faults";
    }
    if (o.discovery_server) {
      return "fault schedule: partition and loss do not work with --discovery-server (the server listens on this "
             "host's loopback, outside the processes' network namespaces)";
    }
    // The one-host profiles and one-host cells speak on loopback only; in a
    // namespace of its own each process must speak on its veth
    // (deploy/dds/*-netns.xml).
    if ((o.dds_profile.empty() || o.dds_profile == "cells") && o.hosts <= 1) {
      p.notes.push_back({PlanNote::Level::Info,
                         "fault schedule: partition and loss run every process in a network namespace of its own, "
                         "with flat discovery (profile netns) instead of cells"});
      o.dds_profile = "netns";
    } else if (onehost_profile(o.dds_profile)) {
      o.dds_profile = "netns";
    } else if (o.dds_profile != "netns") {
      p.notes.push_back({PlanNote::Level::Warn,
                         "network faults: every process runs in its own network namespace; DDS profile '" +
                             o.dds_profile +
                             "' must not limit it to the loopback interface (the netns profile is made for this)"});
    }
  }
  // A standby started later needs a swarm whose processes all run with
  // --standby (the QoS of the place agents' output): the run becomes one.
  if (standby && p.standby == Standby::Off) {
    p.notes.push_back({PlanNote::Level::Info, "fault schedule: 'standby' events: every process runs with --standby"});
    p.standby = Standby::OnFault;
  }
  p.faults = std::move(schedule);
  return std::nullopt;
}

}  // namespace

std::string process_name(const std::string& role, uint32_t index, uint32_t replica) {
  if (role == "ground") return role;
  std::string n = role + "-" + std::to_string(index);
  if (replica > 0) n += ".r" + std::to_string(replica);
  return n;
}

bool HostShare::runs(const std::string& role, uint32_t index, uint32_t replica) const {
  if (hosts <= 1) return true;
  SwarmShape shape;
  shape.regions = regions;
  shape.hosts = hosts;
  shape.ground_host = ground_host;
  shape.uav_hosts = uav_hosts;
  return CellLayout(shape).host_of(role, index, replica) == host_index;
}

PlannedProcess RunPlan::place(uint32_t region, uint32_t replica, uint32_t participant_id) const {
  // --ticks only so that the run the place agent publishes for monitors
  // (RunScenario) is the UAVs'; a realtime place agent runs until the end.
  return planned(*this, "place", region, replica,
                 {"--region", std::to_string(region), "--ticks", std::to_string(ticks)}, participant_id);
}

PlannedProcess RunPlan::restarted_uav(uint32_t index, uint32_t ticks_left, uint32_t seq_base,
                                      uint32_t participant_id) const {
  return planned(
      *this, "uav", index, 0,
      {"--id", std::to_string(index), "--ticks", std::to_string(ticks_left), "--seq-base", std::to_string(seq_base)},
      participant_id);
}

std::vector<std::string> RunPlan::identities() const {
  std::vector<std::string> names;
  if (share.runs("ground", 0)) names.emplace_back("ground");
  for (uint32_t r = 0; r < regions; ++r) {
    for (uint32_t k = 0; k < (standby != Standby::Off ? 2U : 1U); ++k) {
      if (share.runs("place", r, k)) names.push_back(process_name("place", r, k));
    }
  }
  for (uint32_t u = 0; u < uavs; ++u) {
    if (share.runs("uav", u)) names.push_back(process_name("uav", u, 0));
  }
  return names;
}

RunSize run_size(const core::ScenarioConfig& s) {
  RunSize n;
  n.rate_hz = s.tick_rate_hz;
  n.ticks = s.ticks;
  n.uavs = s.uavs;
  n.regions = s.geometry().region_count();
  return n;
}

core::Result<RunPlan> make_run_plan(const RunOptions& o, const core::ScenarioConfig& s, const DdsPlan& dds,
                                    const std::string& bin_dir) {
  const RunSize n = run_size(s);
  RunPlan p;
  p.options = o;
  p.process_scenario = s.overrides.empty() ? o.scenario : (fs::path(o.out_dir) / kOverriddenScenarioFile).string();
  p.dds = dds;
  p.bin_dir = bin_dir;
  auto pins = parse_uav_pins(o.pin_uavs, n.uavs, o.hosts);
  if (!pins) return pins.error();
  p.share = {o.hosts, o.host_index, o.ground_host, n.regions, std::move(pins).value()};
  p.clock = o.clock == "lockstep" ? RunClock::Lockstep : RunClock::Realtime;
  p.ticks = n.ticks;
  p.uavs = n.uavs;
  p.regions = n.regions;
  p.rate_hz = n.rate_hz;
  p.standby = s.standby ? Standby::FromStart : Standby::Off;
  auto schedule = merged_faults(o, s, n);
  if (!schedule) return schedule.error();
  if (!schedule->empty()) {
    if (auto err = settle_faults(p, std::move(schedule).value())) return core::Error{*err};
  }
  if (auto err = settle_profile(p)) return core::Error{*err};
  p.host_processes = count_host_processes(p);
  settle_lease(p);
  p.processes = start_order(p);
  p.stagger = stagger(p);
  if (!o.secure.empty() && dds.ground == "fastdds") p.spawn_gap = kSecureFastDdsSpawnGap;
  p.deadlines = deadlines(p);
  p.stop_early = {{"uav", seconds(10)}};
  if (p.multi_host()) p.stop_early.insert(p.stop_early.end(), {{"place", seconds(15)}, {"ground", seconds(15)}});
  p.stop_final = {{"place", seconds(15)}, {"ground", seconds(15)}};
  return p;
}

std::optional<std::string> check_multi_host(const RunPlan& plan, ControlKey key, const std::string& key_error) {
  const RunOptions& o = plan.options;
  if (o.hosts == 0) return "--hosts must be at least 1";
  if (o.host_index >= o.hosts) {
    return "--host-index " + std::to_string(o.host_index) + " is not below --hosts " + std::to_string(o.hosts) +
           " (hosts are numbered 0.." + std::to_string(o.hosts - 1) + ")";
  }
  if (o.ground_host >= o.hosts) {
    return "--ground-host " + std::to_string(o.ground_host) + " is not below --hosts " + std::to_string(o.hosts);
  }
  if (!plan.multi_host()) return std::nullopt;
  if (onehost_profile(o.dds_profile) || o.dds_profile == "netns") {
    return "--hosts " + std::to_string(o.hosts) + ": DDS profile '" + o.dds_profile +
           "' keeps traffic on this host; leave --dds-profile out (cells, with --dds-peers HOST,HOST,... in host "
           "order), or use lan (multicast discovery) or lan-unicast --dds-peers HOST,HOST,... (docs/deployment.md)";
  }
  if (o.dds_profile == "lan-unicast" && o.dds_peers.empty()) {
    return "--dds-profile lan-unicast needs --dds-peers: the address or name of every host of the swarm";
  }
  if (key != ControlKey::Set) {
    return std::string("--hosts ") + std::to_string(o.hosts) +
           ": every host of one swarm needs the same control key in $" + auth::kControlKeyEnv +
           " (the ground station signs the start and the end of the run with it); make one with " +
           "`pheromesh key` and export it on every host" +
           (key == ControlKey::Unset ? "" : " (the one set is malformed: " + key_error + ")");
  }
  if (o.discovery_server) return "--discovery-server runs on one host; it does not work with --hosts";
  if (o.http_port && !plan.share.runs("ground", 0)) {
    return "--http: the web console is served by the ground station, which runs on host " +
           std::to_string(o.ground_host) +
           " (--ground-host); give --http there, or attach a monitor anywhere with `pheromesh attach --http PORT`";
  }
  if (!plan.faults) return std::nullopt;
  if (plan.faults->has_network()) {
    return "fault schedule: partition and loss put every process of one host in its own network namespace; they do "
           "not work with --hosts (use them on one host, or shape the LAN itself)";
  }
  if (plan.lockstep()) {
    return "fault schedule: a lockstep run injects faults through the conductor's line to its launcher, on one host; "
           "with --hosts give the faults to a realtime run";
  }
  for (const auto& e : plan.faults->events) {
    for (const auto& t : e.targets) {
      bool here = false;
      for (uint32_t k = 0; k < (t.role == "place" ? plan.replicas_at_start() : 1); ++k)
        here = here || plan.share.runs(t.role, t.index, k);
      if (!here) {
        return "fault schedule: '" + e.text + "': " + t.process_name() + " does not run on host " +
               std::to_string(o.host_index) + " (--hosts " + std::to_string(o.hosts) +
               ": place agent R on host R % hosts, its standby on the next, UAV U on the host of place agent U % "
               "regions unless --pin-uavs puts it elsewhere, the ground station on --ground-host); give this fault "
               "to that host's pheromesh run";
      }
    }
  }
  return std::nullopt;
}

std::optional<std::string> cells_attach_command(const RunPlan& plan) {
  const RunOptions& o = plan.options;
  if (!plan.cells) return std::nullopt;
  std::string cmd = "pheromesh attach --domain " + std::to_string(o.domain) + " --cell-hubs " +
                    std::to_string(plan.cells->most_hubs_on_a_host());
  if (plan.multi_host()) {
    std::string peers;
    for (const auto& a : o.host_addresses) peers += (peers.empty() ? "" : ",") + a;
    cmd += " --dds-peers " + peers;
  }
  // A secure swarm admits only authenticated participants: the monitor's
  // read-only identity is in the same directory.
  if (!o.secure.empty()) cmd += " --secure " + o.secure;
  return cmd;
}

}  // namespace pheromesh::cli
