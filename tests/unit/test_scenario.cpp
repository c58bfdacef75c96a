// Scenario loading and validation (common/core/src/scenario/scenario.cpp).
#include "pheromesh/core/scenario.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <utility>

#include "unit_support.hpp"

namespace pheromesh::core {
namespace {

using test::source_path;

Result<ScenarioConfig> load_fixture(const std::string& name) { return load_scenario(source_path("tests/data/" + name)); }

// The message names the file, the 1-based line and the field path.
void expect_error_at(const Result<ScenarioConfig>& r, const std::string& file, int line, const std::string& field) {
  ASSERT_FALSE(r.ok()) << "expected an error for " << file;
  const std::string& msg = r.error().message;
  EXPECT_NE(msg.find(file + ":" + std::to_string(line) + ":"), std::string::npos) << msg;
  EXPECT_NE(msg.find("field '" + field + "'"), std::string::npos) << msg;
}

void expect_valid_start_cells(const ScenarioConfig& s) {
  std::set<std::pair<int32_t, int32_t>> seen;
  for (uint32_t id = 0; id < s.uavs; ++id) {
    const Cell c = start_cell(s, id);
    EXPECT_TRUE(s.start_area.contains(c)) << "uav " << id;
    for (const Rect& o : s.obstacles) EXPECT_FALSE(o.contains(c)) << "uav " << id << " starts on an obstacle";
    EXPECT_TRUE(seen.insert({c.x, c.y}).second) << "uav " << id << " shares its start cell";
  }
}

// --- shipped scenarios --------------------------------------------------------

TEST(ScenarioShipped, Shao50x50LoadsWithTable1Parameters) {
  const auto r = load_scenario(source_path("scenarios/shao2020-50x50.textproto"));
  ASSERT_TRUE(r.ok()) << r.error().message;
  const ScenarioConfig& s = r.value();
  EXPECT_EQ(s.name, "shao2020-50x50");
  EXPECT_EQ(s.width, 50);
  EXPECT_EQ(s.height, 50);
  EXPECT_EQ(s.targets.size(), 5U);
  EXPECT_EQ(s.ticks, 3000U);
  EXPECT_EQ(s.aco.revisit_period, 500U);
  EXPECT_EQ(s.uavs, 10U);
  EXPECT_DOUBLE_EQ(s.aco.sensor_radius, 4.0);
  EXPECT_DOUBLE_EQ(s.aco.lambda_obstacle, -0.3);
  EXPECT_DOUBLE_EQ(s.layers.sigma_min, 0.1);
  EXPECT_EQ(s.source_path, source_path("scenarios/shao2020-50x50.textproto"));
  expect_valid_start_cells(s);
}

TEST(ScenarioShipped, Shao100x100LoadsWithTable1Parameters) {
  const auto r = load_scenario(source_path("scenarios/shao2020-100x100.textproto"));
  ASSERT_TRUE(r.ok()) << r.error().message;
  const ScenarioConfig& s = r.value();
  EXPECT_EQ(s.width, 100);
  EXPECT_EQ(s.targets.size(), 20U);
  EXPECT_EQ(s.ticks, 10000U);
  EXPECT_EQ(s.aco.revisit_period, 800U);
  EXPECT_EQ(s.geometry().region_count(), 16U);
  expect_valid_start_cells(s);
}

TEST(ScenarioShipped, SmallTestLoadsAndIsSmall) {
  const auto r = load_scenario(source_path("scenarios/small-test.textproto"));
  ASSERT_TRUE(r.ok()) << r.error().message;
  const ScenarioConfig& s = r.value();
  EXPECT_EQ(s.width, 30);
  EXPECT_EQ(s.tile_size, 6);
  EXPECT_EQ(s.uavs, 4U);
  EXPECT_EQ(s.targets.size(), 3U);
  EXPECT_EQ(s.obstacles.size(), 2U);
  EXPECT_EQ(s.aco.revisit_period, 60U);
  expect_valid_start_cells(s);
}

// --- errors name file, line and field ------------------------------------------

TEST(ScenarioErrors, TileSizeOutOfRangeNamesFileLineAndField) {
  const auto r = load_fixture("bad-tile-size.textproto");
  expect_error_at(r, "bad-tile-size.textproto", 5, "map.tile_size");
  EXPECT_NE(r.error().message.find("bad-tile-size.textproto:5:3: field 'map.tile_size': must be between 4 and 32"),
            std::string::npos)
      << r.error().message;
  EXPECT_NE(r.error().message.find("(got 40)"), std::string::npos) << r.error().message;
}

TEST(ScenarioErrors, ObstacleOutsideMapNamesElementIndexAndItsLine) {
  const auto r = load_fixture("bad-obstacle-outside-map.textproto");
  expect_error_at(r, "bad-obstacle-outside-map.textproto", 10, "map.obstacles[2].w");
  EXPECT_NE(r.error().message.find(":10:15:"), std::string::npos) << r.error().message;
}

TEST(ScenarioErrors, TargetOnObstacleNamesTargetAndObstacle) {
  const auto r = load_fixture("bad-target-on-obstacle.textproto");
  expect_error_at(r, "bad-target-on-obstacle.textproto", 9, "map.targets[1]");
  EXPECT_NE(r.error().message.find("map.obstacles[0]"), std::string::npos) << r.error().message;
}

TEST(ScenarioErrors, MissingWidthIsReportedAtTheMapBlock) {
  expect_error_at(load_fixture("bad-missing-width.textproto"), "bad-missing-width.textproto", 4, "map.width");
}

TEST(ScenarioErrors, AbsentFieldMadeInvalidByAnotherIsReportedAtEnclosingMessage) {
  const auto r = load_fixture("bad-sigma-order.textproto");
  expect_error_at(r, "bad-sigma-order.textproto", 6, "shao.layers.sigma0");
}

TEST(ScenarioErrors, CrowdedStartAreaIsRejected) {
  const auto r = load_fixture("bad-start-area-crowded.textproto");
  expect_error_at(r, "bad-start-area-crowded.textproto", 10, "swarm.start_area");
  EXPECT_NE(r.error().message.find("has 2 free"), std::string::npos) << r.error().message;
}

TEST(ScenarioErrors, UnknownFieldGivesFileLineAndColumn) {
  const auto r = load_fixture("bad-unknown-field.textproto");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("bad-unknown-field.textproto:5:"), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find("speed"), std::string::npos) << r.error().message;
}

TEST(ScenarioErrors, SyntaxErrorGivesFileLineAndColumn) {
  const auto r = load_fixture("bad-syntax.textproto");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("bad-syntax.textproto:4:"), std::string::npos) << r.error().message;
}

TEST(ScenarioErrors, AllSemanticErrorsAreReportedAtOnce) {
  const std::string file = "bad-many-errors.textproto";
  const auto r = load_fixture(file);
  expect_error_at(r, file, 6, "map.regions_x");
  expect_error_at(r, file, 7, "map.targets[0].x");
  expect_error_at(r, file, 9, "swarm.uavs");
  expect_error_at(r, file, 11, "run.ticks");
  expect_error_at(r, file, 12, "run.tick_rate_hz");
  expect_error_at(r, file, 16, "shao.aco.lambda_obstacle");
  // One line per error, in file order.
  const std::string& msg = r.error().message;
  EXPECT_EQ(std::count(msg.begin(), msg.end(), '\n'), 5) << msg;
  EXPECT_LT(msg.find(":6:"), msg.find(":16:")) << msg;
}

TEST(ScenarioErrors, UnreadableFileNamesPathAndReason) {
  const auto r = load_scenario("/nonexistent/dir/x.textproto");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "/nonexistent/dir/x.textproto: cannot read file: No such file or directory");
}

TEST(ScenarioErrors, MissingMapIsRequired) {
  const auto r = parse_scenario("name: \"x\"\n", "t.textproto");
  expect_error_at(r, "t.textproto", 1, "map");
}

TEST(ScenarioErrors, NanAndInfinityAreRejected) {
  const auto r = parse_scenario("map { width: 10 height: 10 }\nshao { layers { d0: nan q: inf } }\n", "t.textproto");
  expect_error_at(r, "t.textproto", 2, "shao.layers.d0");
  expect_error_at(r, "t.textproto", 2, "shao.layers.q");
}

TEST(ScenarioErrors, DuplicateTargetsAreRejected) {
  const auto r = parse_scenario("map { width: 10 height: 10\n targets { x: 1 y: 1 }\n targets { x: 1 y: 1 } }\n", "t.textproto");
  expect_error_at(r, "t.textproto", 3, "map.targets[1]");
}

TEST(ScenarioErrors, RectangleFieldsAreRequired) {
  const auto r = parse_scenario("map { width: 10 height: 10\n obstacles { x: 1 y: 1 w: 2 } }\n", "t.textproto");
  expect_error_at(r, "t.textproto", 2, "map.obstacles[0].h");
}

TEST(ScenarioErrors, ExplicitZeroIsNotTakenForAbsent) {
  const auto r = parse_scenario("map { width: 10 height: 10 }\nshao { layers { q: 0 } }\n", "t.textproto");
  expect_error_at(r, "t.textproto", 2, "shao.layers.q");
}

TEST(ScenarioErrors, AMalformedFaultLineNamesFileLineFieldAndTheEvent) {
  const auto r = load_fixture("bad-fault.textproto");
  expect_error_at(r, "bad-fault.textproto", 8, "fault[1]");
  expect_error_at(r, "bad-fault.textproto", 10, "fault[3]");
  const std::string& msg = r.error().message;
  EXPECT_NE(msg.find("bad-fault.textproto:8:1: field 'fault[1]': 'stop uav:2 for 3s': no time (@TIME)"),
            std::string::npos)
      << msg;
  EXPECT_NE(msg.find("'kill place:3 @4s': place-3 does not exist (the map has 1 region: place:0)"), std::string::npos)
      << msg;
  // The good lines are not reported.
  EXPECT_EQ(msg.find("fault[0]"), std::string::npos) << msg;
  EXPECT_EQ(msg.find("fault[2]"), std::string::npos) << msg;
}

TEST(ScenarioErrors, FaultLinesMustShareOneClock) {
  const auto r = parse_scenario("map { width: 10 height: 10 }\nfault: \"kill uav:0 @5t\"\nfault: \"kill uav:1 @2s\"\n",
                                "t.textproto");
  expect_error_at(r, "t.textproto", 3, "fault[1]");
  EXPECT_NE(r.error().message.find("mixes tick times"), std::string::npos) << r.error().message;
}

TEST(ScenarioFaults, FaultLinesBecomeOneScheduleSortedByTime) {
  const auto r = parse_scenario(
      "map { width: 20 height: 20 tile_size: 5 regions_x: 2 }\n"
      "fault: \"stop place:1 @10s for 5s\"\n"
      "fault: \"kill uav:3 @5s; loss 30% @2s for 20s\"\n",
      "t.textproto");
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->faults.events.size(), 3U);
  EXPECT_EQ(r->faults.events[0].action, FaultAction::Loss);
  EXPECT_EQ(r->faults.events[1].action, FaultAction::Kill);
  EXPECT_EQ(r->faults.events[2].action, FaultAction::Stop);
  EXPECT_EQ(r->faults.events[2].targets.front().process_name(), "place-1");
  EXPECT_TRUE(r->faults.has_network());
  // No fault lines: an empty schedule.
  const auto none = parse_scenario("map { width: 20 height: 20 }\n", "t.textproto");
  ASSERT_TRUE(none.ok());
  EXPECT_TRUE(none->faults.empty());
}

// --- defaults ----------------------------------------------------------------

TEST(ScenarioDefaults, AbsentFieldsTakeDefaultsFromHeaders) {
  const auto r = parse_scenario("map { width: 40 height: 20 }\n", "dir/minimal.textproto");
  ASSERT_TRUE(r.ok()) << r.error().message;
  const ScenarioConfig& s = r.value();
  const ScenarioConfig d;
  const ShaoLayerParams dl;
  const ShaoAcoParams da;
  EXPECT_EQ(s.name, "minimal");
  EXPECT_EQ(s.source_path, "");
  EXPECT_EQ(s.tile_size, d.tile_size);
  EXPECT_EQ(s.regions_x, 1);
  EXPECT_EQ(s.regions_y, 1);
  EXPECT_EQ(s.uavs, d.uavs);
  EXPECT_EQ(s.start_area, (Rect{0, 0, 40, 20}));
  EXPECT_EQ(s.ticks, 1000U);
  EXPECT_DOUBLE_EQ(s.tick_rate_hz, 10.0);
  EXPECT_EQ(s.seed, 1U);
  EXPECT_DOUBLE_EQ(s.layers.e_tau, dl.e_tau);
  EXPECT_DOUBLE_EQ(s.layers.sigma0, dl.sigma0);
  EXPECT_DOUBLE_EQ(s.layers.q, dl.q);
  EXPECT_DOUBLE_EQ(s.aco.lambda_obstacle, da.lambda_obstacle);
  EXPECT_DOUBLE_EQ(s.aco.random_fraction, da.random_fraction);
  EXPECT_EQ(s.aco.revisit_period, da.revisit_period);
  EXPECT_TRUE(s.obstacles.empty());
  EXPECT_TRUE(s.targets.empty());
}

TEST(ScenarioDefaults, ExplicitValuesOverrideDefaults) {
  const auto r = parse_scenario(
      "name: \"n\" map { width: 40 height: 20 tile_size: 4 regions_x: 3 }\n"
      "run { seed: 42 ticks: 7 tick_rate_hz: 0.5 }\nshao { aco { revisit_period: 9 lambda_obstacle: 0 } }\n",
      "t.textproto");
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->name, "n");
  EXPECT_EQ(r->tile_size, 4);
  EXPECT_EQ(r->regions_x, 3);
  EXPECT_EQ(r->seed, 42U);
  EXPECT_EQ(r->ticks, 7U);
  EXPECT_DOUBLE_EQ(r->tick_rate_hz, 0.5);
  EXPECT_EQ(r->aco.revisit_period, 9U);
  EXPECT_DOUBLE_EQ(r->aco.lambda_obstacle, 0.0);
}

// --- start cells ---------------------------------------------------------------

TEST(ScenarioStartCell, DistinctForAllUavsAndNeverOnObstacles) {
  const auto r = parse_scenario(
      "map { width: 20 height: 20\n"
      " obstacles { x: 0 y: 0 w: 3 h: 3 }\n"
      " obstacles { x: 5 y: 1 w: 2 h: 6 }\n"
      " obstacles { x: 2 y: 4 w: 4 h: 1 } }\n"
      "swarm { uavs: 30 start_area { x: 0 y: 0 w: 8 h: 8 } }\n",
      "t.textproto");
  ASSERT_TRUE(r.ok()) << r.error().message;
  expect_valid_start_cells(r.value());
}

TEST(ScenarioStartCell, FillsEveryFreeCellWhenUavsEqualFreeCells) {
  const auto r = parse_scenario(
      "map { width: 10 height: 10 obstacles { x: 1 y: 0 w: 2 h: 1 } }\n"
      "swarm { uavs: 4 start_area { x: 0 y: 0 w: 3 h: 2 } }\n",
      "t.textproto");
  ASSERT_TRUE(r.ok()) << r.error().message;
  std::set<std::pair<int32_t, int32_t>> cells;
  for (uint32_t id = 0; id < 4; ++id) cells.insert({start_cell(r.value(), id).x, start_cell(r.value(), id).y});
  EXPECT_EQ(cells, (std::set<std::pair<int32_t, int32_t>>{{0, 0}, {0, 1}, {1, 1}, {2, 1}}));
}

TEST(ScenarioStartCell, IsDeterministicAndWrapsForLargeIds) {
  const auto r = load_scenario(source_path("scenarios/small-test.textproto"));
  ASSERT_TRUE(r.ok()) << r.error().message;
  const ScenarioConfig& s = r.value();
  EXPECT_EQ(start_cell(s, 2), start_cell(s, 2));
  for (uint32_t id = 0; id < 100; ++id) EXPECT_TRUE(s.start_area.contains(start_cell(s, id + 4'000'000'000U)));
}

}  // namespace
}  // namespace pheromesh::core
