// The tidy outputs of a run (docs/outputs.md): metrics.json against its JSON
// Schema, the per-tick series, tracks, the final field as CSV, and the
// console recording of `pheromesh sim --record`.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "json_schema_subset.hpp"
#include "pheromesh/console/recording.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"
#include "pheromesh/report/report.hpp"
#include "pheromesh/report/tidy.hpp"
#include "cli/sim_command.hpp"
#include "unit_support.hpp"

namespace pheromesh {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const std::string kSrc = PHEROMESH_SOURCE_DIR;

using test::slurp;

test::SchemaSubset metrics_schema() {
  return test::SchemaSubset(json::parse(slurp(kSrc + "/docs/schema/metrics.schema.json")));
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& e : v) s += e + "\n";
  return s;
}

core::ScenarioConfig small_test(uint32_t ticks) {
  auto s = core::load_scenario(kSrc + "/scenarios/small-test.textproto");
  EXPECT_TRUE(s.ok());
  core::ScenarioConfig c = s.value();
  c.ticks = ticks;
  return c;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string l; std::getline(ss, l);) out.push_back(l);
  return out;
}

TEST(MetricsSchema, TheSimulatorsMetricsConformAndLeaveOutWhatOnlyProcessesHave) {
  core::Simulator sim(small_test(40));
  sim.run();
  const json m = cli::sim_metrics(sim, 0.5);
  EXPECT_EQ(joined(metrics_schema().check(m)), "");
  EXPECT_EQ(m["runner"], "simulator");
  for (const char* key : {"dds", "discovery_s", "place_agents_alive", "ground_bytes_received_per_tick",
                          "samples_per_uav_tick", "uav_late_share", "place_tick_gaps", "lockstep"}) {
    EXPECT_FALSE(m.contains(key)) << key;
  }
  for (const auto& [id, u] : m["uav_status"].items()) {
    EXPECT_TRUE(u["role"].is_string()) << id;
    EXPECT_FALSE(u.contains("samples_received")) << id;
  }
  EXPECT_FALSE(m.dump().find("null") != std::string::npos) << "the simulator has no figure it could not measure";
}

TEST(MetricsSchema, AGroundStationsMetricsConformInRealtimeAndInLockstep) {
  core::Simulator sim(small_test(30));
  sim.run();
  report::RunInfo realtime{"cyclone", "realtime", report::Runner::Processes, 4, 1.25, {}, {}, uint64_t{123456}};
  const json rt = report::metrics_json(sim.recorder(), realtime);
  EXPECT_EQ(joined(metrics_schema().check(rt)), "");
  for (const char* key : {"dds", "discovery_s", "uav_late_share", "place_tick_gaps", "place_agents_alive"}) {
    EXPECT_TRUE(rt.contains(key)) << key;
  }
  report::RunInfo lockstep{"fastdds", "lockstep", report::Runner::Processes, 4, std::nullopt, {1.0, 2.0}, {0.5, 0.25}, {}};
  const json ls = report::metrics_json(sim.recorder(), lockstep);
  EXPECT_EQ(joined(metrics_schema().check(ls)), "");
  EXPECT_TRUE(ls.contains("lockstep"));
  for (const char* key : {"discovery_s", "uav_late_share", "uav_tick_gap_max_ms", "place_tick_gaps"}) {
    EXPECT_FALSE(ls.contains(key)) << key << ": realtime timekeeping does not apply to conducted ticks";
  }
}

TEST(MetricsSchema, TheCheckerRefusesAnUndocumentedKeyAWrongTypeAMissingKeyAndARoleCode) {
  core::Simulator sim(small_test(10));
  sim.run();
  json m = cli::sim_metrics(sim, 0.5);
  m["surprise"] = 1;
  m["coverage"] = "high";
  m.erase("policy");
  m["uav_status"]["0"]["role"] = 0;
  const auto errors = metrics_schema().check(m);
  EXPECT_EQ(errors.size(), 4U) << joined(errors);
  const std::string all = joined(errors);
  for (const char* path : {"/surprise", "/coverage", "'policy'", "/uav_status/0/role"}) {
    EXPECT_NE(all.find(path), std::string::npos) << path << " in\n" << all;
  }
  // A schema keyword the checker would skip is an error, not a pass.
  test::SchemaSubset unknown(json{{"type", "object"}, {"patternProperties", json::object()}});
  EXPECT_EQ(unknown.check(json::object()).size(), 1U);
}

// Two UAVs moving east along their start row and region 0's health, fed in
// tick order or UAV by UAV with the healths first (two DDS writers).
TEST(TickSeries, RowsDoNotDependOnTheOrderStatesAndHealthsArrive) {
  const core::ScenarioConfig s = small_test(8);
  const core::MapGeometry geo = s.geometry();  // the world keeps a pointer to it
  const core::World world(geo, s.obstacles, s.targets);
  const core::PolicyTraits traits = core::policy_traits(s);
  std::vector<core::UavStateMsg> states;
  for (uint32_t u = 0; u < 2; ++u) {
    const core::Cell start = core::uav_start(s, traits, u);
    for (uint32_t k = 0; k <= 8; ++k) {
      core::UavStateMsg m;
      m.uav = u;
      m.tick = k;
      m.x = std::min<double>(start.x + 0.5 * traits.max_step * k, s.width - 1);
      m.y = start.y;
      m.deposits_sent = 2 * k + u;
      states.push_back(m);
    }
  }
  std::vector<core::HealthMsg> healths;
  for (uint32_t k = 0; k <= 8; ++k) healths.push_back(core::HealthMsg{0, k, 0.0F, 3 * k, 3 * k, 0, 0, false});

  core::RunRecorder in_order(s, world);
  std::vector<core::UavStateMsg> by_tick = states;
  std::stable_sort(by_tick.begin(), by_tick.end(), [](const auto& a, const auto& b) { return a.tick < b.tick; });
  for (uint32_t k = 0; k <= 8; ++k) {
    for (const auto& m : by_tick) {
      if (m.tick == k) {
        EXPECT_TRUE(in_order.on_uav_state(m));
      }
    }
    in_order.on_health(healths[k]);
  }
  core::RunRecorder by_writer(s, world);
  for (auto it = healths.rbegin(); it != healths.rend(); ++it) by_writer.on_health(*it);  // newest first
  for (const auto& m : states) EXPECT_TRUE(by_writer.on_uav_state(m));

  const std::string a = report::series_csv(in_order.tick_series());
  EXPECT_EQ(a, report::series_csv(by_writer.tick_series()));
  const auto rows = in_order.tick_series();
  ASSERT_EQ(rows.size(), 9U);
  for (uint32_t k = 0; k <= 8; ++k) {
    EXPECT_EQ(rows[k].uavs_reporting, 2U);
    EXPECT_EQ(rows[k].deposits_sent, 4U * k + 1U) << k;  // 2k + (2k + 1)
    EXPECT_EQ(rows[k].deposits_applied, 3U * k) << k;
    if (k > 0) {
      EXPECT_GE(rows[k].covered_cells, rows[k - 1].covered_cells);
    }
  }
  EXPECT_GT(rows[8].covered_cells, rows[0].covered_cells) << "the UAVs moved over new cells";
  EXPECT_EQ(lines_of(a).front(), report::kSeriesHeader);
}

// The ground station sums the series as states arrive (RunRecorder keeps a
// UAV's latest tick and count, not every state): a later state of one tick
// replaces that tick's count and reports once; a tick skipped counts no UAV.
TEST(TickSeries, ALaterStateOfOneTickReplacesItsCountAndATickSkippedHasNoReport) {
  const core::ScenarioConfig s = small_test(8);
  const core::MapGeometry geo = s.geometry();
  const core::World world(geo, s.obstacles, s.targets);
  const core::Cell start = core::uav_start(s, core::policy_traits(s), 0);
  core::RunRecorder rec(s, world);
  const auto state = [&](uint32_t tick, uint64_t sent) {
    core::UavStateMsg m;
    m.tick = tick;
    m.x = start.x;
    m.y = start.y;
    m.deposits_sent = sent;
    return m;
  };
  for (const auto& m : {state(0, 0), state(1, 2), state(1, 3), state(3, 7)}) ASSERT_TRUE(rec.on_uav_state(m));
  const auto rows = rec.tick_series();
  ASSERT_EQ(rows.size(), 4U);
  const std::vector<uint64_t> sent{0, 3, 3, 7};
  const std::vector<uint32_t> reporting{1, 1, 0, 1};
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(rows[k].deposits_sent, sent[k]) << k;
    EXPECT_EQ(rows[k].uavs_reporting, reporting[k]) << k;
  }
}

TEST(TickSeries, TheSimulatorsLastRowHoldsTheTotalsOfMetricsJsonAndTheCoverageSeriesHasEachTickOnce) {
  core::Simulator sim(small_test(45));
  sim.run();
  const auto rows = sim.recorder().tick_series();
  ASSERT_EQ(rows.size(), 46U);
  const json m = cli::sim_metrics(sim, 1.0);
  EXPECT_EQ(rows.back().coverage, m["coverage"].get<double>());
  EXPECT_EQ(rows.back().targets_found, m["targets_found"].get<uint32_t>());
  EXPECT_EQ(rows.back().deposits_sent, m["deposits_sent"].get<uint64_t>());
  EXPECT_EQ(rows.back().deposits_applied, m["deposits_applied"].get<uint64_t>());
  EXPECT_EQ(rows.back().uavs_reporting, sim.scenario().uavs);
  std::vector<uint32_t> ticks;
  for (const auto& p : m["coverage_series"]) ticks.push_back(p[0].get<uint32_t>());
  EXPECT_EQ(ticks, (std::vector<uint32_t>{0, 10, 20, 30, 40, 45}));
  for (const auto& p : m["coverage_series"]) EXPECT_EQ(p[1].get<double>(), rows[p[0].get<uint32_t>()].coverage);
}

TEST(TidyFiles, NumbersReadBackExactlyAndNaNIsSpelledAsRAndPandasReadIt) {
  EXPECT_EQ(report::number_text(0.1), "0.1");
  EXPECT_EQ(report::number_text(0.1F), "0.1");
  EXPECT_EQ(std::stod(report::number_text(1.0 / 3.0)), 1.0 / 3.0);
  EXPECT_EQ(report::number_text(std::nan("")), "NaN");
  EXPECT_EQ(report::number_text(-INFINITY), "-Inf");
}

TEST(TidyFiles, SimWritesSeriesTracksAFieldCsvEqualToTheTextAndARecordingReplayReads) {
  const fs::path out = fs::temp_directory_path() / ("pheromesh-tidy-sim-" + std::to_string(::getpid()));
  fs::remove_all(out);
  cli::SimOptions o;
  o.out_dir = out.string();
  o.quiet = true;
  o.tracks = true;
  o.record = (out / "sim.phrec").string();
  const core::ScenarioConfig s = small_test(20);
  ASSERT_EQ(cli::simulate(s, {}, o), 0);

  EXPECT_EQ(lines_of(slurp(out / "series.csv")).size(), 22U);  // header + ticks 0..20
  const auto tracks = lines_of(slurp(out / "tracks.csv"));
  ASSERT_EQ(tracks.size(), 1U + 21U * s.uavs);
  EXPECT_EQ(tracks[0], report::kTracksHeader);
  EXPECT_EQ(tracks[1].rfind("0,0,", 0), 0U) << tracks[1];
  EXPECT_NE(tracks[1].find(",searcher"), std::string::npos) << tracks[1];

  // final_field.csv holds exactly the numbers of final_field.txt, in its order.
  std::vector<double> text_values;
  {
    std::stringstream txt(slurp(out / "final_field.txt"));
    for (std::string line; std::getline(txt, line);) {
      if (line.empty() || line[0] == '#' || line.rfind("layer ", 0) == 0) continue;
      std::stringstream row(line);
      for (double v; row >> v;) text_values.push_back(v);
    }
  }
  const auto csv = lines_of(slurp(out / "final_field.csv"));
  ASSERT_EQ(csv.size(), text_values.size() + 1);
  EXPECT_EQ(csv[0], report::kFieldHeader);
  const auto layers = core::policy_traits(s).layers;
  for (std::size_t i = 1; i < csv.size(); ++i) {
    const std::string& line = csv[i];
    const std::size_t last = line.rfind(',');
    ASSERT_NE(last, std::string::npos);
    EXPECT_EQ(static_cast<float>(std::stod(line.substr(last + 1))), static_cast<float>(text_values[i - 1])) << line;
  }
  EXPECT_EQ(csv[1].rfind(layers.front() + ",0,0,", 0), 0U) << csv[1];

  auto rec = console::read_recording(o.record);
  ASSERT_TRUE(rec.ok()) << rec.error().message;
  EXPECT_FALSE(rec->truncated);
  EXPECT_EQ(rec->frames.size(), 22U);  // one per tick and the closing one
  EXPECT_EQ(rec->info.layers, layers);
  EXPECT_DOUBLE_EQ(rec->frames.back().t_s, 20 / s.tick_rate_hz);
  EXPECT_EQ(rec->frames.back().uavs.size(), s.uavs);
  console::ReplayIndex index(std::move(rec).value());
  EXPECT_EQ(index.at(index.t1()).tick, 20U);
}

}  // namespace
}  // namespace pheromesh
