#include "child_process.hpp"

#include <csignal>
#include <cstring>
#include <fstream>

namespace pheromesh::cli {

bool ChildProcess::crashed() const {
  if (running || pid < 0) return false;
  if (term_signal != 0) return !killed_on_purpose && !killed_at_stop() && !ended_by_stop();
  return exit_code != 0;
}

bool ChildProcess::ended_by_stop() const {
  if (running || pid < 0) return false;
  return (term_signal == SIGTERM && asked_to_stop) || term_signal == SIGINT;
}

bool ChildProcess::killed_at_stop() const {
  return !running && pid >= 0 && !killed_on_purpose && killed_after_sigterm_s > 0 && term_signal == SIGKILL;
}

std::string ChildProcess::describe() const {
  if (running) return "running";
  if (term_signal != 0) {
    if (ended_by_stop()) {
      return term_signal == SIGINT ? std::string("stopped by Interrupt (Ctrl-C)")
                                   : std::string("stopped by the launcher's SIGTERM before it handled signals");
    }
    if (killed_at_stop()) {
      return std::string("killed by ") + strsignal(term_signal) + " after ignoring SIGTERM for " +
             std::to_string(killed_after_sigterm_s) + " s";
    }
    return std::string("killed by ") + strsignal(term_signal) + (killed_on_purpose ? " (on purpose)" : "");
  }
  return "exited with " + std::to_string(exit_code);
}

std::optional<std::string> first_error_line(const std::string& log_path) {
  std::ifstream in(log_path);
  for (std::string line; std::getline(in, line);) {
    // "HH:MM:SS.mmm LEVEL [name] text"; a terminal's colour codes
    // ("\x1b[31m") may surround the level.
    std::size_t at = line.find(' ');
    if (at == std::string::npos) continue;
    std::string level;
    for (++at; at < line.size() && line[at] != ' ' && line[at] != '['; ++at) {
      if (line[at] == '\x1b') {
        while (at < line.size() && line[at] != 'm') ++at;
        continue;
      }
      level.push_back(line[at]);
    }
    if (level != "error" && level != "critical") continue;
    const auto name = line.find("] ", at);
    return line.substr(name == std::string::npos ? at : name + 2);
  }
  return std::nullopt;
}

std::string failure_line(const ChildProcess& c, const std::string& log_path) {
  const auto first = first_error_line(log_path);
  return "the run failed: " + c.name + " (pid " + std::to_string(c.pid) + ") " + c.describe() +
         (first ? "; its log's first error: " + *first : std::string("; its log has no error line")) + " (" +
         log_path + ")";
}

}  // namespace pheromesh::cli
