// bench start (bench/commands/bench_start.hpp): the command lines it runs,
// and what it reads of a child it ran.
#include <gtest/gtest.h>

#include <cstdlib>

#include "bench/commands/bench_start.hpp"

using namespace pheromesh;  // NOLINT

TEST(BenchStart, TheUavIsLoadedAloneThenStartedAloneOnceForEachVendorAsked) {
  cli::BenchStartOptions o;
  o.scenario = "/s/scale.textproto";
  o.dds = {"fastdds"};
  o.domain = 51;
  const auto cmds = cli::start_commands("/b/pheromesh-uav", o);
  ASSERT_EQ(cmds.size(), 3U);
  EXPECT_EQ(cmds[0].argv, (std::vector<std::string>{"/b/pheromesh-uav", "--help"}));
  EXPECT_EQ(cmds[1].what, "a Fast DDS UAV started alone for one tick");
  EXPECT_EQ(cmds[1].argv, (std::vector<std::string>{"/b/pheromesh-uav", "--scenario", "/s/scale.textproto", "--id", "0",
                                                    "--dds", "fastdds", "--domain", "51", "--wait-for-places", "0",
                                                    "--wait-for-start", "0.1", "--ticks", "1"}));
  EXPECT_TRUE(cmds[1].env.empty());
  // The same start with a key, so that it waits for a start nobody sends,
  // with a big swarm's lease: the waiting row, set beside it.
  EXPECT_EQ(cmds[2].what, "a Fast DDS UAV waiting 4 s for a start, then one tick");
  EXPECT_EQ(cmds[2].argv, (std::vector<std::string>{"/b/pheromesh-uav", "--scenario", "/s/scale.textproto", "--id", "0",
                                                    "--dds", "fastdds", "--domain", "51", "--wait-for-places", "0",
                                                    "--wait-for-start", "4", "--ticks", "1", "--lease-ms", "5000"}));
  ASSERT_EQ(cmds[2].env.size(), 1U);
  EXPECT_EQ(cmds[2].env[0].rfind("PHEROMESH_CONTROL_KEY=", 0), 0U);
  EXPECT_EQ(cmds[2].env[0].size(), std::string("PHEROMESH_CONTROL_KEY=").size() + 64);
  EXPECT_EQ(cmds[2].waits_beside, cmds[1].what);
  o.wait_s = 0;
  EXPECT_EQ(cli::start_commands("/b/pheromesh-uav", o).size(), 2U);
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
  // What the child is given is in its environment, and wins over this process's.
  EXPECT_TRUE(
      cli::run_child({"/bin/sh", "-c", "test \"$PHEROMESH_BENCH_PROBE\" = yes"}, {"PHEROMESH_BENCH_PROBE=yes"}).ok);
  ::setenv("PHEROMESH_BENCH_PROBE", "no", 1);
  EXPECT_FALSE(cli::run_child({"/bin/sh", "-c", "test \"$PHEROMESH_BENCH_PROBE\" = yes"}).ok);
  EXPECT_TRUE(
      cli::run_child({"/bin/sh", "-c", "test \"$PHEROMESH_BENCH_PROBE\" = yes"}, {"PHEROMESH_BENCH_PROBE=yes"}).ok);
  ::unsetenv("PHEROMESH_BENCH_PROBE");
}

TEST(BenchStart, AWaitingRowReadsWhatTheChildRanInItsWindowOnly) {
  ASSERT_FALSE(cli::waiting_window(2.9).has_value());
  const auto w = cli::waiting_window(4);
  ASSERT_TRUE(w.has_value());
  EXPECT_DOUBLE_EQ(w->from_s, 1.5);
  EXPECT_DOUBLE_EQ(w->to_s, 3.5);
  // A child that sleeps runs next to nothing in its window; one that spins
  // runs much of it (two cores shared with the other tests: a loose bound).
  const auto idle = cli::run_child({"/bin/sleep", "0.8"}, {}, cli::Window{0.1, 0.6});
  EXPECT_TRUE(idle.ok);
  ASSERT_TRUE(idle.window_cpu_ms.has_value());
  EXPECT_LT(*idle.window_cpu_ms, 20.0);
  // Spins for one to two seconds of wall time, whatever the host's speed.
  const auto busy =
      cli::run_child({"/bin/bash", "-c", "while [ $SECONDS -lt 2 ]; do :; done"}, {}, cli::Window{0.05, 0.45});
  EXPECT_TRUE(busy.ok);
  ASSERT_TRUE(busy.window_cpu_ms.has_value());
  EXPECT_GT(*busy.window_cpu_ms, 40.0);
  EXPECT_GT(busy.cpu_ms, *busy.window_cpu_ms);
  EXPECT_FALSE(cli::run_child({"/bin/true"}).window_cpu_ms.has_value());
}
