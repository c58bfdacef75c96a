// A policy written in Python (issue 27, docs/python.md):
// examples/python/repulsive_coverage.py, the algorithm of the C++ plugin
// examples/repulsive_coverage. `pheromesh sim` of both on the same map and
// seed gives the same field byte for byte; flown in lockstep as real
// processes (every one embedding an interpreter) it gives the simulator's
// numbers on every backend (domain 55), and so does a random walk on the
// UAVs' own streams with a place model in Python (tests/data/python, domain
// 59); an exception raised in Python stops
// the simulator (exit 4) and the UAV processes with Python's traceback
// (domain 58).
#include <cstdlib>
#include <regex>

#include "harness.hpp"

using namespace pheromesh::itest;  // NOLINT: the test helpers

namespace {

const std::string kPythonScenario = kSrc + "/examples/python/repulsive-coverage-python.textproto";

// A copy of the Python example's scenario in OUT with `config` lines added;
// its module is then found through $PHEROMESH_PYTHONPATH.
std::string python_scenario(const std::string& out, const std::string& config) {
  std::string text = slurp(kPythonScenario);
  text = std::regex_replace(text, std::regex("class: \"RepulsiveCoverage\""),
                            "class: \"RepulsiveCoverage\"" + config);
  const std::string path = out + "/repulsive-coverage-python.textproto";
  std::ofstream(path) << text;
  return path;
}

const std::string kPythonPath = "PHEROMESH_PYTHONPATH=" + kSrc + "/examples/python ";

}  // namespace

TEST(Cli, APythonPolicyGivesTheFieldOfTheSameAlgorithmInCppByteForByte) {
  const std::string dir = out_dir("python-vs-cpp");
  // The C++ plugin, built in the build tree (tests/plugins/), on the same map.
  std::string text = slurp(kSrc + "/examples/repulsive_coverage/repulsive-coverage.textproto");
  text = std::regex_replace(text, std::regex("library: \"[^\"]*\""),
                            "library: \"" + std::string(PHEROMESH_TEST_PLUGIN_DIR) +
                                "/libpheromesh_test_plugin_repulsive.so\"");
  const std::string cpp_scenario = dir + "/repulsive-coverage.textproto";
  std::ofstream(cpp_scenario) << text;

  const Output v = run(kBin + "/pheromesh validate " + kPythonScenario);
  ASSERT_EQ(v.exit_code, 0) << v.text;
  EXPECT_NE(v.text.find("policy      repulsive_coverage_py from the Python class "
                        "repulsive_coverage.RepulsiveCoverage (" + kSrc + "/examples/python/repulsive_coverage.py)"),
            std::string::npos)
      << v.text;
  const Output c = run(kBin + "/pheromesh sim " + cpp_scenario + " --seed 3 --tracks --quiet --out " + dir + "/cpp");
  ASSERT_EQ(c.exit_code, 0) << c.text;
  const Output p = run(kBin + "/pheromesh sim " + kPythonScenario + " --seed 3 --tracks --quiet --out " + dir + "/py");
  ASSERT_EQ(p.exit_code, 0) << p.text;
  const json a = read_metrics(dir + "/cpp");
  const json b = read_metrics(dir + "/py");
  EXPECT_EQ(a["policy"], "repulsive_coverage");
  EXPECT_EQ(b["policy"], "repulsive_coverage_py");
  for (const char* key : {"ticks", "uavs", "coverage", "covered_cells", "targets_found", "deposits_sent",
                          "deposits_applied", "field"}) {
    EXPECT_EQ(a[key], b[key]) << key;
  }
  EXPECT_GT(b["covered_cells"].get<int>(), 100);
  EXPECT_GT(b["field"]["cells_marked"].get<double>(), 100.0);  // the class's field_summary
  const std::string field = slurp(dir + "/cpp/final_field.txt");
  EXPECT_GT(field.size(), 1000U);
  EXPECT_TRUE(slurp(dir + "/py/final_field.txt") == field) << "final_field.txt differs";
  // Where every UAV was at every tick, too.
  EXPECT_TRUE(slurp(dir + "/py/tracks.csv") == slurp(dir + "/cpp/tracks.csv")) << "tracks.csv differs";
}

TEST(PythonPolicy, FliesInLockstepAndGivesTheSimulatorsNumbers) {
  // Every process (6 UAVs, 4 place agents, the ground station) imports the module.
  expect_lockstep_matches_sim("../examples/python/repulsive-coverage-python.textproto", "--ticks 40", 55,
                              "python-lockstep");
}

TEST(PythonPolicy, AWalkOnItsRandomStreamWithAPlaceModelInPythonFliesInLockstepAndGivesTheSimulatorsNumbers) {
  // tests/data/python/counted_walk.py: uav.rng and a pheromesh.PlaceModel, in every process.
  // Python's own default buffering, whatever this shell asked for.
  unsetenv("PYTHONUNBUFFERED");
  expect_lockstep_matches_sim("../tests/data/python/counted-walk.textproto", "--ticks 30", 59, "python-place-lockstep");
  // A policy's print() is in its process's log (line-buffered, and flushed at
  // exit: the interpreter is never finalized).
  const std::string log = slurp(out_path("python-place-lockstep-lockstep") + "/logs/uav-2.log");
  EXPECT_NE(log.find("counted_walk: uav 2 starts at ("), std::string::npos) << log;
}

TEST(Cli, AnExceptionInAPythonStepStopsTheRunWithItsTraceback) {
  const std::string dir = out_dir("python-throws");
  const std::string scenario = python_scenario(dir, "\n    config { key: \"fail_at_tick\" number: 5 }");
  const Output s = run(kPythonPath + kBin + "/pheromesh sim " + scenario + " --quiet --out " + dir + "/sim");
  EXPECT_EQ(s.exit_code, 4) << s.text;
  EXPECT_NE(s.text.find("fatal: python policy repulsive_coverage.RepulsiveCoverage: uav 0 tick 5: step raised:"),
            std::string::npos)
      << s.text;
  EXPECT_NE(s.text.find("Traceback (most recent call last):"), std::string::npos) << s.text;
  EXPECT_NE(s.text.find("repulsive_coverage.py\", line "), std::string::npos) << s.text;
  EXPECT_NE(s.text.find("RuntimeError: repulsive_coverage_py: uav 0 was told to fail at tick 5 (config fail_at_tick)"),
            std::string::npos)
      << s.text;

  // Real processes: the UAVs exit 4 and the run fails, naming them; each UAV's log holds the traceback.
  const Output r = run(kPythonPath + kBin + "/pheromesh run " + scenario + " --out " + dir + "/run" +
                       " --domain 58 --progress 0.5 --duration 3 --dds cyclone");
  EXPECT_NE(r.exit_code, 0) << r.text;
  EXPECT_NE(r.text.find("uav-0 (pid"), std::string::npos) << r.text;
  EXPECT_NE(r.text.find("exited with 4"), std::string::npos) << r.text;
  const std::string log = slurp(dir + "/run/logs/uav-0.log");
  EXPECT_NE(log.find("Traceback (most recent call last):"), std::string::npos) << log;
  EXPECT_NE(log.find("RuntimeError: repulsive_coverage_py: uav 0 was told to fail at tick 5"), std::string::npos)
      << log;
}
