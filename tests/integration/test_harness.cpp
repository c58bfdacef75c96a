// The helpers themselves (harness.hpp): a background process that is still
// running when its test ends, because an ASSERT gave up, is ended with its
// process group. Before, a failed swarm test left its swarm flying, and the
// next test on the same domain read its samples. No DDS.
#include "harness.hpp"

using namespace pheromesh::itest;  // NOLINT: the test helpers

TEST(Harness, ABackgroundProcessStillRunningWhenItsTestEndsIsEndedWithItsGroup) {
  const std::string out = out_dir("harness-background") + "/shell.txt";
  pid_t shell = -1;
  pid_t sleeper = -1;
  {
    // A shell that starts a child of its own, as `sh -c "pheromesh run ..."` does.
    const Background b = start({"/bin/sh", "-c", "sleep 300 & echo $!; wait"}, out);
    shell = b.pid;
    ASSERT_GT(shell, 0);
    ASSERT_TRUE(wait_for_text(out, "\n", std::chrono::seconds(10))) << "the shell printed no pid";
    sleeper = std::stoi(slurp(out));
    ASSERT_EQ(kill(sleeper, 0), 0) << "the shell's child is not running";
  }  // the test "gave up" here, with both running
  errno = 0;
  EXPECT_EQ(waitpid(shell, nullptr, WNOHANG), -1) << "the shell was not reaped";
  EXPECT_EQ(errno, ECHILD);
  // The sleeper is the shell's child, reaped by init once it is gone.
  const auto deadline = Clock::now() + std::chrono::seconds(5);
  while (Clock::now() < deadline && kill(sleeper, 0) == 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_NE(kill(sleeper, 0), 0) << "the shell's child " << sleeper << " outlived the test";
}

TEST(Harness, ABackgroundHandleMovesItsOwnershipAndAWaitedProcessEndsTheTestCleanly) {
  const std::string out = out_dir("harness-waited") + "/true.txt";
  Background b = start({"/bin/true"}, out);
  EXPECT_EQ(wait_exit(b.pid, std::chrono::seconds(10)), 0);
  // One owner after a move: the moved-from handle no longer names the process.
  Background moved = std::move(b);
  EXPECT_EQ(b.pid, -1);  // NOLINT(bugprone-use-after-move): the moved-from state is what is checked
  EXPECT_GT(moved.pid, 0);
}
