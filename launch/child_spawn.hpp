// Starting `pheromesh run` as the child of a bench (bench scale, bench soak):
// its output goes to a log file, and it dies with the bench.
#pragma once

#include <sys/types.h>

#include <string>
#include <vector>

namespace pheromesh::cli {

// In a forked child, just before exec: closes every descriptor from `first`
// up, so the program gets stdin, stdout, stderr (and whatever the caller put
// below `first`) and nothing else its parent had open without close-on-exec
// (a test runner's log, another child's pipe, a socket). Async-signal-safe.
void close_descriptors_from(int first) noexcept;

// Forks and executes `exe` with `args` (args[0] is the program name), its
// stdout and stderr on `log_fd` and no other descriptor of the caller's. The child gets SIGTERM when the calling
// process ends (PR_SET_PDEATHSIG) and stays in the caller's process group.
// With `default_signals`, SIGINT and SIGTERM are reset to their default
// action in the child (for a caller that installed handlers of its own).
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
