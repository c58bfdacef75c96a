// The children the CLI starts (launch/child_spawn.hpp) get their log and the
// standard streams, and no other descriptor the parent held open without
// close-on-exec. ctest hands its test processes its log as fd 3 that way; a
// swarm that inherited it kept ctest waiting after a failed test.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "launch/child_spawn.hpp"

namespace pheromesh::cli {
namespace {

namespace fs = std::filesystem;

// The descriptor numbers a child listed (one per line, as `ls /proc/self/fd` prints them).
std::set<int> listed(const fs::path& log) {
  std::ifstream in(log);
  std::set<int> fds;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line.find_first_not_of("0123456789") == std::string::npos) fds.insert(std::stoi(line));
  }
  return fds;
}

class ChildSpawn : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("phm-child-spawn-" + std::to_string(getpid()));
    fs::create_directories(dir_);
    // Held open without close-on-exec, at a number the child would not reuse.
    const int fd = open("/dev/null", O_RDONLY);
    ASSERT_GE(fd, 0);
    leaked_ = fcntl(fd, F_DUPFD, 50);
    close(fd);
    ASSERT_GE(leaked_, 50);
    ASSERT_EQ(fcntl(leaked_, F_GETFD) & FD_CLOEXEC, 0);
  }
  void TearDown() override {
    if (leaked_ >= 0) close(leaked_);
    fs::remove_all(dir_);
  }
  fs::path dir_;
  int leaked_ = -1;
};

TEST_F(ChildSpawn, ALoggedChildHasItsLogAndTheStandardStreamsOnly) {
  const fs::path log = dir_ / "ls.log";
  const int log_fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  ASSERT_GE(log_fd, 0);
  const pid_t pid = spawn_logged_child("/bin/ls", {"ls", "/proc/self/fd"}, log_fd, false);
  close(log_fd);
  ASSERT_GT(pid, 0);
  int st = 0;
  ASSERT_EQ(waitpid(pid, &st, 0), pid);
  ASSERT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0) << "status " << st;
  const std::set<int> fds = listed(log);
  EXPECT_TRUE(fds.count(1) && fds.count(2)) << "stdout and stderr are missing";
  EXPECT_EQ(fds.count(leaked_), 0u) << "the child inherited the parent's descriptor " << leaked_;
  // ls opens the directory it lists: at most 0, 1, 2 and that one.
  EXPECT_LE(fds.size(), 4u);
}

TEST_F(ChildSpawn, ABoundedRunHasItsLogAndTheStandardStreamsOnly) {
  const fs::path log = dir_ / "bounded.log";
  bool timed_out = true;
  EXPECT_EQ(run_bounded({"/bin/ls", "/proc/self/fd"}, log.string(), 30.0, timed_out), 0);
  EXPECT_FALSE(timed_out);
  const std::set<int> fds = listed(log);
  EXPECT_TRUE(fds.count(1) && fds.count(2)) << "stdout and stderr are missing";
  EXPECT_EQ(fds.count(leaked_), 0u) << "the child inherited the parent's descriptor " << leaked_;
  EXPECT_LE(fds.size(), 4u);
}

// What a child forked from this test and put in its group reports, as its
// exit code: 0 when it leads a process group of its own and its session is
// `own_session ? its own : ours`.
int group_of_a_child(Scheduling scheduling, bool own_session) {
  const pid_t ours = getsid(0);
  const pid_t pid = fork();
  if (pid == 0) {
    enter_process_group(scheduling);
    const bool group = getpgid(0) == getpid();
    const bool session = own_session ? getsid(0) == getpid() : getsid(0) == ours;
    _exit(group && session ? 0 : 1);
  }
  int st = 0;
  if (pid < 0 || waitpid(pid, &st, 0) != pid || !WIFEXITED(st)) return -1;
  return WEXITSTATUS(st);
}

TEST(ChildGroup, AHubLeadsASessionAndAGroupOfItsOwnAndAUavAGroupInTheLaunchersSession) {
  EXPECT_EQ(group_of_a_child(Scheduling::OwnSession, /*own_session=*/true), 0);
  EXPECT_EQ(group_of_a_child(Scheduling::LauncherSession, /*own_session=*/false), 0);
  // The checks can fail: a UAV's child is not in a session of its own.
  EXPECT_EQ(group_of_a_child(Scheduling::LauncherSession, /*own_session=*/true), 1);
}

}  // namespace
namespace {
std::atomic<int> g_stop_signals_caught{0};
extern "C" void count_stop_signal(int /*sig*/) { g_stop_signals_caught.fetch_add(1); }
}  // namespace

// The launcher's handlers, and a SIGTERM that reaches a child between fork
// and exec (a swarm stopped while it starts): without StopSignalsHeld the
// parent's handler runs in the child and the stop is lost; with it, the
// child dies of it, and the parent's own signals still reach its handler.
TEST(StopSignalsHeld, AStopThatReachesAChildBeforeItsExecEndsItInsteadOfRunningTheParentsHandler) {
  struct sigaction sa {};
  struct sigaction old_int {};
  struct sigaction old_term {};
  sa.sa_handler = count_stop_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGTERM, &sa, &old_term);
  sigaction(SIGINT, &sa, &old_int);
  g_stop_signals_caught = 0;
  int st = 0;
  const pid_t bare = fork();
  if (bare == 0) {
    raise(SIGTERM);
    _exit(g_stop_signals_caught.load() == 1 ? 0 : 3);
  }
  ASSERT_EQ(waitpid(bare, &st, 0), bare);
  EXPECT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0) << "unheld, the parent's handler swallows the stop in the child";
  {
    const StopSignalsHeld held;
    const pid_t pid = fork();
    if (pid == 0) {
      raise(SIGTERM);  // sent between fork and exec: held
      held.release_in_child();
      _exit(0);  // not reached: the held SIGTERM ends the child at its default action
    }
    ASSERT_EQ(waitpid(pid, &st, 0), pid);
  }
  ASSERT_TRUE(WIFSIGNALED(st)) << "the child went on: status " << st;
  EXPECT_EQ(WTERMSIG(st), SIGTERM);
  EXPECT_EQ(g_stop_signals_caught.load(), 0) << "no handler ran in the parent";
  raise(SIGTERM);  // the parent's mask is as it was
  EXPECT_EQ(g_stop_signals_caught.load(), 1);
  sigaction(SIGTERM, &old_term, nullptr);
  sigaction(SIGINT, &old_int, nullptr);
}

}  // namespace pheromesh::cli
