// runtime::bound_teardown: a process whose teardown hangs after its work is
// done ends anyway, with the app's exit code; one that ends by itself is not
// touched. Real child processes (fork), the hang a blocked sleep.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <thread>

#include "pheromesh/runtime/process.hpp"

namespace pheromesh::runtime {
namespace {

using namespace std::chrono_literals;

// Waits up to `limit` for `pid`; the raw status, or -1 (then it is killed).
int wait_status(pid_t pid, std::chrono::milliseconds limit) {
  const auto until = std::chrono::steady_clock::now() + limit;
  int status = 0;
  while (std::chrono::steady_clock::now() < until) {
    if (waitpid(pid, &status, WNOHANG) == pid) return status;
    std::this_thread::sleep_for(10ms);
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  return -1;
}

TEST(Teardown, AProcessWhoseTeardownHangsEndsWithTheAppsCodeAfterTheGrace) {
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    (void)bound_teardown(7, 300ms);
    for (;;) pause();  // the teardown that never ends; SIGTERM is not what ends it here
  }
  const int status = wait_status(pid, 5000ms);
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_NE(status, -1) << "the hung child did not end within 5 s";
  ASSERT_TRUE(WIFEXITED(status)) << status;
  EXPECT_EQ(WEXITSTATUS(status), 7);
  EXPECT_GE(took, 0.3);
}

TEST(Teardown, AProcessThatEndsBeforeTheGraceKeepsItsOwnExit) {
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    (void)bound_teardown(7, 2000ms);
    std::this_thread::sleep_for(50ms);  // a teardown that ends
    _exit(3);
  }
  const int status = wait_status(pid, 5000ms);
  ASSERT_NE(status, -1);
  ASSERT_TRUE(WIFEXITED(status)) << status;
  EXPECT_EQ(WEXITSTATUS(status), 3);
}

}  // namespace
}  // namespace pheromesh::runtime
