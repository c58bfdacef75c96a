#include "child_spawn.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <optional>
#include <thread>

namespace pheromesh::cli {

void close_descriptors_from(int first) noexcept {
  if (close_range(static_cast<unsigned>(first), ~0U, 0) == 0) return;
  // A kernel before 5.9: one by one, up to the limit of open descriptors.
  const long limit = sysconf(_SC_OPEN_MAX);
  for (long fd = first; fd < (limit > 0 && limit < 65536 ? limit : 65536); ++fd) close(static_cast<int>(fd));
}

StopSignalsHeld::StopSignalsHeld() noexcept {
  sigset_t stop;
  sigemptyset(&stop);
  sigaddset(&stop, SIGINT);
  sigaddset(&stop, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop, &old_);
}

StopSignalsHeld::~StopSignalsHeld() { pthread_sigmask(SIG_SETMASK, &old_, nullptr); }

void StopSignalsHeld::release_in_child() const noexcept {
  signal(SIGINT, SIG_DFL);
  signal(SIGTERM, SIG_DFL);
  pthread_sigmask(SIG_SETMASK, &old_, nullptr);
}

void enter_process_group(Scheduling scheduling) noexcept {
  if (scheduling != Scheduling::OwnSession || setsid() < 0) setpgid(0, 0);
}

pid_t spawn_logged_child(const std::string& exe, std::vector<std::string> args, int log_fd, bool default_signals) {
  const pid_t parent = getpid();
  std::optional<StopSignalsHeld> held;
  if (default_signals) held.emplace();
  const pid_t pid = fork();
  if (pid != 0) return pid;             // the parent: the child's pid, or -1
  prctl(PR_SET_PDEATHSIG, SIGTERM);     // never outlives the bench
  if (getppid() != parent) _exit(127);  // the bench ended before prctl took effect
  if (held) held->release_in_child();
  dup2(log_fd, STDOUT_FILENO);
  dup2(log_fd, STDERR_FILENO);
  close_descriptors_from(3);
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  execv(exe.c_str(), argv.data());
  dprintf(STDERR_FILENO, "cannot execute %s: %s\n", exe.c_str(), std::strerror(errno));
  _exit(127);
}

int run_bounded(const std::vector<std::string>& args, const std::string& log, double timeout_s, bool& timed_out) {
  using Clock = std::chrono::steady_clock;
  timed_out = false;
  std::optional<StopSignalsHeld> held(std::in_place);  // as spawn_logged_child's
  const pid_t pid = fork();
  if (pid < 0) return -1;
  if (pid == 0) {
    held->release_in_child();
    setpgid(0, 0);
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd >= 0) {
      dup2(fd, STDOUT_FILENO);
      dup2(fd, STDERR_FILENO);
    }
    close_descriptors_from(3);
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  setpgid(pid, pid);
  held.reset();
  const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
  int st = 0;
  for (;;) {
    const pid_t r = waitpid(pid, &st, WNOHANG);
    if (r == pid) break;
    if (r < 0 && errno != EINTR) return -1;
    if (Clock::now() > deadline) {
      timed_out = true;
      kill(-pid, SIGTERM);
      std::this_thread::sleep_for(std::chrono::seconds(5));
      kill(-pid, SIGKILL);
      waitpid(pid, &st, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
}

}  // namespace pheromesh::cli
