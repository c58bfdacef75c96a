// Policy plugins (core/policy_plugin.hpp, core/plugin_loader.hpp): a scenario
// names a library, the parser loads it and the plugin reads its config with
// errors at their lines; every refusal (not found, not a plugin, another ABI,
// a built-in's name, a SHA-256 pin) says what and where. The plugin is
// examples/repulsive_coverage built in the build tree (tests/plugins/).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "pheromesh/core/plugin_loader.hpp"
#include "pheromesh/core/policy_table.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/sha256.hpp"
#include "pheromesh/core/simulator.hpp"

using namespace pheromesh::core;
namespace fs = std::filesystem;

namespace {

const std::string kDir = PHEROMESH_TEST_PLUGIN_DIR;
const std::string kRepulsive = kDir + "/libpheromesh_test_plugin_repulsive.so";

// A temporary folder with scenario files; removed at the end of the test.
class PluginScenario : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("phm-plugin-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    unsetenv(kPluginPinEnv);
    unsetenv(kPluginPathEnv);
  }
  void TearDown() override {
    fs::remove_all(dir_);
    unsetenv(kPluginPinEnv);
    unsetenv(kPluginPathEnv);
  }
  // A scenario whose policy block is `plugin` (the text inside plugin { }).
  std::string write(const std::string& plugin, int32_t regions = 1, uint32_t ticks = 60) {
    const std::string path = (dir_ / "s.textproto").string();
    std::ofstream(path) << "map { width: 24 height: 20 tile_size: 6 regions_x: " << regions << " regions_y: " << regions
                        << "\n  targets { x: 20 y: 15 } obstacles { x: 10 y: 8 w: 3 h: 2 } }\n"
                        << "swarm { uavs: 4 start_area { x: 0 y: 0 w: 3 h: 3 } }\nrun { ticks: " << ticks << " }\n"
                        << "policy {\n  plugin {\n" << plugin << "\n  }\n}\n";
    return path;
  }
  static std::string lib(const std::string& path = kRepulsive) { return "    library: \"" + path + "\"\n"; }
  fs::path dir_;
};

std::string error_of(const Result<ScenarioConfig>& r) { return r.ok() ? std::string("(loaded)") : r.error().message; }

}  // namespace

TEST_F(PluginScenario, AScenarioLoadsItsPluginAndFindPolicyFindsTheEntry) {
  auto s = load_scenario(write(lib() + "    name: \"repulsive_coverage\"\n    config { key: \"mark\" number: 4 }"));
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(s->policy, "repulsive_coverage");
  ASSERT_TRUE(s->plugin.has_value());
  EXPECT_EQ(s->plugin->library, fs::canonical(kRepulsive).string());
  EXPECT_EQ(s->plugin->sha256, sha256_file_hex(kRepulsive).value());
  EXPECT_EQ(s->plugin->pinned_by, "");
  const PolicyEntry* e = find_policy("repulsive_coverage");
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(&policy_entry(s.value()), e);
  const PolicyTraits t = policy_traits(s.value());
  EXPECT_EQ(t.layers, std::vector<std::string>{"repulsion"});
  ASSERT_EQ(t.layer_ranges.size(), 1U);
  EXPECT_EQ(t.layer_ranges[0].hi, 1000.0F);
}

TEST_F(PluginScenario, TheSimulatorRunsThePluginAndARegionSplitChangesNothing) {
  auto whole = load_scenario(write(lib() + "    name: \"repulsive_coverage\"", 1));
  ASSERT_TRUE(whole.ok()) << whole.error().message;
  auto split = load_scenario(write(lib() + "    name: \"repulsive_coverage\"", 2));
  ASSERT_TRUE(split.ok()) << split.error().message;
  Simulator a(whole.value());
  Simulator b(split.value());
  a.run();
  b.run();
  int differing = 0;
  float total = 0;
  for (int32_t y = 0; y < 20; ++y) {
    for (int32_t x = 0; x < 24; ++x) {
      differing += a.field_value(0, {x, y}) != b.field_value(0, {x, y}) ? 1 : 0;
      total += a.field_value(0, {x, y});
    }
  }
  EXPECT_EQ(differing, 0);
  EXPECT_GT(total, 0.0F);
  EXPECT_GT(a.recorder().coverage().covered_cells(), 40U);  // the swarm spread out of its 3 x 3 start
  EXPECT_EQ(a.recorder().coverage().covered_cells(), b.recorder().coverage().covered_cells());
}

TEST_F(PluginScenario, ThePluginsConfigErrorsNameTheFileTheLineAndTheParameter) {
  const std::string path = write(lib() +
                                 "    name: \"repulsive_coverage\"\n"
                                 "    config { key: \"evaporation\" number: 2 }\n"    // line 9
                                 "    config { key: \"when_blocked\" number: 1 }\n"   // line 10
                                 "    config { key: \"evaporatoin\" number: 0.1 }");  // line 11
  const std::string e = error_of(load_scenario(path));
  EXPECT_NE(e.find(path + ":9:5: field 'policy.plugin.config[0]': (key \"evaporation\"): must be in [0, 0.999] (got 2)"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find(path + ":10:5: field 'policy.plugin.config[1]': (key \"when_blocked\"): is a number; the plugin "
                          "reads a text (text: ...)"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find(path + ":11:5: field 'policy.plugin.config[2]': key \"evaporatoin\" is not a parameter of the "
                          "policy repulsive_coverage (it reads: mark, sensor_radius, evaporation, diffusion, max, "
                          "when_blocked, fail_at_tick)"),
            std::string::npos)
      << e;
  // A duplicate key or a parameter without a value is refused before the plugin reads anything.
  const std::string dup = error_of(load_scenario(write(lib() +
                                                       "    name: \"repulsive_coverage\"\n"
                                                       "    config { key: \"mark\" number: 1 }\n"
                                                       "    config { key: \"mark\" number: 2 }\n"
                                                       "    config { key: \"max\" }")));
  EXPECT_NE(dup.find(":10:5: field 'policy.plugin.config[1]': (key \"mark\"): same key as config[0]"), std::string::npos)
      << dup;
  EXPECT_NE(dup.find(":11:5: field 'policy.plugin.config[2]': (key \"max\"): has no value; give number:, text: or flag:"),
            std::string::npos)
      << dup;
}

TEST_F(PluginScenario, ALibraryNotFoundNamesEveryPathTriedAndTheSearchPathIsUsed) {
  setenv(kPluginPathEnv, "/nonexistent/a:/nonexistent/b", 1);
  const std::string e = error_of(load_scenario(write("    library: \"libnope.so\"\n    name: \"nope\"")));
  EXPECT_NE(e.find(":7:5: field 'policy.plugin.library': library libnope.so not found (tried " + dir_.string() +
                   "/libnope.so, /nonexistent/a/libnope.so, /nonexistent/b/libnope.so"),
            std::string::npos)
      << e;
  setenv(kPluginPathEnv, ("/nonexistent/a:" + kDir).c_str(), 1);
  auto found = load_scenario(write("    library: \"libpheromesh_test_plugin_repulsive.so\"\n    name: \"repulsive_coverage\""));
  ASSERT_TRUE(found.ok()) << found.error().message;
  EXPECT_EQ(found->plugin->library, fs::canonical(kRepulsive).string());
  // Relative to the scenario's folder first (a link to the same file is the same library).
  unsetenv(kPluginPathEnv);
  fs::create_directories(dir_ / "build");
  fs::create_symlink(kRepulsive, dir_ / "build" / "librep.so");
  auto beside = load_scenario(write("    library: \"build/librep.so\"\n    name: \"repulsive_coverage\""));
  ASSERT_TRUE(beside.ok()) << beside.error().message;
  EXPECT_EQ(beside->plugin->library, fs::canonical(kRepulsive).string());
}

TEST_F(PluginScenario, ALibraryThatIsNoPluginOrOfAnotherAbiOrABuiltInsNameIsRefused) {
  const std::string no_symbol = error_of(
      load_scenario(write(lib(kDir + "/libpheromesh_test_plugin_no_symbol.so") + "    name: \"x\"")));
  EXPECT_NE(no_symbol.find("is not a pheromesh policy plugin: it exports no symbol pheromesh_policy_plugin_abi"),
            std::string::npos)
      << no_symbol;
  const std::string abi = error_of(
      load_scenario(write(lib(kDir + "/libpheromesh_test_plugin_other_abi.so") + "    name: \"x\"")));
  EXPECT_NE(abi.find("was built for plugin ABI version " + std::to_string(kPolicyPluginAbi + 998) +
                     ", this pheromesh has version " + std::to_string(kPolicyPluginAbi)),
            std::string::npos)
      << abi;
  const std::string builtin = error_of(
      load_scenario(write(lib(kDir + "/libpheromesh_test_plugin_builtin_name.so") + "    name: \"liu\"")));
  EXPECT_NE(builtin.find("exports the policy 'liu', which is the name of a built-in policy"), std::string::npos)
      << builtin;
  const std::string wrong_name = error_of(load_scenario(write(lib() + "    name: \"coverage\"")));
  EXPECT_NE(wrong_name.find("exports the policy 'repulsive_coverage', not 'coverage'"), std::string::npos) << wrong_name;
  const std::string not_a_library = error_of(load_scenario(write(lib(std::string(PHEROMESH_SOURCE_DIR) +
                                                                    "/README.md") + "    name: \"x\"")));
  EXPECT_NE(not_a_library.find("cannot load the plugin library " + std::string(PHEROMESH_SOURCE_DIR) + "/README.md: "),
            std::string::npos)
      << not_a_library;
}

TEST_F(PluginScenario, AnotherBuildThanThePinnedOneIsRefusedWithTheHostNamed) {
  const std::string sha = sha256_file_hex(kRepulsive).value();
  const std::string other(64, 'a');
  auto pinned = load_scenario(write(lib() + "    name: \"repulsive_coverage\"\n    sha256: \"" + sha + "\""));
  ASSERT_TRUE(pinned.ok()) << pinned.error().message;
  EXPECT_EQ(pinned->plugin->pinned_by, "the scenario");
  const std::string e = error_of(
      load_scenario(write(lib() + "    name: \"repulsive_coverage\"\n    sha256: \"" + other + "\"")));
  EXPECT_NE(e.find(":9:5: field 'policy.plugin.sha256': host " + host_name() + ": the plugin library " +
                   fs::canonical(kRepulsive).string() + " has SHA-256 " + sha + ", but the scenario pins " + other),
            std::string::npos)
      << e;
  setenv(kPluginPinEnv, other.c_str(), 1);
  const std::string env = error_of(load_scenario(write(lib() + "    name: \"repulsive_coverage\"")));
  EXPECT_NE(env.find("host " + host_name() + ": the plugin library"), std::string::npos) << env;
  EXPECT_NE(env.find("but $PHEROMESH_PLUGIN_SHA256 pins " + other), std::string::npos) << env;
  setenv(kPluginPinEnv, sha.c_str(), 1);
  auto by_env = load_scenario(write(lib() + "    name: \"repulsive_coverage\""));
  ASSERT_TRUE(by_env.ok()) << by_env.error().message;
  EXPECT_EQ(by_env->plugin->pinned_by, "$PHEROMESH_PLUGIN_SHA256");
  const std::string malformed =
      error_of(load_scenario(write(lib() + "    name: \"repulsive_coverage\"\n    sha256: \"abc\"")));
  EXPECT_NE(malformed.find("field 'policy.plugin.sha256': must be 64 hex digits"), std::string::npos) << malformed;
}

TEST_F(PluginScenario, TextWithoutAFileLoadsNoPlugin) {
  std::ifstream in(write(lib() + "    name: \"repulsive_coverage\""));
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string e = error_of(parse_scenario(text, "RunScenario"));
  EXPECT_NE(e.find("RunScenario:6:3: field 'policy.plugin': a policy plugin is loaded from a scenario file only"),
            std::string::npos)
      << e;
}

TEST_F(PluginScenario, AnOverriddenScenarioNamesTheLibraryByItsFullPathForTheProcesses) {
  fs::create_directories(dir_ / "build");
  fs::create_symlink(kRepulsive, dir_ / "build" / "librep.so");
  auto s = load_scenario(write("    library: \"build/librep.so\"\n    name: \"repulsive_coverage\""),
                         ScenarioOverrides{{"swarm.uavs", "3", "--uavs 3"}});
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_NE(s->source_text.find("library: \"" + fs::canonical(kRepulsive).string() + "\""), std::string::npos)
      << s->source_text;
  // The text parses again from another folder (OUT/scenario.textproto).
  fs::create_directories(dir_ / "out");
  std::ofstream(dir_ / "out" / "scenario.textproto") << s->source_text;
  auto again = load_scenario((dir_ / "out" / "scenario.textproto").string());
  ASSERT_TRUE(again.ok()) << again.error().message;
  EXPECT_EQ(again->uavs, 3U);
}

TEST_F(PluginScenario, AnExceptionFromThePluginsStepReachesTheCallerWithItsMessage) {
  auto s = load_scenario(write(lib() + "    name: \"repulsive_coverage\"\n    config { key: \"fail_at_tick\" number: 7 }"));
  ASSERT_TRUE(s.ok()) << s.error().message;
  Simulator sim(s.value());
  try {
    sim.run();
    FAIL() << "the plugin's exception did not reach the caller";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("was told to fail at tick 7"), std::string::npos) << e.what();
  }
}

// --set of a plugin parameter (field_override.hpp): by its key, whatever line
// it is on; by its position, refused with the key it would have hit.
namespace {
std::vector<float> plugin_repulsion_field(const ScenarioConfig& s) {
  Simulator sim(s);
  sim.run();
  std::vector<float> v;
  for (int32_t y = 0; y < 20; ++y) {
    for (int32_t x = 0; x < 24; ++x) v.push_back(sim.field_value(0, {x, y}));
  }
  return v;
}
}  // namespace

TEST_F(PluginScenario, AParameterSetByItsKeyIsTheSameParameterWhateverLineItIsOn) {
  const std::string mark = "    config { key: \"mark\" number: 4 }\n";
  const std::string evaporation = "    config { key: \"evaporation\" number: 0.01 }\n";
  const ScenarioOverrides set = {{"policy.plugin.param.evaporation", "0.2", "--set"}};
  auto first = load_scenario(write(lib() + "    name: \"repulsive_coverage\"\n" + evaporation + mark), set);
  ASSERT_TRUE(first.ok()) << first.error().message;
  auto second = load_scenario(write(lib() + "    name: \"repulsive_coverage\"\n" + mark + evaporation), set);
  ASSERT_TRUE(second.ok()) << second.error().message;
  auto unset = load_scenario(write(lib() + "    name: \"repulsive_coverage\"\n" + mark + evaporation));
  ASSERT_TRUE(unset.ok()) << unset.error().message;
  EXPECT_NE(first->source_text.find("number: 0.2"), std::string::npos) << first->source_text;
  EXPECT_EQ(plugin_repulsion_field(first.value()), plugin_repulsion_field(second.value()));
  EXPECT_NE(plugin_repulsion_field(first.value()), plugin_repulsion_field(unset.value()));  // the guard: the set changes the run
}

TEST_F(PluginScenario, AParameterTheFileDoesNotGiveIsAddedAndCheckedByThePlugin) {
  const std::string file = write(lib() + "    name: \"repulsive_coverage\"\n    config { key: \"mark\" number: 4 }");
  auto added = load_scenario(file, {{"policy.plugin.param.evaporation", "0.2", "--set"}});
  ASSERT_TRUE(added.ok()) << added.error().message;
  EXPECT_NE(added->source_text.find("key: \"evaporation\""), std::string::npos) << added->source_text;
  auto out_of_range = load_scenario(file, {{"policy.plugin.param.evaporation", "2", "--set"}});
  EXPECT_NE(error_of(out_of_range).find("(key \"evaporation\"): must be in [0, 0.999] (got 2)"), std::string::npos)
      << error_of(out_of_range);
  EXPECT_NE(error_of(out_of_range).find("--set"), std::string::npos) << error_of(out_of_range);
  auto unknown = load_scenario(file, {{"policy.plugin.param.evaporatoin", "0.2", "--set"}});
  EXPECT_NE(error_of(unknown).find("key \"evaporatoin\" is not a parameter of the policy repulsive_coverage"),
            std::string::npos)
      << error_of(unknown);
  auto wrong_kind = load_scenario(file, {{"policy.plugin.param.mark", "lots", "--set"}});
  EXPECT_NE(error_of(wrong_kind).find("policy.plugin.param.mark: 'lots' is not a number"), std::string::npos)
      << error_of(wrong_kind);
}

TEST_F(PluginScenario, AParameterSetByItsPositionIsRefusedNamingItsKey) {
  const std::string file = write(lib() + "    name: \"repulsive_coverage\"\n    config { key: \"mark\" number: 4 }\n" +
                                 "    config { key: \"evaporation\" number: 0.01 }");
  auto r = load_scenario(file, {{"policy.plugin.config[1].number", "0.2", "--set"}});
  EXPECT_NE(error_of(r).find("'policy.plugin.config[1].number': a parameter is set by its key, "
                             "policy.plugin.param.evaporation=VALUE (policy.plugin.config[1] is \"evaporation\")"),
            std::string::npos)
      << error_of(r);
  auto beyond = load_scenario(file, {{"policy.plugin.config[5].key", "x", "--set"}});
  EXPECT_NE(error_of(beyond).find("policy.plugin.param.NAME=VALUE"), std::string::npos) << error_of(beyond);
  auto no_name = load_scenario(file, {{"policy.plugin.param", "3", "--set"}});
  EXPECT_NE(error_of(no_name).find("name one parameter by its key"), std::string::npos) << error_of(no_name);
}
