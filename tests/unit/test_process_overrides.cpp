// The flags every process takes that change the scenario (--uavs, --ticks,
// --seed, --rate; runtime::load_scenario): validated with the file exactly as
// `pheromesh --set` is, the error naming the flag; 0 is a value like any
// other (refused where the file refuses it), never "the scenario's".
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "pheromesh/runtime/process.hpp"

namespace pheromesh::runtime {
namespace {

std::string small_test() { return std::string(PHEROMESH_SOURCE_DIR) + "/scenarios/small-test.textproto"; }

std::string error_of(const core::Result<core::ScenarioConfig>& r) { return r.ok() ? "" : r.error().message; }

TEST(ProcessOverrides, AValueTheFileMayNotHoldIsRefusedNamingTheFlag) {
  CommonOptions o;
  o.scenario = small_test();
  o.ticks = "0";
  EXPECT_EQ(error_of(load_scenario(o)), "--ticks 0: field 'run.ticks': must be between 1 and 4294967295 (got 0)");
  o.ticks.reset();
  o.uavs = "0";
  EXPECT_EQ(error_of(load_scenario(o)), "--uavs 0: field 'swarm.uavs': must be between 1 and 5000 (got 0)");
  o.uavs = "50";  // small-test's start area is 4 x 4
  EXPECT_NE(error_of(load_scenario(o)).find("--uavs 50: field 'swarm.uavs': the start area holds 16 UAVs"),
            std::string::npos)
      << error_of(load_scenario(o));
  o.uavs.reset();
  o.rate_hz = "0";
  EXPECT_NE(error_of(load_scenario(o)).find("--rate 0: field 'run.tick_rate_hz': must be in (0, 1000]"),
            std::string::npos)
      << error_of(load_scenario(o));
  o.rate_hz = "fast";
  EXPECT_NE(error_of(load_scenario(o)).find("--rate fast:"), std::string::npos) << error_of(load_scenario(o));
}

TEST(ProcessOverrides, EveryFlagGivenChangesTheScenarioSeedZeroIncluded) {
  CommonOptions o;
  o.scenario = small_test();
  const auto plain = load_scenario(o);
  ASSERT_TRUE(plain.ok()) << plain.error().message;
  ASSERT_NE(plain->seed, 0U);
  o.seed = "0";
  o.uavs = "3";
  o.ticks = "7";
  o.rate_hz = "25";
  const auto s = load_scenario(o);
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(s->seed, 0U);
  EXPECT_EQ(s->uavs, 3U);
  EXPECT_EQ(s->ticks, 7U);
  EXPECT_DOUBLE_EQ(s->tick_rate_hz, 25.0);
  EXPECT_EQ(core::describe_overrides(overrides_of(o)), "--rate 25, --ticks 7, --seed 0, --uavs 3");
}

// $PHEROMESH_RUN_ONE_HOST, which `pheromesh run` sets without --hosts: the
// tick ceiling's slack (core::kOneHostSlack), else a LAN run's.
TEST(LaunchSlack, OneHostIsTwoSecondsAndFiveTicksAndAnythingElseTheLanSlack) {
  unsetenv(kOneHostEnv);
  EXPECT_EQ(launch_slack().seconds, 30.0);
  setenv(kOneHostEnv, "1", 1);
  EXPECT_EQ(launch_slack().seconds, 2.0);
  EXPECT_EQ(launch_slack().ticks, 5U);
  setenv(kOneHostEnv, "yes", 1);
  EXPECT_EQ(launch_slack().seconds, 30.0) << "only 1 means one host";
  unsetenv(kOneHostEnv);
}

}  // namespace
}  // namespace pheromesh::runtime
