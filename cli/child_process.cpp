#include "child_process.hpp"

#include <csignal>

#include <cstring>

namespace pheromesh::cli {

bool ChildProcess::crashed() const {
  if (running || pid < 0) return false;
  if (term_signal != 0) return !killed_on_purpose && !killed_at_stop();
  return exit_code != 0;
}

bool ChildProcess::killed_at_stop() const {
  return !running && pid >= 0 && !killed_on_purpose && killed_after_sigterm_s > 0 && term_signal == SIGKILL;
}

std::string ChildProcess::describe() const {
  if (running) return "running";
  if (term_signal != 0) {
    if (killed_at_stop()) {
      return std::string("killed by ") + strsignal(term_signal) + " after ignoring SIGTERM for " +
             std::to_string(killed_after_sigterm_s) + " s";
    }
    return std::string("killed by ") + strsignal(term_signal) + (killed_on_purpose ? " (on purpose)" : "");
  }
  return "exited with " + std::to_string(exit_code);
}

}  // namespace pheromesh::cli
