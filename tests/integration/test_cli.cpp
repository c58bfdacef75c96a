// Issue 28: a command line that teaches. Every test here stops before a DDS
// participant exists (a refusal, --help, --version, validate), so they take
// milliseconds and need no domain.
#include "harness.hpp"

namespace pheromesh::itest {
namespace {

const std::string kPrograms[] = {"pheromesh", "pheromesh-uav", "pheromesh-place", "pheromesh-ground"};

TEST(Cli, AnUnknownSubcommandOrFlagIsAnsweredWithTheNearestName) {
  const Output sub = run(kBin + "/pheromesh sime small-test");
  EXPECT_EQ(sub.exit_code, 2) << sub.text;
  EXPECT_NE(sub.text.find("pheromesh: unknown subcommand 'sime' — did you mean 'sim'?"), std::string::npos) << sub.text;
  const Output nested = run(kBin + "/pheromesh bench scal small-test");
  EXPECT_EQ(nested.exit_code, 2) << nested.text;
  EXPECT_NE(nested.text.find("pheromesh bench: unknown subcommand 'scal' — did you mean 'scale'?"), std::string::npos)
      << nested.text;
  const Output flag = run(kBin + "/pheromesh sim small-test --tick 50");
  EXPECT_EQ(flag.exit_code, 2) << flag.text;
  EXPECT_NE(flag.text.find("pheromesh sim: unknown flag '--tick' — did you mean --ticks?"), std::string::npos)
      << flag.text;
  const Output uav = run(kBin + "/pheromesh-uav --scenario small-test --id 0 --wait-for-place 3");
  EXPECT_EQ(uav.exit_code, 2) << uav.text;
  EXPECT_NE(uav.text.find("unknown flag '--wait-for-place' — did you mean --wait-for-places?"), std::string::npos)
      << uav.text;
  // One name per meaning: the place agent's --max-ticks and the ground
  // station's --expect-uavs are gone (--ticks, --uavs).
  const Output place = run(kBin + "/pheromesh-place --scenario small-test --region 0 --max-ticks 5");
  EXPECT_EQ(place.exit_code, 2) << place.text;
  EXPECT_NE(place.text.find("unknown flag '--max-ticks'"), std::string::npos) << place.text;
}

TEST(Cli, HelpAndVersionAnswerInEveryProgram) {
  const Output help = run(kBin + "/pheromesh help");
  EXPECT_EQ(help.exit_code, 0) << help.text;
  for (const char* sub :
       {"validate", "sim", "sweep", "experiment", "key", "run", "attach", "cell", "replay", "bench", "security"}) {
    EXPECT_NE(help.text.find("  " + std::string(sub)), std::string::npos) << sub << "\n" << help.text;
  }
  const Output sim = run(kBin + "/pheromesh help sim");
  EXPECT_EQ(sim.exit_code, 0) << sim.text;
  EXPECT_NE(sim.text.find("--ticks"), std::string::npos) << sim.text;
  EXPECT_NE(sim.text.find("Usage: pheromesh sim [OPTIONS] SCENARIO"), std::string::npos) << sim.text;
  const Output scale = run(kBin + "/pheromesh help bench scale");
  EXPECT_EQ(scale.exit_code, 0) << scale.text;
  EXPECT_NE(scale.text.find("--sizes"), std::string::npos) << scale.text;
  std::string first;
  for (const auto& p : kPrograms) {
    const Output v = run(kBin + "/" + p + " --version");
    EXPECT_EQ(v.exit_code, 0) << p << "\n" << v.text;
    ASSERT_EQ(v.text.rfind(p + " ", 0), 0U) << v.text;
    const std::string version = v.text.substr(p.size() + 1);
    if (first.empty()) first = version;
    EXPECT_EQ(version, first) << p;  // one version for the whole build
  }
  // The help of the UAV program says what it runs: the scenario's policy.
  const Output uav = run(kBin + "/pheromesh-uav --help");
  EXPECT_EQ(uav.text.find("running the Shao 2020 ACO search"), std::string::npos) << uav.text;
  EXPECT_NE(uav.text.find("the scenario's policy"), std::string::npos) << uav.text;
  const Output levels = run(kBin + "/pheromesh-ground --help");
  EXPECT_NE(levels.text.find("critical"), std::string::npos) << levels.text;
  // metrics.json carries the same version (the simulator's; the ground
  // station's comes from the same report code).
  const std::string out = out_dir("cli-version");
  const Output s = run(kBin + "/pheromesh sim small-test --ticks 5 --quiet --out " + out);
  ASSERT_EQ(s.exit_code, 0) << s.text;
  EXPECT_EQ(read_metrics(out)["version"].get<std::string>() + "\n", first);
}

TEST(Cli, AFolderGivenAsTheScenarioIsRefusedAsAFolderByEveryProgram) {
  const std::string dir = kSrc + "/scenarios";
  for (const std::string& cmd :
       {kBin + "/pheromesh validate " + dir, kBin + "/pheromesh sim " + dir,
        kBin + "/pheromesh-uav --id 0 --scenario " + dir, kBin + "/pheromesh-ground --scenario " + dir}) {
    const Output o = run(cmd);
    EXPECT_NE(o.exit_code, 0) << cmd << "\n" << o.text;
    EXPECT_NE(o.text.find("'" + dir + "' is a directory; give a scenario file (.textproto) or a shipped scenario's name"),
              std::string::npos)
        << cmd << "\n" << o.text;
    EXPECT_EQ(o.text.find("no such file"), std::string::npos) << cmd << "\n" << o.text;
  }
}

// The process programs take shipped names as `pheromesh` does, and their
// --uavs/--ticks/--seed/--rate are validated with the file, the error naming
// the flag (exit 2 before any DDS participant exists).
TEST(Cli, ProcessProgramsTakeShippedNamesAndRefuseFlagValuesTheFileCouldNotHold) {
  const std::pair<std::string, std::string> refused[] = {
      {"/pheromesh-uav --scenario small-test --id 0 --uavs 50",
       "--uavs 50: field 'swarm.uavs': the start area holds 16 UAVs"},
      {"/pheromesh-uav --scenario small-test --id 0 --uavs 0",
       "--uavs 0: field 'swarm.uavs': must be between 1 and 5000 (got 0)"},
      {"/pheromesh-place --scenario small-test --region 0 --ticks 0",
       "--ticks 0: field 'run.ticks': must be between 1 and 4294967295 (got 0)"},
      {"/pheromesh-ground --scenario small-test --rate 0", "--rate 0: field 'run.tick_rate_hz': must be in (0, 1000]"},
  };
  for (const auto& [cmd, message] : refused) {
    const Output o = run(kBin + cmd);
    EXPECT_EQ(o.exit_code, 2) << cmd << "\n" << o.text;
    EXPECT_NE(o.text.find(message), std::string::npos) << cmd << "\n" << o.text;
    EXPECT_EQ(o.text.find("File does not exist"), std::string::npos) << cmd << "\n" << o.text;
  }
  const Output typo = run(kBin + "/pheromesh-ground --scenario small-tset");
  EXPECT_NE(typo.exit_code, 0) << typo.text;
  EXPECT_NE(typo.text.find("'small-tset' is neither a file nor a shipped scenario; shipped scenarios (in "),
            std::string::npos)
      << typo.text;
}

TEST(Cli, ValidatePrintsThePolicyAndWarnsOnAShaoBlockBesideAnotherPolicy) {
  const Output shao = run(kBin + "/pheromesh validate small-test");
  ASSERT_EQ(shao.exit_code, 0) << shao.text;
  EXPECT_NE(shao.text.find("  policy      shao_search\n"), std::string::npos) << shao.text;
  EXPECT_NE(shao.text.find("  revisit     every "), std::string::npos) << shao.text;
  EXPECT_EQ(shao.text.find("warning"), std::string::npos) << shao.text;

  const std::string out = out_dir("validate-warning");
  const std::string file = out + "/shostak-with-shao.textproto";
  const std::string original = slurp(kSrc + "/scenarios/shostak-small.textproto");
  ASSERT_FALSE(original.empty());
  const auto lines_before = std::count(original.begin(), original.end(), '\n');
  std::ofstream(file) << original << "shao { aco { alpha: 2 } }\n";
  const Output v = run(kBin + "/pheromesh validate " + file);
  ASSERT_EQ(v.exit_code, 0) << v.text;
  EXPECT_NE(v.text.find("  policy      shostak\n"), std::string::npos) << v.text;
  EXPECT_EQ(v.text.find("revisit"), std::string::npos) << v.text;
  EXPECT_NE(v.text.find("  warning     " + file + ":" + std::to_string(lines_before + 1) +
                        ":1: block 'shao': the policy shostak does not read it (shao_search and shao_navigation "
                        "do); it changes nothing in this run"),
            std::string::npos)
      << v.text;
}

TEST(Cli, ADurationIsANumberWithAnOptionalUnitAndAnythingElseIsRefused) {
  const std::string out = out_dir("durations");
  for (const std::string& cmd : {kBin + "/pheromesh run small-test --duration 1h30m --out " + out,
                                 kBin + "/pheromesh bench soak small-test --duration 2d --out " + out}) {
    const Output o = run(cmd);
    EXPECT_NE(o.exit_code, 0) << cmd << "\n" << o.text;
    EXPECT_NE(o.text.find("a duration is a number >= 0 with an optional unit ms, s, m or h"), std::string::npos)
        << cmd << "\n" << o.text;
  }
  EXPECT_FALSE(fs::exists(out + "/logs"));
  // A unit becomes seconds (refused here before anything starts, as run.ticks
  // is given twice).
  const Output twice = run(kBin + "/pheromesh run small-test --duration 0.5m --set run.ticks=5 --out " + out);
  EXPECT_EQ(twice.exit_code, 2) << twice.text;
  EXPECT_NE(twice.text.find("--set run.ticks=5 and --duration 30 both set run.ticks; give one of them"),
            std::string::npos)
      << twice.text;
  const Output level = run(kBin + "/pheromesh --log-level loud validate small-test");
  EXPECT_NE(level.exit_code, 0) << level.text;
  EXPECT_NE(level.text.find("critical"), std::string::npos) << level.text;
}

// Issue 44 D1: bench scale measures, before its runs, the floor of a UAV tick
// per vendor - a view-sized sample down and an uplink-sized one up between
// two processes, and the CPU both spent - and sets each run's flying CPU per
// UAV tick against it. Two UAVs for ten ticks per vendor; domains 108-109.
TEST(Cli, BenchScaleMeasuresTheFloorOfAViewDownAndAnUplinkUpPerVendorBeforeItsRuns) {
  const std::string out = out_dir("bench-scale-floor");
  const Output r =
      run(kBin + "/pheromesh bench scale " + kSrc + "/scenarios/small-test.textproto --sizes 2 --ticks 10 " +
          "--rate 10 --dds cyclone,fastdds --floor-pings 40 --domain 108 --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.text;
  const json j = json::parse(slurp(out + "/scale.json"), nullptr, false);
  ASSERT_TRUE(j.is_object()) << slurp(out + "/scale.json");
  ASSERT_EQ(j["floors"].size(), 2U) << j["floors"].dump(2);
  for (std::size_t i = 0; i < 2; ++i) {
    const json& f = j["floors"][i];
    EXPECT_EQ(f["vendor"], i == 0 ? "cyclone" : "fastdds");
    EXPECT_EQ(f["error"], "") << f.dump();
    // 10700 B rounded down to whole 8-byte counts, 280 B exactly.
    EXPECT_EQ(f["down_bytes"], 10696);
    EXPECT_EQ(f["up_bytes"], 280);
    EXPECT_EQ(f["lost"], 0);
    ASSERT_TRUE(f["cpu_ms_per_round_trip"].is_number()) << f.dump();
    EXPECT_GT(f["cpu_ms_per_round_trip"].get<double>(), 0.0);
    EXPECT_LT(f["cpu_ms_per_round_trip"].get<double>(), 50.0) << "two processes, one sample each way";
    EXPECT_GT(f["rtt_ms_p50"].get<double>(), 0.0);
  }
  ASSERT_EQ(j["rows"].size(), 2U);
  for (const auto& row : j["rows"]) EXPECT_EQ(row["exit_code"], 0) << row.dump();
  const std::string md = slurp(out + "/scale.md");
  EXPECT_NE(md.find("## The floor: a view down and an uplink up between two processes"), std::string::npos) << md;
  EXPECT_NE(md.find("| cyclone | 10696, 280 |"), std::string::npos) << md;
}

// bench lockstep --repeat: every run flown N times, with a baseline the
// builds alternating and swapping which goes first every other round; the
// report gives per build the median and range of ticks/s and of the paired
// ratio. This build as its own baseline, 2 UAVs for 20 ticks, Cyclone;
// domains 110-111. A repeat of 0 is refused.
TEST(Cli, BenchLockstepRepeatAlternatesTheBuildsAndReportsMediansAndRanges) {
  const std::string out = out_dir("bench-lockstep-repeat");
  const std::string bin = kBin + "/pheromesh";
  const Output r = run(bin + " bench lockstep --swarms small-test:2 --dds cyclone --ticks 20 --pings 10 --repeat 2 " +
                       "--baseline " + bin + " --domain 110 --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.text;
  const json j = json::parse(slurp(out + "/lockstep.json"), nullptr, false);
  ASSERT_TRUE(j.is_object()) << slurp(out + "/lockstep.json");
  EXPECT_EQ(j["repeat"], 2);
  ASSERT_EQ(j["runs"].size(), 4U) << j["runs"].dump(2);
  // Round 1: this, baseline; round 2: baseline, this.
  const std::pair<const char*, int> order[] = {{"this", 1}, {"baseline", 1}, {"baseline", 2}, {"this", 2}};
  for (std::size_t i = 0; i < 4; ++i) {
    const json& run_i = j["runs"][i];
    EXPECT_EQ(run_i["build"], order[i].first) << i;
    EXPECT_EQ(run_i["round"], order[i].second) << i;
    EXPECT_EQ(run_i["equal_to_sim"], true) << run_i.dump();
    EXPECT_GT(run_i["ticks_per_s"].get<double>(), 0.0) << run_i.dump();
  }
  ASSERT_EQ(j["medians"].size(), 3U) << j["medians"].dump(2);
  const auto tps = [&](std::size_t i) { return j["runs"][i]["ticks_per_s"].get<double>(); };
  const json& mine = j["medians"][0];
  EXPECT_EQ(mine["build"], "this");
  EXPECT_EQ(mine["runs"], 2);
  // Nearest rank: the lower of two.
  EXPECT_DOUBLE_EQ(mine["median"].get<double>(), std::min(tps(0), tps(3)));
  EXPECT_DOUBLE_EQ(mine["max"].get<double>(), std::max(tps(0), tps(3)));
  EXPECT_EQ(j["medians"][1]["build"], "baseline");
  EXPECT_DOUBLE_EQ(j["medians"][1]["min"].get<double>(), std::min(tps(1), tps(2)));
  const json& ratio = j["medians"][2];
  EXPECT_EQ(ratio["build"], "this / baseline");
  EXPECT_EQ(ratio["runs"], 2);
  const double r1 = tps(0) / tps(1), r2 = tps(3) / tps(2);
  EXPECT_DOUBLE_EQ(ratio["min"].get<double>(), std::min(r1, r2));
  EXPECT_DOUBLE_EQ(ratio["max"].get<double>(), std::max(r1, r2));
  const std::string md = slurp(out + "/lockstep.md");
  EXPECT_NE(md.find("## Over 2 runs each: median (nearest rank) and range"), std::string::npos) << md;
  EXPECT_NE(md.find("| small-test:2 | cyclone | this / baseline | 2 |"), std::string::npos) << md;

  const Output zero = run(bin + " bench lockstep --repeat 0 --out " + out + "-zero");
  EXPECT_NE(zero.exit_code, 0) << zero.text;
  EXPECT_NE(zero.text.find("--repeat"), std::string::npos) << zero.text;
}

}  // namespace
}  // namespace pheromesh::itest
