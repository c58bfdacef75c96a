// Every process's log reaches its log file (issue 42 D3): the ground station
// under `pheromesh run` has its stderr on the launcher's terminal and its
// stdout on its log file, and its log was empty; runtime::make_logger writes
// to both when they are different files (runtime::streams_differ).
#include <gtest/gtest.h>
#include <fcntl.h>
#include <unistd.h>

#include <string>

#include "pheromesh/runtime/process.hpp"

namespace pheromesh::runtime {
namespace {

TEST(ProcessLog, TwoDescriptorsOfOneFileAreNotDifferentStreamsAndTwoFilesAre) {
  const std::string a = ::testing::TempDir() + "/phm-log-a-" + std::to_string(::getpid());
  const std::string b = ::testing::TempDir() + "/phm-log-b-" + std::to_string(::getpid());
  const int fa = ::open(a.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  const int fb = ::open(b.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ASSERT_GE(fa, 0);
  ASSERT_GE(fb, 0);
  const int again = ::dup(fa);  // as `pheromesh run` gives a UAV its log as stdout and stderr
  EXPECT_FALSE(streams_differ(fa, again));
  EXPECT_TRUE(streams_differ(fa, fb));  // as it gives the ground station
  EXPECT_FALSE(streams_differ(fa, -1)) << "a descriptor that cannot be inspected: one stream";
  ::close(again);
  ::close(fa);
  ::close(fb);
  ::unlink(a.c_str());
  ::unlink(b.c_str());
}

}  // namespace
}  // namespace pheromesh::runtime
