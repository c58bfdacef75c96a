// How `pheromesh run|sim|validate SCENARIO` finds a scenario
// (common/cliutil/include/pheromesh/cliutil/scenario_paths.hpp): a file as given, else a shipped scenario's name,
// in the installed folder beside the program, then (build tree only) in the
// source tree.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "pheromesh/cliutil/scenario_paths.hpp"

namespace pheromesh::cli {
namespace {

namespace fs = std::filesystem;

// A fresh folder with an installed prefix and a source tree, removed at the end.
class ScenarioPaths : public testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(installed_);
    fs::create_directories(source_);
    fs::create_directories(root_ / "prefix/bin");
    write(installed_ / "small-test.textproto", "installed");
    write(installed_ / "shao2020-50x50.textproto", "installed");
    write(source_ / "small-test.textproto", "source");
    write(source_ / "only-in-source.textproto", "source");
    write(source_ / "README.md", "not a scenario");
  }
  void TearDown() override {
    fs::current_path(cwd_);
    fs::remove_all(root_);
  }
  static void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }
  static std::string read(const std::string& p) {
    std::ifstream in(p);
    std::string s;
    std::getline(in, s);
    return s;
  }
  [[nodiscard]] std::vector<fs::path> dirs() const { return {installed_, source_}; }

  fs::path cwd_ = fs::current_path();
  fs::path root_ = fs::temp_directory_path() / ("phm-scenario-paths-" + std::to_string(std::random_device{}()));
  fs::path installed_ = root_ / "prefix/share/pheromesh/scenarios";
  fs::path source_ = root_ / "src/scenarios";
};

TEST_F(ScenarioPaths, AShippedNameResolvesWithOrWithoutItsExtension) {
  for (const char* arg : {"shao2020-50x50", "shao2020-50x50.textproto"}) {
    const auto r = resolve_scenario(arg, dirs());
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(fs::path(r.value()), installed_ / "shao2020-50x50.textproto") << arg;
  }
}

TEST_F(ScenarioPaths, TheInstalledFolderIsSearchedBeforeTheSourceTree) {
  const auto r = resolve_scenario("small-test", dirs());
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(read(r.value()), "installed");
  // A name only the second folder has is found there.
  const auto s = resolve_scenario("only-in-source", dirs());
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(read(s.value()), "source");
}

TEST_F(ScenarioPaths, AnExistingFileIsUsedAsGivenEvenWhenAShippedScenarioHasItsName) {
  fs::create_directories(root_ / "work");
  fs::current_path(root_ / "work");
  write("small-test.textproto", "mine");
  const auto r = resolve_scenario("small-test.textproto", dirs());
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r.value(), "small-test.textproto");  // as given: relative to the current directory
  EXPECT_EQ(read(r.value()), "mine");
  // Guard: without the local file the same argument is the shipped one.
  fs::remove("small-test.textproto");
  const auto s = resolve_scenario("small-test.textproto", dirs());
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(read(s.value()), "installed");
}

TEST_F(ScenarioPaths, AFolderNamedLikeAScenarioIsNotTakenForIt) {
  fs::create_directories(root_ / "work/small-test");
  fs::current_path(root_ / "work");
  const auto r = resolve_scenario("small-test", dirs());
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(fs::path(r.value()), installed_ / "small-test.textproto");
}

TEST_F(ScenarioPaths, AFolderGivenAsTheScenarioIsRefusedAsAFolderNotAsAMissingFile) {
  fs::create_directories(root_ / "work/runs");
  fs::current_path(root_ / "work");
  for (const std::string& arg : std::vector<std::string>{"runs", "runs/", (root_ / "work/runs").string()}) {
    const auto r = resolve_scenario(arg, dirs());
    ASSERT_FALSE(r.ok()) << arg;
    EXPECT_EQ(r.error().message.rfind("'" + arg + "' is a directory; give a scenario file (.textproto) or a shipped "
                                      "scenario's name; shipped scenarios (in ", 0),
              0U)
        << r.error().message;
    EXPECT_NE(r.error().message.find("small-test"), std::string::npos) << r.error().message;
  }
}

TEST_F(ScenarioPaths, AnUnknownNameIsRefusedListingTheShippedScenarios) {
  const auto r = resolve_scenario("small-tset", dirs());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("'small-tset' is neither a file nor a shipped scenario"), std::string::npos)
      << r.error().message;
  // Every scenario of both folders, once, sorted; nothing that is not a scenario.
  EXPECT_NE(r.error().message.find(": only-in-source, shao2020-50x50, small-test"), std::string::npos)
      << r.error().message;
  EXPECT_EQ(r.error().message.find("README"), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find("(in " + installed_.string() + ", " + source_.string() + "): "), std::string::npos)
      << r.error().message;
  // A folder searched but absent is not named among those holding scenarios.
  const auto s = resolve_scenario("small-tset", {root_ / "nowhere", source_});
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("(in " + source_.string() + "): only-in-source, small-test"), std::string::npos)
      << s.error().message;
}

TEST_F(ScenarioPaths, WithNoScenarioFolderTheErrorSaysWhereItLooked) {
  const auto r = resolve_scenario("small-test", {root_ / "nowhere"});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("no shipped scenarios found in " + (root_ / "nowhere").string()), std::string::npos)
      << r.error().message;
}

TEST_F(ScenarioPaths, AMissingPathIsNotReplacedByTheShippedFileOfThatNameButPointsToIt) {
  fs::current_path(root_);
  const auto r = resolve_scenario("scenarios/small-test.textproto", dirs());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message,
            "'scenarios/small-test.textproto': no such file (a shipped scenario has that name: give it without the "
            "folder, 'small-test')");
  const auto s = resolve_scenario("scenarios/nothing.textproto", dirs());
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message, "'scenarios/nothing.textproto': no such file");
}

TEST_F(ScenarioPaths, TheInstalledFolderIsFoundRelativeToTheProgramSoAMovedPrefixStillWorks) {
  const ScenarioSearch moved{root_ / "moved/bin", "../share/pheromesh/scenarios", "/build/bin", "/src/scenarios"};
  const auto d = scenario_dirs(moved);
  ASSERT_EQ(d.size(), 1U);
  EXPECT_EQ(d[0], root_ / "moved/share/pheromesh/scenarios");
}

TEST_F(ScenarioPaths, OnlyTheProgramInTheBuildTreeSearchesTheSourceTree) {
  const fs::path build_bin = root_ / "build/bin";
  fs::create_directories(build_bin);
  const auto in_build = scenario_dirs({build_bin, "../share/pheromesh/scenarios", build_bin, source_});
  ASSERT_EQ(in_build.size(), 2U);
  EXPECT_EQ(in_build[1], source_);
  // The same build's program once installed elsewhere: no source tree.
  const auto installed = scenario_dirs({root_ / "prefix/bin", "../share/pheromesh/scenarios", build_bin, source_});
  ASSERT_EQ(installed.size(), 1U);
  EXPECT_EQ(installed[0], installed_);
}

// This test program lives in the build tree's bin/, like `pheromesh`: with
// this build's configuration it finds the source tree's scenarios.
TEST(ScenarioPathsOfThisBuild, AProgramInTheBuildTreeFindsTheSourceTreesScenariosByName) {
  const auto r = resolve_scenario("small-test", default_scenario_dirs());
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_TRUE(fs::equivalent(r.value(), fs::path(PHEROMESH_SOURCE_DIR) / "scenarios/small-test.textproto"))
      << r.value();
  EXPECT_TRUE(fs::equivalent(shipped_scenario("shao2020-50x50.textproto"),
                             fs::path(PHEROMESH_SOURCE_DIR) / "scenarios/shao2020-50x50.textproto"));
}

}  // namespace
}  // namespace pheromesh::cli
