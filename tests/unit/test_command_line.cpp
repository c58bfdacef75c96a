// What every program's command line shares (pheromesh/cliutil/command_line.hpp):
// the nearest name for a typo, the one duration syntax, and the answers of
// parse_command_line to `help`, --version and an unknown subcommand or flag.
#include <gtest/gtest.h>

#include <CLI/CLI.hpp>
#include <cctype>
#include <vector>

#include "pheromesh/cliutil/command_line.hpp"

namespace pheromesh::cli {
namespace {

TEST(EditDistance, CountsInsertionsDeletionsAndSubstitutions) {
  EXPECT_EQ(edit_distance("", ""), 0U);
  EXPECT_EQ(edit_distance("sim", "sim"), 0U);
  EXPECT_EQ(edit_distance("sime", "sim"), 1U);   // deletion
  EXPECT_EQ(edit_distance("sm", "sim"), 1U);     // insertion
  EXPECT_EQ(edit_distance("sun", "run"), 1U);    // substitution
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3U);
  EXPECT_EQ(edit_distance("abc", ""), 3U);
}

TEST(DidYouMean, ANearNameIsSuggestedAndAFarOneIsNot) {
  const std::vector<std::string> subcommands{"validate", "sim", "sweep", "experiment", "run", "bench", "key"};
  EXPECT_EQ(did_you_mean("sime", subcommands), "sim");
  EXPECT_EQ(did_you_mean("valdate", subcommands), "validate");
  EXPECT_EQ(did_you_mean("experimnet", subcommands), "experiment");
  EXPECT_EQ(did_you_mean("swep", subcommands), "sweep");
  EXPECT_FALSE(did_you_mean("launch", subcommands).has_value());
  EXPECT_FALSE(did_you_mean("", subcommands).has_value());
  // A name typed right is not "near" itself.
  EXPECT_FALSE(did_you_mean("sim", {"sim"}).has_value());
}

TEST(DidYouMean, FlagsAreComparedWithoutTheirDashesAndAClippedFlagFindsItsWholeName) {
  const std::vector<std::string> flags{"--ticks", "--uavs", "--seed", "--set", "--out", "--duration", "-h", "--help"};
  EXPECT_EQ(did_you_mean("--tick", flags), "--ticks");
  EXPECT_EQ(did_you_mean("--uav", flags), "--uavs");
  EXPECT_EQ(did_you_mean("--dur", flags), "--duration");
  EXPECT_EQ(did_you_mean("-ticks", flags), "--ticks");
  EXPECT_FALSE(did_you_mean("--frobnicate", flags).has_value());
}

TEST(Duration, APlainNumberIsSecondsAndUnitsScaleIt) {
  const auto secs = [](const char* t) {
    auto d = parse_duration_s(t, "--duration");
    EXPECT_TRUE(d.ok()) << t << ": " << d.error().message;
    return d.ok() ? d.value() : -1.0;
  };
  EXPECT_DOUBLE_EQ(secs("20"), 20.0);
  EXPECT_DOUBLE_EQ(secs("0.5"), 0.5);
  EXPECT_DOUBLE_EQ(secs("90s"), 90.0);
  EXPECT_DOUBLE_EQ(secs("2500ms"), 2.5);
  EXPECT_DOUBLE_EQ(secs("10m"), 600.0);
  EXPECT_DOUBLE_EQ(secs("10min"), 600.0);
  EXPECT_DOUBLE_EQ(secs("1.5h"), 5400.0);
  EXPECT_DOUBLE_EQ(secs("0"), 0.0);
}

TEST(Duration, WhatIsNotADurationIsRefusedNamingTheFlagAndTheSyntax) {
  for (const char* bad : {"", "-5", "1d", "ten", "5 s", "nan", "inf", "1h30m"}) {
    const auto d = parse_duration_s(bad, "--duration");
    ASSERT_FALSE(d.ok()) << bad;
    EXPECT_EQ(d.error().message, "--duration " + std::string(bad) +
                                     ": a duration is a number >= 0 with an optional unit ms, s, m or h, e.g. 20 "
                                     "(seconds), 90s, 10m, 1h, 2500ms");
  }
}

TEST(Duration, TheCli11CheckTurnsAUnitIntoSecondsForANumericOption) {
  CLI::App app{"test", "prog"};
  std::optional<double> seconds;
  app.add_option("--duration", seconds)->transform(duration_validator(true));
  const char* argv[] = {"prog", "--duration", "10m"};
  app.parse(3, argv);
  ASSERT_TRUE(seconds.has_value());
  EXPECT_DOUBLE_EQ(*seconds, 600.0);
  CLI::App refusing{"test", "prog"};
  std::string text;
  refusing.add_option("--every", text)->check(duration_validator(false));
  const char* bad[] = {"prog", "--every", "soon"};
  EXPECT_THROW(refusing.parse(3, bad), CLI::ValidationError);
}

// A program shaped like `pheromesh`: subcommands, one of them with its own.
class CommandLine : public testing::Test {
 protected:
  CommandLine() {
    add_version_flag(app_);
    app_.require_subcommand(1);
    sim_ = app_.add_subcommand("sim", "simulate");
    sim_->add_option("SCENARIO", scenario_)->required();
    sim_->add_option("--ticks", ticks_);
    auto* bench = app_.add_subcommand("bench", "benchmarks");
    bench->require_subcommand(1);
    bench->add_subcommand("scale", "sizes");
  }
  std::optional<int> parse(std::vector<const char*> args) {
    args.insert(args.begin(), "pheromesh");
    return parse_command_line(app_, static_cast<int>(args.size()), args.data());
  }
  CLI::App app_{"test", "pheromesh"};
  CLI::App* sim_ = nullptr;
  std::string scenario_;
  uint32_t ticks_ = 0;
};

TEST_F(CommandLine, AKnownCommandLineIsParsedAndRuns) {
  EXPECT_FALSE(parse({"sim", "small-test", "--ticks", "5"}).has_value());
  EXPECT_TRUE(sim_->parsed());
  EXPECT_EQ(ticks_, 5U);
}

TEST_F(CommandLine, VersionAndHelpAnswerWithExitZero) {
  testing::internal::CaptureStdout();
  EXPECT_EQ(parse({"--version"}), 0);
  const std::string version = testing::internal::GetCapturedStdout();
  EXPECT_EQ(version, version_line("pheromesh") + "\n");
  EXPECT_TRUE(version.starts_with("pheromesh ") && version.size() > 12 && std::isdigit(version[10])) << version;
  testing::internal::CaptureStdout();
  EXPECT_EQ(parse({"help"}), 0);
  EXPECT_NE(testing::internal::GetCapturedStdout().find("simulate"), std::string::npos);
  testing::internal::CaptureStdout();
  EXPECT_EQ(parse({"help", "bench", "scale"}), 0);
  EXPECT_NE(testing::internal::GetCapturedStdout().find("sizes"), std::string::npos);
}

TEST_F(CommandLine, AnUnknownSubcommandIsRefusedWithTheNearestName) {
  testing::internal::CaptureStderr();
  EXPECT_EQ(parse({"sime", "small-test"}), 2);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("pheromesh: unknown subcommand 'sime' — did you mean 'sim'?"), std::string::npos) << err;
  testing::internal::CaptureStderr();
  EXPECT_EQ(parse({"bench", "scal"}), 2);
  const std::string nested = testing::internal::GetCapturedStderr();
  EXPECT_NE(nested.find("pheromesh bench: unknown subcommand 'scal' — did you mean 'scale'?"), std::string::npos)
      << nested;
  testing::internal::CaptureStderr();
  EXPECT_EQ(parse({"help", "simm"}), 2);
  EXPECT_NE(testing::internal::GetCapturedStderr().find("did you mean 'sim'?"), std::string::npos);
}

// A bare `pheromesh` (or `pheromesh bench`) shows what there is to run,
// not CLI11's "A subcommand is required"; --help still answers 0.
TEST_F(CommandLine, NoSubcommandWhereOneIsNeededShowsTheHelpAndTheChoices) {
  testing::internal::CaptureStderr();
  EXPECT_EQ(parse({}), 2);
  const std::string bare = testing::internal::GetCapturedStderr();
  EXPECT_NE(bare.find("simulate"), std::string::npos) << bare;
  EXPECT_NE(bare.find("pheromesh: which subcommand? one of: sim, bench"), std::string::npos) << bare;
  EXPECT_NE(bare.find("`pheromesh help SUBCOMMAND` explains one"), std::string::npos) << bare;
  EXPECT_EQ(bare.find("A subcommand is required"), std::string::npos) << bare;
  testing::internal::CaptureStderr();
  EXPECT_EQ(parse({"bench"}), 2);
  const std::string nested = testing::internal::GetCapturedStderr();
  EXPECT_NE(nested.find("pheromesh bench: which subcommand? one of: scale"), std::string::npos) << nested;
  EXPECT_NE(nested.find("`pheromesh help bench SUBCOMMAND` explains one"), std::string::npos) << nested;
  testing::internal::CaptureStdout();
  EXPECT_EQ(parse({"--help"}), 0);
  EXPECT_NE(testing::internal::GetCapturedStdout().find("simulate"), std::string::npos);
}

TEST_F(CommandLine, AnUnknownFlagIsRefusedWithTheNearestFlagOfItsSubcommand) {
  testing::internal::CaptureStderr();
  EXPECT_EQ(parse({"sim", "small-test", "--tick", "50"}), 2);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("pheromesh sim: unknown flag '--tick' — did you mean --ticks?"), std::string::npos) << err;
  EXPECT_NE(err.find("`pheromesh sim --help` lists its flags"), std::string::npos) << err;
}

}  // namespace
}  // namespace pheromesh::cli
