// What `pheromesh run` will do, decided before anything starts: from the
// options and the loaded scenario, which processes this host starts, in which
// order, with which arguments and environment, and the deadlines and stop
// order that bound the run. Pure: no fork, no DDS, no file touched (the
// launcher checks the executables and identities it names), so that the unit
// tests pin every flag (tests/unit/test_run_plan.cpp).
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "cell_layout.hpp"
#include "child_spawn.hpp"
#include "cli/scenario_overrides.hpp"
#include "dds_plan.hpp"
#include "pheromesh/core/faults.hpp"
#include "pheromesh/core/result.hpp"
#include "pheromesh/core/scenario.hpp"

namespace pheromesh::cli {

inline constexpr const char* kDefaultDdsProfile = "cells";
// The lease a run takes when none is given: a dead process noticed within a
// second, but a host that starts hundreds of processes stalls them longer
// than that while they discover one another (measured: 500 Fast DDS UAVs in
// cells with 1 s flew 74 % of their ticks, "lost (liveliness)" at tick 0;
// with 5 s all of them, docs/benchmarks.md).
inline constexpr uint32_t kShortLeaseMs = 1000;
inline constexpr uint32_t kLongLeaseMs = 5000;
inline constexpr uint32_t kLongLeaseAbove = 150;

struct RunOptions {
  std::string scenario;
  // --set, --uavs, --ticks, --duration, --seed, --rate, --standby: applied
  // to the scenario when it is loaded (load_overridden), so the plan takes
  // the swarm's size, length, rate and standbys from the scenario alone.
  OverrideFlags overrides;
  std::string out_dir = "out/run";
  std::string faults_spec;                    // --faults: the fault schedule (docs/faults.md), added to the scenario's
  std::string kill_spec;                      // --kill: the older form of --faults ("uav:3@5s,place:1@2500ms")
  std::string netns_subnet = "10.77.0.0/16";  // the processes' addresses when network faults need namespaces
  std::string dds;                            // a DdsPlan spec: cyclone, fastdds, mixed or ROLE=VENDOR,...
  // Empty (none given): cells, where each process discovers only those it
  // talks to, on one host or over several (docs/dds.md, "Cell discovery");
  // network faults and --discovery-server take the flat profile they need
  // instead (netns, onehost), and so does a one-host run whose cells cannot
  // be (a domain above 100, whose well-known ports are ephemeral), each with
  // a note. Given: cells, or a flat profile by name (onehost,
  // onehost-unicast, lan, lan-unicast, netns, default) or files.
  std::string dds_profile;
  std::string dds_peers;  // lan profiles: discovery peers (every process gets them); cells: every host, in host order
  // cells over several hosts: dds_peers resolved, one IPv4 address per host
  // in host-index order (the launcher resolves them before planning).
  std::vector<std::string> host_addresses;
  uint32_t domain = 0;
  // One swarm over several hosts (docs/deployment.md): each host runs
  // `pheromesh run` with the same scenario and options and its own index,
  // and starts only its share: place agent R (its standby R.rN) on host
  // (R + N) % hosts, UAV U beside its home place agent (cell_layout.hpp),
  // the ground station on ground_host.
  uint32_t hosts = 1;
  uint32_t host_index = 0;
  uint32_t ground_host = 0;
  // --hosts-file (hosts_file.hpp): stands for --hosts and --dds-peers, and
  // without --host-index names this host by its address. The launcher
  // applies it (apply_hosts_file) before it resolves the peers; the flags
  // given beside it, which it refuses or replaces, are told apart by these.
  std::string hosts_file;
  bool hosts_given = false;       // --hosts on the command line
  bool host_index_given = false;  // --host-index on the command line
  std::string dds_peers_from;     // "--dds-peers" or "$PHEROMESH_DDS_PEERS" when dds_peers came from one
  // --pin-uavs: UAVs that fly on a host of the user's choosing instead of
  // beside their home place agent ("U=H,A-B=H"; cell_layout.hpp).
  std::string pin_uavs;
  std::string log_level = "info";
  double progress_s = 1.0;
  double start_timeout_s = 0;      // lockstep: the conductor's wait for every Ready (0: the ground station's default)
  std::string clock = "realtime";  // realtime | lockstep
  // Liveliness lease of every process [ms]; 0: kShortLeaseMs, or
  // kLongLeaseMs when this host starts more than kLongLeaseAbove processes.
  uint32_t lease_ms = 0;
  bool discovery_server = false;   // Fast DDS only: discover through a fast-discovery-server the launcher starts
  double start_rate = 50;  // UAV processes started per second when the swarm exceeds 64 processes (0: all at once)
  // Web console of the ground station (docs/console.md).
  std::optional<uint16_t> http_port;
  std::string http_bind = "127.0.0.1";
  std::string record;  // default with --http: OUT/console.phrec
  bool no_record = false;
  bool tracks = false;  // the ground station also writes OUT/tracks.csv
  // The ground station streams to a MAVLink station (docs/mavlink.md): "udp:HOST:PORT", empty: none.
  std::string mavlink;
  double mavlink_rate_hz = 4.0;  // [Hz] (console::kMavlinkDefaultRateHz)
  std::string secure;  // DDS Security: the directory of `pheromesh security init` (docs/security.md)
  bool strict = false;  // a state refused as implausible fails the run (kExitRefusedStates)
};

// The name of a process: "uav-3", "place-1", "place-1.r2", "ground".
std::string process_name(const std::string& role, uint32_t index, uint32_t replica = 0);

// --hosts: which host runs which process (docs/deployment.md).
struct HostShare {
  uint32_t hosts = 1;
  uint32_t host_index = 0;
  uint32_t ground_host = 0;
  uint32_t regions = 1;  // a UAV runs on the host of its home place agent
  std::map<uint32_t, uint32_t> uav_hosts;  // ... unless pinned (--pin-uavs)
  [[nodiscard]] bool multi_host() const { return hosts > 1; }
  // Whether this host runs process `index` (replica `replica`) of `role`.
  [[nodiscard]] bool runs(const std::string& role, uint32_t index, uint32_t replica = 0) const;
};

enum class RunClock : uint8_t { Realtime, Lockstep };

// Hot-standby place agents: none; every process runs with --standby and
// 'standby' faults start the replicas; or a replica of every region from the
// start (--standby, the scenario's run.standby).
enum class Standby : uint8_t { Off, OnFault, FromStart };

// Where a process's standard error goes: its log file like its standard
// output, or the launcher's (the ground station's errors reach the user).
enum class StderrTo : uint8_t { Log, Launcher };

// Whether the process gets the launcher's control line as fd 3 (the
// ground station: the console's requests, the conductor's `faults K`).
enum class ControlLine : uint8_t { None, Fd3 };

struct PlannedProcess {
  std::string role;  // "uav", "place", "ground"
  uint32_t index = 0;
  uint32_t replica = 0;           // place agents: 0 primary, 1.. standbys
  std::string name;               // process_name(role, index, replica)
  std::string dds;                // its DDS vendor
  std::vector<std::string> argv;  // argv[0]: the executable
  // PHEROMESH_PARTICIPANT_ID: Fast DDS takes its ports from it (docs/dds.md).
  uint32_t participant_id = 0;
  std::vector<std::string> env;  // NAME=VALUE added to the launcher's environment
  std::string log_path;          // OUT/logs/NAME.log: its standard output
  uint32_t life = 0;             // 0 its first start; 1.. started again (Supervisor::spawn): the log is appended to
  StderrTo stderr_to = StderrTo::Log;
  ControlLine control = ControlLine::None;
  // How the kernel weighs it (child_spawn.hpp): place agents and the ground
  // station in sessions of their own, the UAVs in the launcher's.
  Scheduling scheduling = Scheduling::LauncherSession;
  [[nodiscard]] const std::string& executable() const { return argv.front(); }
};

// Above kStaggerAbove processes the UAVs start in batches.
struct Stagger {
  uint32_t batch = 1;                  // UAVs per batch: a tenth of a second's worth of --start-rate
  std::chrono::milliseconds pause{0};  // before each batch (the first: the place agents' head start)
};

// Counted from the moment every process of this host has been started.
struct RunDeadlines {
  // UAVs still flying then are stopped: twice the flight (a year in
  // lockstep, which the conductor bounds instead), 45 s, and 200 ms per
  // process of this host.
  std::chrono::milliseconds uavs_end{0};
  // Over several hosts: a minute more for the End of a ground station on
  // another host (it waits for the slowest host's UAVs).
  std::chrono::milliseconds other_hosts{0};
  // The one resource sample: at 60 % of the flight (ticks / rate).
  std::chrono::milliseconds resource_sample{0};
  // Lockstep: after the conductor ended, how long its processes get to end
  // by themselves (their ConductorWatch limit, and slack for a busy host).
  std::chrono::milliseconds conductor_grace{0};
};

// Stop every running process of `role` with SIGTERM; SIGKILL after `grace`.
struct StopStep {
  std::string role;
  std::chrono::seconds grace{0};
};

// Something the plan says before the run starts.
struct PlanNote {
  enum class Level : uint8_t { Info, Warn };
  Level level = Level::Info;
  std::string text;
};

// The scenario file the processes of a run with overrides read: the changed
// scenario, written by the launcher into the output folder (docs/scenario-format.md).
inline constexpr const char* kOverriddenScenarioFile = "scenario.textproto";

struct RunPlan {
  // As given, with what the plan settles: the DDS profile of network faults
  // (netns).
  RunOptions options;
  // The scenario file every process gets: the one given, or with overrides
  // OUT/scenario.textproto, which the launcher writes from the scenario's
  // source_text before starting any.
  std::string process_scenario;
  DdsPlan dds;
  std::string bin_dir;  // where pheromesh-uav, -place and -ground are
  HostShare share;
  RunClock clock = RunClock::Realtime;
  uint32_t ticks = 0;    // each UAV flies
  uint32_t uavs = 0;     // of the whole swarm
  uint32_t regions = 0;  // place agents, without standbys
  double rate_hz = 0;    // [Hz]
  Standby standby = Standby::Off;
  std::optional<core::FaultSchedule> faults;  // --faults, --kill and the scenario's, merged; none if empty
  // --dds-profile cells: who runs where and names whom.
  std::optional<CellLayout> cells;
  std::vector<PlanNote> notes;
  // This host's processes in start order: the ground station, the place
  // agents, their standbys, the UAVs.
  std::vector<PlannedProcess> processes;
  // How many processes this host starts (processes.size(), known before
  // they are planned): each gets it as $PHEROMESH_SWARM_PROCESSES, which
  // sizes Cyclone's heartbeat (bus::kQuietHeartbeatAbove).
  uint32_t host_processes = 0;
  std::optional<Stagger> stagger;
  // --secure over Fast DDS: processes start this far apart (run_plan.cpp,
  // docs/security.md).
  std::chrono::milliseconds spawn_gap{0};
  RunDeadlines deadlines{};
  // When the UAVs are over (interrupted, or past their deadline): the UAVs,
  // and over several hosts this host's place agents and ground station.
  std::vector<StopStep> stop_early;
  // After the flight: the place agents, then the ground station.
  std::vector<StopStep> stop_final;

  [[nodiscard]] bool lockstep() const { return clock == RunClock::Lockstep; }
  [[nodiscard]] bool lockstep_faults() const { return faults && lockstep(); }
  [[nodiscard]] bool multi_host() const { return share.multi_host(); }
  // Place agents per region at the start: 2 with standbys, else 1.
  [[nodiscard]] uint32_t replicas_at_start() const { return standby == Standby::FromStart ? 2 : 1; }
  // A place agent started during the run (restart, 'standby' fault).
  [[nodiscard]] PlannedProcess place(uint32_t region, uint32_t replica, uint32_t participant_id) const;
  // A UAV started again for the `ticks_left` of the run; its deposits are
  // numbered from `seq_base` (above its earlier lives').
  [[nodiscard]] PlannedProcess restarted_uav(uint32_t index, uint32_t ticks_left, uint32_t seq_base,
                                             uint32_t participant_id) const;
  // The processes of this host that need a DDS Security identity (--secure),
  // standbys that faults may start included.
  [[nodiscard]] std::vector<std::string> identities() const;
};

// The run's length and swarm: the scenario's, overrides applied.
struct RunSize {
  uint32_t ticks = 0;
  uint32_t uavs = 0;
  uint32_t regions = 0;
  double rate_hz = 0;  // [Hz]
};
RunSize run_size(const core::ScenarioConfig& s);

// The plan, or why the fault schedule (--faults, --kill, the scenario's)
// cannot run in this swarm.
core::Result<RunPlan> make_run_plan(const RunOptions& o, const core::ScenarioConfig& s, const DdsPlan& dds,
                                    const std::string& bin_dir);

// $PHEROMESH_CONTROL_KEY, which every host of one swarm shares.
enum class ControlKey : uint8_t { Set, Unset, Malformed };

// --hosts: what a swarm over several hosts cannot do; an error message.
std::optional<std::string> check_multi_host(const RunPlan& plan, ControlKey key, const std::string& key_error = "");

// --dds-profile cells: the `pheromesh attach` command that watches this run
// (from any host of it, or another on its network); nullopt for other
// profiles.
std::optional<std::string> cells_attach_command(const RunPlan& plan);

}  // namespace pheromesh::cli
