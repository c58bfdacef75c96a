// One process `pheromesh run` started, and how it ended: what the supervisor
// (cli/supervisor.hpp) keeps of it and the metrics merge
// (cli/metrics_merge.hpp) reports.
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
  // Ended by itself with an error, or by a signal nobody sent on purpose.
  [[nodiscard]] bool crashed() const;
  // "running", "exited with 3", "killed by Killed (on purpose)".
  [[nodiscard]] std::string describe() const;
};

}  // namespace pheromesh::cli
