// `pheromesh run`: spawns every place agent, UAV and the ground station of a
// swarm as separate processes on this host, injects faults on a schedule
// (docs/faults.md), stops everything in order and leaves OUT/metrics.json.
#pragma once

#include <sys/resource.h>
#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "dds_plan.hpp"
#include "netns.hpp"
#include "pheromesh/core/fault_plan.hpp"
#include "pheromesh/core/result.hpp"
#include "pheromesh/core/scenario.hpp"
#include "proc_stats.hpp"

namespace pheromesh::cli {

struct RunOptions {
  std::string scenario;
  uint32_t uavs = 0;           // 0: the scenario's
  uint32_t ticks = 0;          // 0: the scenario's (or from duration)
  double duration_s = 0;       // alternative to ticks [s]
  uint64_t seed = 0;           // 0: the scenario's
  double rate_hz = 0;          // 0: the scenario's
  std::string out_dir = "out/run";
  std::string faults_spec;                    // --faults: the fault schedule (docs/faults.md), added to the scenario's
  std::string kill_spec;                      // --kill: the older form of --faults ("uav:3@5s,place:1@2500ms")
  std::string netns_subnet = "10.77.0.0/16";  // the processes' addresses when network faults need namespaces
  std::string dds;             // a DdsPlan spec: cyclone, fastdds, mixed or ROLE=VENDOR,...
  std::string dds_profile = "onehost";
  std::string dds_peers;  // lan profiles: discovery peers (every process gets them)
  uint32_t domain = 0;
  // One swarm over several hosts (docs/deployment.md): each host runs
  // `pheromesh run` with the same scenario and options and its own index,
  // and starts only its share: place agent R (its standby R.rN) on host
  // (R + N) % hosts, UAV U on host U % hosts, the ground station on ground_host.
  uint32_t hosts = 1;
  uint32_t host_index = 0;
  uint32_t ground_host = 0;
  std::string log_level = "info";
  double progress_s = 1.0;
  std::string clock = "realtime";  // realtime | lockstep
  uint32_t lease_ms = 1000;        // liveliness lease of every process [ms]
  bool discovery_server = false;   // Fast DDS only: discover through a fast-discovery-server the launcher starts
  bool standby = false;            // a hot-standby replica of every place agent (also the scenario's run.standby)
  double start_rate = 50;          // UAV processes started per second when the swarm exceeds 64 processes (0: all at once)
  // Web console of the ground station (docs/console.md).
  std::optional<uint16_t> http_port;
  std::string http_bind = "127.0.0.1";
  std::string record;              // default with --http: OUT/console.phrec
  bool no_record = false;
  std::string secure;              // DDS Security: the directory of `pheromesh security init` (docs/security.md)
};

struct ChildProcess {
  std::string name;  // "uav-3", "place-0", "place-0.r1" (replica 1), "ground"
  std::string role;  // "uav", "place", "ground"
  std::string dds;   // its DDS vendor
  uint32_t index = 0;
  uint32_t replica = 0;  // place agents: 0 primary, 1.. standbys
  pid_t pid = -1;
  bool running = false;
  bool stopped = false;  // SIGSTOPped by a fault, not continued yet
  bool killed_on_purpose = false;
  bool asked_to_stop = false;
  int exit_code = -1;    // if exited
  int term_signal = 0;   // if signalled
  // From wait4's rusage once reaped (all its threads, and any children it
  // reaped itself).
  bool reaped = false;
  double cpu_user_s = 0;   // ru_utime [s]
  double cpu_sys_s = 0;    // ru_stime [s]
  double max_rss_mib = 0;  // ru_maxrss [MiB]; Linux keeps the pre-exec peak: never below the anonymous memory the forked copy of the launcher had
  // The one look at it during the flight (Launcher::sample_resources).
  std::optional<ProcessSample> sample;
  [[nodiscard]] bool crashed() const;
  [[nodiscard]] std::string describe() const;
};

// The name of a process: "uav-3", "place-1", "place-1.r2", "ground".
std::string process_name(const std::string& role, uint32_t index, uint32_t replica = 0);

class Launcher {
 public:
  explicit Launcher(RunOptions o);
  ~Launcher();
  Launcher(const Launcher&) = delete;
  Launcher& operator=(const Launcher&) = delete;
  // Returns the process exit code: 0 if the run completed and no process died
  // that was not killed on purpose.
  int run();

 private:
  // `replica` > 0: a standby place agent, named place-R.rN.
  void spawn(const std::string& role, uint32_t index, const std::vector<std::string>& extra_args, uint32_t replica = 0);
  void spawn_place(uint32_t region, uint32_t replica);
  // Starts an ended process again (console restart, restart fault): a UAV for
  // its remaining ticks, its deposits numbered above its earlier lives'; a
  // place agent for the same region and replica. Returns the new pid.
  core::Result<pid_t> respawn(const std::string& name);
  // Starts the place agents and then the UAVs, in batches when the swarm is
  // large. Returns false if interrupted before all were started.
  bool spawn_swarm(uint32_t regions, uint32_t uavs, uint32_t ticks);
  void reap();
  // Records how a child ended (from wait4).
  void record_exit(pid_t pid, int status, const rusage& ru);
  // SIGKILL, then wait until it is reaped (a lockstep kill is complete when
  // the conductor hears of it).
  void kill_and_reap(ChildProcess& c);
  void sample_resources();
  static void raise_fd_limit();
  void stop_role(const std::string& role, std::chrono::seconds grace);
  [[nodiscard]] bool any_running(const std::string& role) const;
  ChildProcess* find(const std::string& name);
  // --hosts: whether this host runs that process.
  [[nodiscard]] bool on_this_host(const std::string& role, uint32_t index, uint32_t replica = 0) const;
  [[nodiscard]] bool multi_host() const { return o_.hosts > 1; }
  // --hosts: what a swarm over several hosts cannot do; an error message.
  // With --secure: an error naming the first process of this host without its identity.
  std::optional<std::string> check_secure(uint32_t uavs, uint32_t regions) const;
  // --secure over Fast DDS: processes start this far apart (spawn()).
  static constexpr std::chrono::milliseconds kSecureFastDdsSpawnGap{300};
  std::chrono::steady_clock::time_point last_secure_spawn_{};
  std::optional<std::string> check_multi_host(const core::ScenarioConfig& s) const;
  std::map<std::string, uint32_t> participant_of_;  // process name -> Fast DDS participant id on this host
  // The process a fault target means now: uav-I, ground, and for place:R the
  // live replica of R with the lowest replica number (null if none runs).
  ChildProcess* resolve(const core::FaultTarget& t);

  // Fault injection (docs/faults.md).
  // Parses --faults / --kill, merges the scenario's schedule, checks it
  // against the swarm; an error message if it cannot run.
  std::optional<std::string> prepare_faults(const core::ScenarioConfig& s, uint32_t uavs, uint32_t regions);
  // Network namespaces for partition and loss, made before anything starts.
  std::optional<std::string> prepare_netns(uint32_t uavs, uint32_t regions);
  [[nodiscard]] double fault_clock_s() const;  // [s] since the swarm was started
  void execute_fault(std::size_t event, std::optional<uint32_t> tick);
  void end_fault(std::size_t event, bool run_over);
  void end_due_faults();
  void end_open_faults();                           // the run is over: continue, remove, give up
  std::string answer_faults(uint32_t tick);         // `faults K` from the lockstep conductor
  void add_fault_metrics(nlohmann::json& m) const;  // metrics.json "faults", "faults_failed", "netns"
  void finish_metrics(int& exit_code);
  void clean_fastdds_shm() const;
  // Requests from the ground station's console (kill / restart / pause).
  void serve_control();
  std::string handle_control(const std::string& line);

  int ctl_fd_ = -1;        // our end of the ground station's control socket
  int child_ctl_fd_ = -1;  // its end, inherited as fd 3 by the ground station only
  std::string ctl_buffer_;
  std::chrono::steady_clock::time_point t0_;
  std::chrono::steady_clock::duration paused_total_{};
  std::optional<std::chrono::steady_clock::time_point> paused_since_;
  std::map<uint32_t, uint32_t> lives_;  // uav -> restarts so far
  std::map<uint32_t, uint32_t> top_replica_;  // region -> highest replica number started
  // Faults.
  std::optional<core::FaultPlan> faults_;
  std::map<std::size_t, std::vector<std::string>> fault_names_;  // event -> processes it acted on
  std::map<std::size_t, std::vector<pid_t>> fault_pids_;
  std::map<std::size_t, std::pair<uint64_t, uint64_t>> fault_packets_;  // partition, loss: frames seen, dropped
  uint32_t fault_failures_ = 0;                                         // events that could not be injected
  std::optional<uint32_t> last_fault_tick_;                             // lockstep: the tick of the last `faults K`
  std::vector<std::string> gone_since_answer_;  // lockstep: processes ended since the last answer
  std::unique_ptr<NetnsSwarm> netns_;
  std::optional<double> netns_setup_s_;    // [s] to make the namespaces
  std::map<pid_t, std::size_t> unreaped_;  // pid -> index in children_, for the children not reaped yet
  // Resource accounting (metrics.json "resources", "wall_s", "udp_*").
  std::chrono::steady_clock::time_point spawn_t0_;  // first spawn
  int64_t run_t0_unix_ms_ = 0;                      // the same instant, Unix time [ms]
  std::optional<double> wall_s_;                    // first spawn -> every child ended [s]
  std::optional<double> sampled_at_s_;              // when sample_resources ran, after the first spawn [s]
  std::optional<UdpCounters> udp_start_, udp_end_;
  uint32_t ticks_ = 0;
  uint32_t regions_ = 0;
  uint32_t uavs_ = 0;
  bool standby_ = false;  // --standby, the scenario's run.standby, or a 'standby' fault: every process runs with --standby
  bool standby_from_scenario_ = false;  // run.standby: a standby for every region from the start
  pid_t discovery_server_pid_ = -1;
  bool start_discovery_server();
  void stop_discovery_server();
  double rate_ = 0;

  RunOptions o_;
  DdsPlan plan_;
  std::string bin_dir_;
  std::vector<ChildProcess> children_;
};

// Folder of the running executable (its siblings are the other binaries).
std::string executable_dir();

}  // namespace pheromesh::cli
