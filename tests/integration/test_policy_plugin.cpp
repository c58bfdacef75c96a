// A policy from a plugin (issue 26, docs/writing-a-policy.md) flown as real
// processes: examples/repulsive_coverage, built in the build tree
// (tests/plugins/), in lockstep on Cyclone DDS (== the simulator, field
// byte-identical; domain 52), in realtime through a killed UAV (domain 53),
// and with an exception from its step, which stops the UAV processes and
// fails the run with the plugin's message (domain 54). The same example built
// against an installed prefix: tests/install/install_consumer.sh.
#include <regex>

#include "harness.hpp"

using namespace pheromesh::itest;  // NOLINT: the test helpers

namespace {

// The example's scenario with its library by the build tree's path, in OUT;
// `config` lines added to the plugin block.
std::string plugin_scenario(const std::string& out, const std::string& config = "") {
  std::string text = slurp(kSrc + "/examples/repulsive_coverage/repulsive-coverage.textproto");
  text = std::regex_replace(text, std::regex("library: \"[^\"]*\""),
                            "library: \"" + std::string(PHEROMESH_TEST_PLUGIN_DIR) +
                                "/libpheromesh_test_plugin_repulsive.so\"" + config);
  const std::string path = out + "/repulsive-coverage.textproto";
  std::ofstream(path) << text;
  return path;
}

std::string run_cmd(const std::string& scenario, const std::string& out, int domain, const std::string& extra) {
  return kBin + "/pheromesh run " + scenario + " --out " + out + " --domain " + std::to_string(domain) +
         " --progress 0.5 " + extra;
}

}  // namespace

TEST(Cli, APluginPolicyFliesInLockstepAndGivesTheSimulatorsFieldByteForByte) {
  const std::string dir = out_dir("plugin-lockstep");
  const std::string scenario = plugin_scenario(dir);
  const Output v = run(kBin + "/pheromesh validate " + scenario);
  ASSERT_EQ(v.exit_code, 0) << v.text;
  EXPECT_NE(v.text.find("policy      repulsive_coverage from the plugin " + std::string(PHEROMESH_TEST_PLUGIN_DIR) +
                        "/libpheromesh_test_plugin_repulsive.so (SHA-256 "),
            std::string::npos)
      << v.text;
  const Output r = run(run_cmd(scenario, dir + "/lockstep", 52, "--clock lockstep --ticks 60 --dds cyclone"));
  ASSERT_EQ(r.exit_code, 0) << r.text;
  EXPECT_NE(r.text.find("policy repulsive_coverage from the plugin"), std::string::npos) << r.text;
  const Output s = run(kBin + "/pheromesh sim " + scenario + " --ticks 60 --quiet --out " + dir + "/sim");
  ASSERT_EQ(s.exit_code, 0) << s.text;
  const json a = read_metrics(dir + "/lockstep");
  const json b = read_metrics(dir + "/sim");
  for (const char* key : {"policy", "ticks", "uavs", "coverage", "covered_cells", "targets_found", "deposits_sent",
                          "deposits_applied", "field"}) {
    EXPECT_EQ(a[key], b[key]) << key;
  }
  EXPECT_EQ(b["policy"], "repulsive_coverage");
  EXPECT_GT(b["field"]["cells_marked"].get<double>(), 50.0);
  expect_accounting(a);
  const std::string field = slurp(dir + "/sim/final_field.txt");
  ASSERT_FALSE(field.empty());
  EXPECT_EQ(slurp(dir + "/lockstep/final_field.txt"), field);
}

TEST(Cli, APluginPolicyFliesInRealtimeThroughAKilledUav) {
  const std::string dir = out_dir("plugin-realtime");
  const std::string scenario = plugin_scenario(dir);
  const Output r = run(run_cmd(scenario, dir + "/run", 53, "--duration 4 --dds cyclone --faults \"kill uav:2 @2s\""));
  ASSERT_EQ(r.exit_code, 0) << r.text;
  const json m = read_metrics(dir + "/run");
  EXPECT_EQ(m["policy"], "repulsive_coverage");
  EXPECT_EQ(m["processes_killed"], 1);
  EXPECT_EQ(m["processes_crashed"], 0);
  EXPECT_GT(m["covered_cells"].get<int>(), 30);
  expect_accounting(m);
}

TEST(Cli, AnExceptionFromAPluginsStepStopsItsProcessesAndFailsTheRunWithTheMessage) {
  const std::string dir = out_dir("plugin-throws");
  const std::string scenario = plugin_scenario(dir, "\n    config { key: \"fail_at_tick\" number: 5 }");
  const Output r = run(run_cmd(scenario, dir + "/run", 54, "--duration 3 --dds cyclone"));
  EXPECT_NE(r.exit_code, 0) << r.text;
  EXPECT_NE(r.text.find("uav-0 (pid"), std::string::npos) << r.text;
  EXPECT_NE(r.text.find("exited with 4"), std::string::npos) << r.text;
  EXPECT_NE(r.text.find("fatal: repulsive_coverage: uav 0 was told to fail at tick 5 (config fail_at_tick)"),
            std::string::npos)
      << r.text;
  // Its last line names the process that failed first, its code and its
  // log's first error (docs/exit-codes.md).
  std::string last = r.text.substr(0, r.text.find_last_not_of('\n') + 1);
  last = last.substr(last.find_last_of('\n') + 1);
  EXPECT_NE(last.find("the run failed: uav-"), std::string::npos) << last;
  EXPECT_NE(last.find(" exited with 4; its log's first error: fatal: repulsive_coverage: uav "), std::string::npos)
      << last;
  // The simulator reports the same and exits non-zero too.
  const Output s = run(kBin + "/pheromesh sim " + scenario + " --quiet --out " + dir + "/sim");
  EXPECT_EQ(s.exit_code, 4) << s.text;
  EXPECT_NE(s.text.find("fatal: repulsive_coverage: uav 0 was told to fail at tick 5"), std::string::npos) << s.text;
}
