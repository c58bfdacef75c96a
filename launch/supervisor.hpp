// The side of `pheromesh run` that acts on processes: starts those of a
// RunPlan, reaps them, serves the ground station's control line (the
// console's kill / restart / pause, the lockstep conductor's `faults K`),
// injects the plan's faults (docs/faults.md; launch/supervisor_faults.cpp),
// watches the flight against the plan's deadlines and stops the roles in the
// plan's order. What it saw becomes a RunRecord for the metrics merge.
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

#include "child_process.hpp"
#include "metrics_merge.hpp"
#include "netns.hpp"
#include "pheromesh/core/fault_plan.hpp"
#include "pheromesh/core/result.hpp"
#include "proc_stats.hpp"
#include "run_plan.hpp"

namespace pheromesh::cli {

// How the flight ended: this host's UAVs (over several hosts: all its
// processes) ended, or the launcher stopped them early (SIGINT / SIGTERM, or
// the lockstep conductor gone).
enum class FlightEnd : uint8_t { Landed, Interrupted };

class Supervisor {
 public:
  explicit Supervisor(RunPlan plan);
  ~Supervisor();
  Supervisor(const Supervisor&) = delete;
  Supervisor& operator=(const Supervisor&) = delete;
  Supervisor(Supervisor&&) = delete;
  Supervisor& operator=(Supervisor&&) = delete;

  // Network namespaces for partition and loss, made before anything starts;
  // an error message if they cannot be.
  std::optional<std::string> prepare_netns();
  // Starts the discovery server (--discovery-server), the ground station and
  // the swarm. False if the discovery server cannot run (logged); if
  // interrupted while starting, fly() stops what was started.
  [[nodiscard]] bool start();
  // Until the UAVs have ended: reaps, serves the control line, injects and
  // ends faults, takes the resource sample, enforces the plan's deadlines.
  FlightEnd fly();
  // After the flight: lasting faults end, the plan's final stop order.
  void land();
  [[nodiscard]] RunRecord record() const;
  // The first process that crashed (failure_line: its name, how it ended and
  // its log's first error line), if one did: the last line of a failed run.
  [[nodiscard]] const std::optional<std::string>& first_failure() const { return first_failure_; }
  // After the merge: the discovery server, Fast DDS's shared memory, the
  // network namespaces.
  void clean_up();

 private:
  std::optional<std::string> first_failure_;
  // Starting.
  void spawn(PlannedProcess p);
  void wait_spawn_gap();
  // The Fast DDS participant id of a process: its earlier life's, or the
  // next of this host's numbering.
  [[nodiscard]] uint32_t participant_for(const std::string& name) const;
  void spawn_place(uint32_t region, uint32_t replica);
  // Starts the place agents and then the UAVs, in batches when the plan
  // staggers them. Returns false if interrupted before all were started.
  bool spawn_swarm();
  // Cells: until this host's hubs listen (hub_gate.hpp); false if interrupted.
  bool await_hubs();
  bool pause_before_batch(uint32_t uav);
  // Starts an ended process again (console restart, restart fault): a UAV for
  // its remaining ticks, its deposits numbered above its earlier lives'; a
  // place agent for the same region and replica. Returns the new pid.
  core::Result<pid_t> respawn(const std::string& name);
  [[nodiscard]] int64_t uav_ticks_left() const;
  void open_control_line();
  void log_console_url(const std::string& token) const;
  bool start_discovery_server();
  void stop_discovery_server();

  // Reaping and stopping.
  void reap();
  // Records how a child ended (from wait4).
  void record_exit(pid_t pid, int status, const rusage& ru);
  // SIGKILL, then wait until it is reaped (a lockstep kill is complete when
  // the conductor hears of it).
  void kill_and_reap(ChildProcess& c);
  void stop_role(const StopStep& step);
  void stop_early();
  [[nodiscard]] bool any_running(const std::string& role) const;
  [[nodiscard]] bool flying() const;
  ChildProcess* find(const std::string& name);
  void sample_resources();
  void sample_window(int end);  // 0: the steady window's start, 1: its end
  // The ground station is one of this host's processes (the plan starts it first).
  [[nodiscard]] bool ground_here() const {
    return !plan_.processes.empty() && plan_.processes.front().role == "ground";
  }
  void clean_fastdds_shm() const;

  // The flight's watches, each at most once per 10 ms round.
  void watch_resources(std::chrono::steady_clock::time_point now, std::chrono::steady_clock::duration paused);
  void watch_conductor(std::chrono::steady_clock::time_point now);
  void watch_deadline(std::chrono::steady_clock::time_point now, std::chrono::steady_clock::duration paused);
  void interrupt();
  [[nodiscard]] bool ended_by_itself(const std::string& role) const;

  // Requests from the ground station's console (kill / restart / pause).
  void serve_control();
  std::string handle_control(const std::string& line);
  std::string control_process(const std::string& verb, const std::string& role, uint32_t index);

  // Fault injection (docs/faults.md; supervisor_faults.cpp). `i` is an
  // event's index in the schedule (core::FaultPlan::event).
  enum class FaultEnd : uint8_t { Due, RunOver };
  // What an injection did: the processes it acted on, notes for metrics.json.
  struct FaultActs {
    std::vector<std::string> names, notes;
    std::vector<pid_t> pids;
  };
  [[nodiscard]] double fault_clock_s() const;  // [s] since the swarm was started
  // The process a fault target means now: uav-I, ground, and for place:R the
  // live replica of R with the lowest replica number (null if none runs).
  ChildProcess* resolve(const core::FaultTarget& t);
  void execute_fault(std::size_t i, std::optional<uint32_t> tick);
  void inject_kill(const core::FaultEvent& e, const std::string& when, FaultActs& acts);
  void inject_stop(const core::FaultEvent& e, const std::string& when, FaultActs& acts);
  void inject_standby(const core::FaultEvent& e, const std::string& when, FaultActs& acts);
  void inject_network(std::size_t i, const core::FaultEvent& e, const std::string& when, FaultActs& acts);
  static void fault_not_running(const core::FaultEvent& e, const core::FaultTarget& t, const std::string& when,
                                FaultActs& acts);
  void fault_failed(const core::FaultEvent& e, const std::string& err, FaultActs& acts);
  void end_fault(std::size_t i, FaultEnd end);
  void continue_stopped(std::size_t i, double now, FaultEnd end);
  void lift_network(std::size_t i, double now, FaultEnd end, std::vector<std::string>& notes);
  void restart_killed(std::size_t i, double now, FaultEnd end, std::vector<std::string>& notes);
  void end_due_faults();
  void end_open_faults();                              // the run is over: continue, remove, give up
  std::string answer_faults(uint32_t tick);            // `faults K` from the lockstep conductor
  [[nodiscard]] nlohmann::json fault_metrics() const;  // metrics.json "faults", "faults_failed", "netns"

  RunPlan plan_;
  std::vector<ChildProcess> children_;
  std::map<pid_t, std::size_t> unreaped_;           // pid -> index in children_, for the children not reaped yet
  std::map<std::string, uint32_t> participant_of_;  // process name -> Fast DDS participant id on this host
  std::map<uint32_t, uint32_t> lives_;              // uav -> restarts so far
  std::map<uint32_t, uint32_t> top_replica_;        // region -> highest replica number started
  std::chrono::steady_clock::time_point last_spawn_{};
  pid_t discovery_server_pid_ = -1;

  // The control line.
  int ctl_fd_ = -1;        // our end of the ground station's control socket
  int child_ctl_fd_ = -1;  // its end, inherited as fd 3 by the ground station only
  std::string ctl_buffer_;

  // The flight.
  std::chrono::steady_clock::time_point t0_;  // every process of this host started
  std::chrono::steady_clock::duration paused_total_{};
  std::optional<std::chrono::steady_clock::time_point> paused_since_;
  bool sampled_ = false;
  FlightEnd flight_end_ = FlightEnd::Landed;
  // Lockstep: when the conductor (the ground station) ended.
  std::optional<std::chrono::steady_clock::time_point> conductor_gone_at_;

  // Faults.
  std::optional<core::FaultPlan> faults_;
  std::map<std::size_t, std::vector<std::string>> fault_names_;  // event -> processes it acted on
  std::map<std::size_t, std::vector<pid_t>> fault_pids_;
  std::map<std::size_t, std::pair<uint64_t, uint64_t>> fault_packets_;  // partition, loss: frames seen, dropped
  uint32_t fault_failures_ = 0;                                         // events that could not be injected
  std::optional<uint32_t> last_fault_tick_;                             // lockstep: the tick of the last `faults K`
  std::vector<std::string> gone_since_answer_;  // lockstep: processes ended since the last answer
  std::unique_ptr<NetnsSwarm> netns_;
  std::optional<double> netns_setup_s_;  // [s] to make the namespaces

  // Resource accounting (metrics.json "resources", "wall_s", "udp_*").
  std::chrono::steady_clock::time_point spawn_t0_;  // first spawn
  int64_t run_t0_unix_ms_ = 0;                      // the same instant, Unix time [ms]
  std::optional<double> wall_s_;                    // first spawn -> every child ended [s]
  std::optional<double> sampled_at_s_;              // when sample_resources ran, after the first spawn [s]
  std::optional<UdpCounters> udp_start_, udp_end_;
  // The steady window of a realtime flight (metrics.json "steady"): from a
  // fifth to four fifths of the flight after the ground station's start.
  std::optional<std::chrono::steady_clock::time_point> started_at_;  // the ground station said "started"
  int windows_taken_ = 0;                                            // 0, 1 (start sampled) or 2
  std::chrono::steady_clock::time_point window_at_[2];
  std::optional<UdpCounters> window_udp_[2];
  // How long the passes over the processes took (the window's opening and
  // the resource sample): the window's closing pass starts that much before
  // four fifths of the flight, so that it ends there, not after the UAVs.
  std::chrono::steady_clock::duration passes_{};
};

}  // namespace pheromesh::cli
