// Scenario limits (scenario_limits.hpp) and UTF-8 checks of scenario strings:
// each limit refuses one step past it with a message naming the limit and
// the variable that raises it, and accepts the scenario just under it.
#include "pheromesh/core/scenario_limits.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>

#include "unit_support.hpp"

namespace pheromesh::core {
namespace {

using test::source_path;

std::string scenario(int width, int height, int tile, int rx, int ry, int uavs, bool standby = false) {
  return "map { width: " + std::to_string(width) + " height: " + std::to_string(height) +
         " tile_size: " + std::to_string(tile) + " regions_x: " + std::to_string(rx) +
         " regions_y: " + std::to_string(ry) + " }\nswarm { uavs: " + std::to_string(uavs) + " }\nrun { standby: " +
         (standby ? "true" : "false") + " }\n";
}

void expect_refused(const Result<ScenarioConfig>& r, const std::string& where, const std::string& limit_text,
                    const char* env) {
  ASSERT_FALSE(r.ok()) << "accepted, expected a refusal at " << where;
  const std::string& m = r.error().message;
  EXPECT_NE(m.find(where), std::string::npos) << m;
  EXPECT_NE(m.find(limit_text), std::string::npos) << m;
  EXPECT_NE(m.find(std::string("$") + env + " to raise it"), std::string::npos) << m;
}

TEST(ScenarioLimits, MapOneCellOverTheLimitIsRefusedAndTheLimitItselfAccepted) {
  ScenarioLimits l;
  l.max_map_cells = 100 * 60;
  EXPECT_TRUE(parse_scenario(scenario(100, 60, 10, 1, 1, 2), "m.textproto", l).ok());
  expect_refused(parse_scenario(scenario(100, 61, 10, 1, 1, 2), "m.textproto", l), "m.textproto:1:7: field 'map.width'",
                 "100 x 61 = 6100 cells, more than the limit of 6000 cells", kMaxMapCellsEnv);
}

TEST(ScenarioLimits, TheDefaultRefusesTheMapThatUsedToAbortAndAcceptsTwoThousandSquare) {
  const ScenarioLimits l;
  expect_refused(parse_scenario(scenario(4096, 4096, 32, 1, 1, 2), "big", l), "field 'map.width'",
                 "4096 x 4096 = 16777216 cells", kMaxMapCellsEnv);
  EXPECT_TRUE(parse_scenario(scenario(2048, 2048, 32, 1, 1, 2), "big", l).ok());
}

// Issue 44 D5: 5000 UAVs at most; above 1024 (MAX_OCCUPANCY: the lockstep
// clock lists the UAVs per occupied tile) only on a map of at most 1024 tiles.
TEST(ScenarioLimits, MoreThan1024UavsNeedAMapOfAtMost1024TilesAnd5000IsTheMost) {
  ScenarioLimits l;
  l.max_processes = 10000;
  l.max_swarm_mib = 1 << 20;
  EXPECT_TRUE(parse_scenario(scenario(100, 100, 10, 4, 4, 2000), "s", l).ok()) << "100 tiles";
  EXPECT_TRUE(parse_scenario(scenario(320, 320, 10, 4, 4, 2000), "s", l).ok()) << "1024 tiles";
  const auto over = parse_scenario(scenario(330, 330, 10, 4, 4, 2000), "s", l);
  ASSERT_FALSE(over.ok());
  EXPECT_NE(over.error().message.find("field 'swarm.uavs': more than 1024 UAVs (2000) need a map of at most 1024 "
                                      "tiles, this one has 1089"),
            std::string::npos)
      << over.error().message;
  EXPECT_TRUE(parse_scenario(scenario(330, 330, 10, 4, 4, 1024), "s", l).ok()) << "1024 UAVs fit any map";
  EXPECT_TRUE(parse_scenario(scenario(100, 100, 10, 4, 4, 5000), "s", l).ok());
  const auto most = parse_scenario(scenario(100, 100, 10, 4, 4, 5001), "s", l);
  ASSERT_FALSE(most.ok());
  EXPECT_NE(most.error().message.find("must be between 1 and 5000 (got 5001)"), std::string::npos)
      << most.error().message;
}

TEST(ScenarioLimits, RegionsOverTheLimitAreRefusedAtRegionsX) {
  ScenarioLimits l;
  l.max_regions = 12;
  EXPECT_TRUE(parse_scenario(scenario(40, 30, 10, 4, 3, 2), "r", l).ok());
  expect_refused(parse_scenario(scenario(50, 30, 10, 5, 3, 2), "r", l), "r:1:42: field 'map.regions_x'",
                 "5 x 3 = 15 place agents, more than the limit of 12", kMaxRegionsEnv);
}

TEST(ScenarioLimits, ProcessesCountUavsPlaceAgentsStandbysAndTheGround) {
  ScenarioLimits l;
  l.max_processes = 20;
  // 15 UAVs + 4 place agents + 1 ground = 20.
  EXPECT_TRUE(parse_scenario(scenario(20, 20, 5, 2, 2, 15), "p", l).ok());
  expect_refused(parse_scenario(scenario(20, 20, 5, 2, 2, 16), "p", l), "p:2:9: field 'swarm.uavs'",
                 "needs 21 processes (16 UAVs + 4 place agents + 1 ground station), more than the limit of 20",
                 kMaxProcessesEnv);
  expect_refused(parse_scenario(scenario(20, 20, 5, 2, 2, 12, true), "p", l), "field 'swarm.uavs'",
                 "needs 21 processes (12 UAVs + 4 place agents x 2 for standbys + 1 ground station)", kMaxProcessesEnv);
}

TEST(ScenarioLimits, ProcessMemoryNamesTheLargestProcessAndTheWayOut) {
  const auto cfg = parse_scenario(scenario(2048, 2048, 32, 1, 1, 2), "mem", ScenarioLimits{});
  ASSERT_TRUE(cfg.ok()) << cfg.error().message;
  const ScenarioCost c = estimate_cost(cfg.value());
  EXPECT_STREQ(c.largest_role(), "place agent");
  ScenarioLimits l;
  l.max_process_mib = static_cast<int64_t>(std::ceil(c.largest_mib())) - 1;  // just short of the estimate
  expect_refused(parse_scenario(scenario(2048, 2048, 32, 1, 1, 2), "mem", l), "field 'map.width'",
                 "the place agent would need about", kMaxProcessMibEnv);
  l.max_process_mib += 1;
  EXPECT_TRUE(parse_scenario(scenario(2048, 2048, 32, 1, 1, 2), "mem", l).ok());
  // More regions shrink the place agents below the ground station's share.
  const auto split = parse_scenario(scenario(2048, 2048, 32, 8, 8, 2), "mem", ScenarioLimits{});
  ASSERT_TRUE(split.ok()) << split.error().message;
  EXPECT_LT(estimate_cost(split.value()).place_mib, c.place_mib);
}

TEST(ScenarioLimits, SwarmMemoryAddsUpEveryProcessWithTheSharedLibrariesOnce) {
  const auto cfg = parse_scenario(scenario(200, 200, 10, 2, 2, 100), "s", ScenarioLimits{});
  ASSERT_TRUE(cfg.ok()) << cfg.error().message;
  const ScenarioCost c = estimate_cost(cfg.value());
  // 105 processes, each with the 16 MiB of libraries they share, which are
  // in memory once: 104 x 16 MiB less than the sum of their RSS.
  EXPECT_NEAR(c.swarm_mib, 100 * c.uav_mib + 4 * c.place_mib + c.ground_mib - 104 * 16.0, 1e-9);
  ScenarioLimits l;
  l.max_swarm_mib = static_cast<int64_t>(std::ceil(c.swarm_mib)) - 1;
  expect_refused(parse_scenario(scenario(200, 200, 10, 2, 2, 100), "s", l), "field 'swarm.uavs'",
                 "the swarm's 105 processes would need about", kMaxSwarmMibEnv);
  l.max_swarm_mib += 1;
  EXPECT_TRUE(parse_scenario(scenario(200, 200, 10, 2, 2, 100), "s", l).ok());
}

TEST(ScenarioLimits, TwoThousandUavsOnTheScaleMapFitTheDefaultSwarmMemory) {
  // The measured swarm (PSS: 2000 x 5.1 MiB + 16 x 22 + 21, about 10.6 GiB)
  // and the estimate: 2000 x (22 + 5 B x 10 000 cells) + 16 place agents +
  // the ground station, less 2016 x 16 MiB of shared libraries, about 12 GiB.
  ScenarioLimits l;
  l.max_processes = 2100;
  const auto cfg = parse_scenario(scenario(100, 100, 10, 4, 4, 2000), "s", l);
  ASSERT_TRUE(cfg.ok()) << cfg.error().message;
  const ScenarioCost c = estimate_cost(cfg.value());
  EXPECT_GT(c.swarm_mib, 10.6 * 1024) << "not below what was measured";
  EXPECT_LT(c.swarm_mib, 13.0 * 1024);
  EXPECT_LT(c.swarm_mib, static_cast<double>(ScenarioLimits{}.max_swarm_mib));
}

TEST(ScenarioLimits, EnvironmentVariablesRaiseTheLimitsAndBadValuesAreErrors) {
  const std::string text = scenario(3000, 3000, 32, 1, 1, 2);
  ::unsetenv(kMaxMapCellsEnv);
  EXPECT_FALSE(parse_scenario(text, "env").ok());
  ::setenv(kMaxMapCellsEnv, "9000000", 1);
  ::setenv(kMaxProcessMibEnv, "4096", 1);
  const auto raised = parse_scenario(text, "env");
  EXPECT_TRUE(raised.ok()) << raised.error().message;
  ::setenv(kMaxMapCellsEnv, "-5", 1);
  const auto bad = parse_scenario(text, "env");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("$PHEROMESH_MAX_MAP_CELLS = '-5': must be a positive integer"), std::string::npos)
      << bad.error().message;
  ::unsetenv(kMaxMapCellsEnv);
  ::unsetenv(kMaxProcessMibEnv);
}

TEST(ScenarioLimits, CheckLimitsSeesOverridesMadeAfterLoading) {
  ScenarioLimits l;
  l.max_processes = 10;
  auto cfg = parse_scenario(scenario(20, 20, 5, 2, 2, 5), "o", l);
  ASSERT_TRUE(cfg.ok()) << cfg.error().message;
  EXPECT_TRUE(check_limits(cfg.value(), l, "o --uavs 5").ok());
  cfg->uavs = 6;
  const auto r = check_limits(cfg.value(), l, "o --uavs 6");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("o --uavs 6: the swarm needs 11 processes"), std::string::npos) << r.error().message;
}

// --- UTF-8 ---------------------------------------------------------------------

TEST(ScenarioUtf8, ValidatorAcceptsUtf8AndRefusesEachKindOfMalformedSequence) {
  EXPECT_TRUE(valid_utf8(""));
  EXPECT_TRUE(valid_utf8("plain ascii"));
  EXPECT_TRUE(valid_utf8("caf\xC3\xA9 \xE2\x9C\x93 \xF0\x9F\x9A\x81 \xF4\x8F\xBF\xBF"));  // up to U+10FFFF
  std::size_t at = 99;
  for (const auto& [bad, offset] : {std::pair<std::string, std::size_t>{"caf\xE9", 3}, {"\x80", 0}, {"ok\xC0\xAF", 2},
                                    {"\xE0\x80\xAF", 0}, {"\xED\xA0\x80", 0}, {"\xF4\x90\x80\x80", 0},
                                    {"ab\xE2\x82", 2}, {"\xF8\x88\x80\x80\x80", 0}, {"\xFF", 0}}) {
    EXPECT_FALSE(valid_utf8(bad, &at)) << bad;
    EXPECT_EQ(at, offset) << bad;
  }
}

TEST(ScenarioUtf8, HostileNameAndFaultLineAreRefusedAtTheirLinesWithoutEchoingTheBytes) {
  const std::string path = source_path("tests/data/bad-utf8-name.textproto");
  const auto r = load_scenario(path);
  ASSERT_FALSE(r.ok());
  const std::string& m = r.error().message;
  EXPECT_NE(m.find("bad-utf8-name.textproto:3:1: field 'name': is not valid UTF-8 (byte 4 of 8)"), std::string::npos)
      << m;
  EXPECT_NE(m.find("bad-utf8-name.textproto:7:1: field 'fault[1]': is not valid UTF-8 (byte 13 of 14)"),
            std::string::npos)
      << m;
  EXPECT_TRUE(valid_utf8(m)) << "the message itself must be printable as UTF-8";
}

TEST(ScenarioUtf8, EscapedBytesInAPolicyStringAreRefusedToo) {
  // Text-format escapes make raw bytes as well: "\377" is the byte 0xFF.
  const auto r = parse_scenario("map { width: 20 height: 20 tile_size: 5 }\npolicy { duan { deposit_rule: \"x\\377\" } }\n",
                                "esc", ScenarioLimits{});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("esc:2:17: field 'policy.duan.deposit_rule': is not valid UTF-8 (byte 2 of 2)"),
            std::string::npos)
      << r.error().message;
}

TEST(ScenarioUtf8, AFileNameThatIsNotUtf8CannotStandInForAMissingName) {
  const auto bad = parse_scenario("map { width: 20 height: 20 tile_size: 5 }\n", "dir/sc\xE9nario.textproto", ScenarioLimits{});
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("field 'name': is not set, and the file name is not valid UTF-8"), std::string::npos)
      << bad.error().message;
  const auto named = parse_scenario("name: \"ok\"\nmap { width: 20 height: 20 tile_size: 5 }\n", "dir/sc\xE9nario.textproto",
                                    ScenarioLimits{});
  EXPECT_TRUE(named.ok());
}

}  // namespace
}  // namespace pheromesh::core
