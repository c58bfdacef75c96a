#include "child_process.hpp"

#include <cstring>

namespace pheromesh::cli {

bool ChildProcess::crashed() const {
  if (running || pid < 0) return false;
  if (term_signal != 0) return !killed_on_purpose;
  return exit_code != 0;
}

std::string ChildProcess::describe() const {
  if (running) return "running";
  if (term_signal != 0) {
    return std::string("killed by ") + strsignal(term_signal) + (killed_on_purpose ? " (on purpose)" : "");
  }
  return "exited with " + std::to_string(exit_code);
}

}  // namespace pheromesh::cli
