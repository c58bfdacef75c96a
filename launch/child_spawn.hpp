// Starting `pheromesh run` as the child of a bench (bench scale, bench soak):
// its output goes to a log file, and it dies with the bench. And what every
// child of the CLI does between fork and exec: the descriptors it keeps, the
// process group and session it goes into.
#pragma once

#include <sys/types.h>

#include <csignal>

#include <cstdint>
#include <string>
#include <vector>

namespace pheromesh::cli {

// How the kernel weighs the process against the others on the host. A place
// agent serves a hundred UAVs or more and the ground station hears them all:
// while hundreds of UAV processes are runnable at once (the swarm's start,
// a burst of views), a hub that waits its turn among them as one process of
// thousands stalls for seconds, its UAVs go without views, take it for dead
// and move to their backup gateway, whose discovery loads the host further
// (measured: docs/benchmarks.md, "2000 UAV processes on two cores"). So a
// hub starts a session of its own (setsid), and with the kernel's automatic
// grouping (Linux autogroup, on by default) it weighs as much as the whole
// herd of UAVs, which share the launcher's session; it still takes only
// the CPU it uses. Realtime swarms only (run_plan.cpp): in lockstep it made
// the UAV phase slower. Where autogroup is off, or the processes run in a CPU
// cgroup other than the root (a container, a systemd login session), a
// session changes nothing but the session.
enum class Scheduling : uint8_t { LauncherSession, OwnSession };

// In a forked child, before exec: a process group of its own (the launcher
// signals each child by its pid and orders the shutdown itself; Ctrl-C at
// the terminal reaches the launcher only), and with OwnSession a session of
// its own too (setsid; a child just forked is no group leader yet, so it
// cannot fail). Async-signal-safe.
void enter_process_group(Scheduling scheduling) noexcept;

// Between fork and exec a child still has its parent's signal handlers. A
// SIGINT or SIGTERM that reaches it there runs the parent's handler in the
// child (the launcher's only sets a flag), and exec forgets it: the program
// then starts as if it had never been told to stop, and is SIGKILLed 10 s
// later (seen when a swarm is stopped while it starts). So the parent holds
// both signals (blocked) across the fork, and the child sets them to their
// default action before it lets them through: one sent in between ends it.
class StopSignalsHeld {
 public:
  // Blocks SIGINT and SIGTERM in the calling thread.
  StopSignalsHeld() noexcept;
  // The parent: its mask as it was; a signal held meanwhile is handled now.
  ~StopSignalsHeld();
  StopSignalsHeld(const StopSignalsHeld&) = delete;
  StopSignalsHeld& operator=(const StopSignalsHeld&) = delete;
  // In the forked child: SIGINT and SIGTERM to their default action, then
  // the parent's mask. Async-signal-safe.
  void release_in_child() const noexcept;

 private:
  sigset_t old_{};
};

// In a forked child, just before exec: closes every descriptor from `first`
// up, so the program gets stdin, stdout, stderr (and whatever the caller put
// below `first`) and nothing else its parent had open without close-on-exec
// (a test runner's log, another child's pipe, a socket). Async-signal-safe.
void close_descriptors_from(int first) noexcept;

// Forks and executes `exe` with `args` (args[0] is the program name), its
// stdout and stderr on `log_fd` and no other descriptor of the caller's. The child gets SIGTERM when the calling
// process ends (PR_SET_PDEATHSIG) and stays in the caller's process group.
// With `default_signals`, SIGINT and SIGTERM are reset to their default
// action in the child (for a caller that installed handlers of its own),
// held across the fork (StopSignalsHeld).
// Returns the child's pid, or -1 (errno set) when fork failed. The caller
// still owns `log_fd`.
pid_t spawn_logged_child(const std::string& exe, std::vector<std::string> args, int log_fd, bool default_signals);

// Runs args (args[0] is the program's path) with stdout and stderr into the
// file `log`, in a process group of its own, and waits for it; after
// `timeout_s` it sends the group SIGTERM, then SIGKILL 5 s later, and sets
// `timed_out`. Returns the exit status (128 + signal), or -1 if it could not
// start.
int run_bounded(const std::vector<std::string>& args, const std::string& log, double timeout_s, bool& timed_out);

}  // namespace pheromesh::cli
