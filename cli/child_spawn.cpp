#include "child_spawn.hpp"

#include <sys/prctl.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>

namespace pheromesh::cli {

pid_t spawn_logged_child(const std::string& exe, std::vector<std::string> args, int log_fd, bool default_signals) {
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid != 0) return pid;             // the parent: the child's pid, or -1
  prctl(PR_SET_PDEATHSIG, SIGTERM);     // never outlives the bench
  if (getppid() != parent) _exit(127);  // the bench ended before prctl took effect
  if (default_signals) {
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
  }
  dup2(log_fd, STDOUT_FILENO);
  dup2(log_fd, STDERR_FILENO);
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  execv(exe.c_str(), argv.data());
  dprintf(STDERR_FILENO, "cannot execute %s: %s\n", exe.c_str(), std::strerror(errno));
  _exit(127);
}

}  // namespace pheromesh::cli
