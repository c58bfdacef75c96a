// bench start (bench/commands/bench_start.hpp): the command lines it runs,
// and what it reads of a child it ran.
#include <gtest/gtest.h>

#include "bench/commands/bench_start.hpp"

using namespace pheromesh;  // NOLINT

TEST(BenchStart, TheUavIsLoadedAloneThenStartedAloneOnceForEachVendorAsked) {
  cli::BenchStartOptions o;
  o.scenario = "/s/scale.textproto";
  o.dds = {"fastdds"};
  o.domain = 51;
  const auto cmds = cli::start_commands("/b/pheromesh-uav", o);
  ASSERT_EQ(cmds.size(), 2U);
  EXPECT_EQ(cmds[0].argv, (std::vector<std::string>{"/b/pheromesh-uav", "--help"}));
  EXPECT_EQ(cmds[1].what, "a Fast DDS UAV started alone for one tick");
  EXPECT_EQ(cmds[1].argv, (std::vector<std::string>{"/b/pheromesh-uav", "--scenario", "/s/scale.textproto", "--id", "0",
                                                    "--dds", "fastdds", "--domain", "51", "--wait-for-places", "0",
                                                    "--wait-for-start", "0.1", "--ticks", "1"}));
}

TEST(BenchStart, AChildsCpuIsItsOwnAndAFailureIsSeen) {
  // A child that spins for a while costs CPU that the parent did not spend.
  const auto busy = cli::run_child({"/bin/sh", "-c", "i=0; while [ $i -lt 200000 ]; do i=$((i+1)); done"});
  EXPECT_TRUE(busy.ok);
  EXPECT_GT(busy.cpu_ms, 20.0);
  const auto idle = cli::run_child({"/bin/true"});
  EXPECT_TRUE(idle.ok);
  EXPECT_LT(idle.cpu_ms, busy.cpu_ms);
  EXPECT_FALSE(cli::run_child({"/bin/sh", "-c", "exit 3"}).ok);
  EXPECT_FALSE(cli::run_child({"/nonexistent/program"}).ok);
}
