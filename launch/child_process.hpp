// One process `pheromesh run` started, and how it ended: what the supervisor
// (launch/supervisor.hpp) keeps of it and the metrics merge
// (launch/metrics_merge.hpp) reports.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <optional>
#include <string>

#include "proc_stats.hpp"

namespace pheromesh::cli {

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
  // SIGKILLed at the stop because it was still running this long [s] after
  // SIGTERM (0: not): a process that hung or was too slow to stop, which is
  // not a crash and not a kill on purpose (Supervisor::stop_role).
  int killed_after_sigterm_s = 0;
  int exit_code = -1;   // if exited
  int term_signal = 0;  // if signalled
  // From wait4's rusage once reaped (all its threads, and any children it
  // reaped itself).
  bool reaped = false;
  double cpu_user_s = 0;   // ru_utime [s]
  double cpu_sys_s = 0;    // ru_stime [s]
  double max_rss_mib = 0;  // ru_maxrss [MiB]; Linux keeps the pre-exec peak: never below the anonymous memory the
                           // forked copy of the launcher had
  // The one look at it during the flight (Supervisor::sample_resources).
  std::optional<ProcessSample> sample;
  // Its CPU at the start and the end of the steady window of a realtime
  // flight (Supervisor::sample_window; metrics.json "steady").
  std::optional<CpuSample> window_cpu[2];
  // Whether the window reads its threads (CpuDetail::Threads), chosen at the
  // window's opening pass and kept for the closing one.
  bool window_threads = true;
  // Ended by itself with an error, or by a signal nobody sent on purpose
  // (the SIGKILL after an ignored SIGTERM is killed_at_stop instead).
  [[nodiscard]] bool crashed() const;
  // Ended by the SIGKILL the stop sends a process still running after its
  // SIGTERM's grace.
  [[nodiscard]] bool killed_at_stop() const;
  // Ended by a stop's own signal, which is no crash: the launcher's SIGTERM
  // (a process stopped a few milliseconds after its start dies of it before
  // it installs its handlers: 13 of 17 secure Cyclone processes stopped at
  // once, issue 42), or SIGINT (Ctrl-C reaches the whole process group).
  [[nodiscard]] bool ended_by_stop() const;
  // "running", "exited with 3", "killed by Killed (on purpose)", "killed by
  // Killed after ignoring SIGTERM for 10 s", "stopped by Interrupt (Ctrl-C)".
  [[nodiscard]] std::string describe() const;
};

// The first line of a process's log at level error or critical (spdlog's
// pattern of runtime::make_logger: "HH:MM:SS.mmm error [name] ..."), without
// its time stamp, level and name; nothing when there is none.
std::optional<std::string> first_error_line(const std::string& log_path);
// The last line of a failed run (docs/exit-codes.md): "the run failed: ground
// (pid 42) exited with 6; its log's first error: ... (PATH)".
std::string failure_line(const ChildProcess& c, const std::string& log_path);

}  // namespace pheromesh::cli
