// The statistics and checks every experiment report relies on (issue 17):
// confidence intervals, the automatic verdict, the variants' gain, scenario
// patches, and the comparison of a simulator run with a run of real
// processes (experiments/flight.hpp). Numbers worked by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "experiments/experiment.hpp"
#include "experiments/flight.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/cliutil/scenario_paths.hpp"

namespace ex = pheromesh::cli::experiments;
using pheromesh::core::ScenarioConfig;

TEST(ExperimentStats, TheConfidenceIntervalUsesStudentsT) {
  // 1, 2, 3, 4, 5: mean 3, sd sqrt(2.5) = 1.5811; t(0.975, 4) = 2.776;
  // half width 2.776 * 1.5811 / sqrt(5) = 1.9630.
  const ex::Interval ci = ex::ci95({1, 2, 3, 4, 5});
  EXPECT_NEAR(ci.lo, 3 - 1.9630, 1e-3);
  EXPECT_NEAR(ci.hi, 3 + 1.9630, 1e-3);
  const ex::Interval one = ex::ci95({7});
  EXPECT_EQ(one.lo, 7);
  EXPECT_EQ(one.hi, 7);
}

TEST(ExperimentStats, TheAutomaticVerdictReproducesWithinFifteenPercentOrTheIntervalAndSaysByHowMuchOtherwise) {
  ex::Row r{"m", 100.0, {110, 112, 114}, "", "", ""};
  EXPECT_EQ(ex::auto_verdict(r), "reproduced");  // 12 % above
  r.ours = {140, 150, 160};                         // 50 % above, CI 125.2-174.8
  EXPECT_EQ(ex::auto_verdict(r), "differs: ours is 50 % higher");
  r.ours = {20, 100, 180};  // mean 100: equal
  EXPECT_EQ(ex::auto_verdict(r), "reproduced");
  // Inside a wide interval of few runs is not enough: 3 runs, mean 60,
  // CI 60 ± 4.303 * 40 / sqrt(3) = -39.4 .. 159.4 holds 100.
  r.ours = {20, 60, 100};
  EXPECT_EQ(ex::auto_verdict(r), "differs: ours is 40 % lower");
  // From 5 runs on it is: 6 runs, mean 80 (20 % low), sd sqrt(7000 / 5) =
  // 37.42, CI 80 ± 2.571 * 37.42 / sqrt(6) = 40.7 .. 119.3 holds 100.
  r.ours = {30, 50, 70, 90, 110, 130};
  EXPECT_EQ(ex::auto_verdict(r), "reproduced");
  r.ours = {40, 60, 50};  // 50 % below; CI 25.2-74.8 excludes 100
  EXPECT_EQ(ex::auto_verdict(r), "differs: ours is 50 % lower");
  r.paper.reset();
  EXPECT_EQ(ex::auto_verdict(r), "");
}

TEST(ExperimentStats, TheGainIsTheImprovementOnTheBaselineMeanWithAnIntervalAroundIt) {
  ex::Comparison lower{"time", "tick", "paper", "ours", true, {100, 100, 100, 100}, {70, 70, 70, 70}, ""};
  ex::Gain g = ex::gain_of(lower);
  EXPECT_DOUBLE_EQ(g.gain, 0.3);  // (100 - 70) / 100
  EXPECT_DOUBLE_EQ(g.ci.lo, 0.3);  // no spread: every resample is the same
  EXPECT_DOUBLE_EQ(g.ci.hi, 0.3);
  ex::Comparison higher{"coverage", "", "paper", "ours", false, {0.5, 0.5}, {0.6, 0.6}, ""};
  EXPECT_NEAR(ex::gain_of(higher).gain, 0.2, 1e-12);  // (0.6 - 0.5) / 0.5
  // With spread the interval holds the point estimate and has width.
  ex::Comparison noisy{"time", "tick", "paper", "ours", true, {90, 100, 110, 95, 105}, {60, 80, 70, 75, 65}, ""};
  g = ex::gain_of(noisy);
  EXPECT_DOUBLE_EQ(g.gain, 0.3);  // (100 - 70) / 100
  EXPECT_LT(g.ci.lo, g.gain);
  EXPECT_GT(g.ci.hi, g.gain);
  EXPECT_EQ(ex::gain_of(noisy).ci.lo, g.ci.lo);  // seeded: the same data give the same interval
}

TEST(ScenarioPatch, APatchReplacesScalarsAppendsRepeatedFieldsAndIsValidatedLikeAFile) {
  auto base = pheromesh::core::load_scenario(pheromesh::cli::shipped_scenario("small-test.textproto"));
  ASSERT_TRUE(base) << base.error().message;
  const std::size_t obstacles = base->obstacles.size();
  auto p = pheromesh::core::patch_scenario(base.value(), "swarm { uavs: 3 } run { seed: 9 } map { obstacles { x: 0 y: 29 w: 2 h: 1 } }",
                                           "patched");
  ASSERT_TRUE(p) << p.error().message;
  EXPECT_EQ(p->uavs, 3U);
  EXPECT_EQ(p->seed, 9U);
  EXPECT_EQ(p->obstacles.size(), obstacles + 1);
  EXPECT_EQ(p->width, base->width);
  // The patched text is the config's text: parsing it again gives it back.
  auto again = pheromesh::core::parse_scenario(p->source_text, "again");
  ASSERT_TRUE(again);
  EXPECT_EQ(again->uavs, 3U);
  // A patch that breaks the scenario is refused with the field named.
  auto bad = pheromesh::core::patch_scenario(base.value(), "map { tile_size: 1 }", "bad-patch");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("map.tile_size"), std::string::npos) << bad.error().message;
  auto garbage = pheromesh::core::patch_scenario(base.value(), "swarm { no_such_field: 1 }", "garbage");
  ASSERT_FALSE(garbage);
  EXPECT_NE(garbage.error().message.find("no_such_field"), std::string::npos) << garbage.error().message;
}

TEST(DistributedCheck, MetricsJsonNumbersAreReadBackAndEveryDifferenceIsNamed) {
  const std::string json = R"({"ticks": 100, "coverage": 0.5, "covered_cells": 450, "targets_found": 2,
    "acquisition_ticks": [12, 40], "revisit_response_ticks": [], "leader_arrival_tick": null,
    "deposits_sent": 800, "field": {"a": 1.5, "b": null}})";
  ex::RunNumbers n;
  std::string error;
  ASSERT_TRUE(ex::numbers_from_metrics_json(json, n, error)) << error;
  EXPECT_EQ(n.ticks, 100U);
  EXPECT_EQ(n.acquisition_ticks, (std::vector<uint32_t>{12, 40}));
  EXPECT_FALSE(n.leader_arrival_tick);
  EXPECT_EQ(n.field.size(), 1U);  // the null (a NaN) is left out
  ex::RunNumbers sim = n;
  sim.field["b"] = std::nan("");  // NaN in the simulator = null in the file: equal
  EXPECT_EQ(ex::differences(sim, n), "");
  sim.acquisition_ticks = {12, 41};
  sim.field["a"] = 1.5000001;
  const std::string d = ex::differences(sim, n);
  EXPECT_NE(d.find("acquisition_ticks: [12 41] (simulator) vs [12 40] (processes)"), std::string::npos) << d;
  EXPECT_NE(d.find("field.a"), std::string::npos) << d;
  EXPECT_FALSE(ex::numbers_from_metrics_json(R"({"ticks": 1})", n, error));
  EXPECT_NE(error.find("coverage"), std::string::npos) << error;
  EXPECT_FALSE(ex::numbers_from_metrics_json("not json", n, error));
}

TEST(DistributedCheck, AScenarioChangedInMemoryOnlyIsReportedAsAFailedCheckNotFlown) {
  auto base = pheromesh::core::load_scenario(pheromesh::cli::shipped_scenario("small-test.textproto"));
  ASSERT_TRUE(base);
  ScenarioConfig s = base.value();
  s.ticks = 5;  // in memory only: the processes would fly the text's ticks
  s.seed = 3;
  ex::DistributedOptions o;
  o.enabled = true;
  o.program = "/nonexistent/pheromesh";  // never reached
  o.work_dir = ::testing::TempDir() + "/dist-check";
  ex::set_distributed(o);
  const ex::RunNumbers n = ex::fly(s);
  EXPECT_EQ(n.ticks, 5U);
  ASSERT_EQ(ex::distributed_checks().size(), 1U);
  const auto& c = ex::distributed_checks().front();
  EXPECT_FALSE(c.equal);
  EXPECT_NE(c.differences.find("changed the scenario in memory"), std::string::npos) << c.differences;
  EXPECT_NE(c.differences.find("ticks 5 vs"), std::string::npos) << c.differences;
  // A run that is not to be checked (a sweep) adds none.
  ex::fly(s, {}, false);
  EXPECT_EQ(ex::distributed_checks().size(), 1U);
  ex::set_distributed({});
  EXPECT_TRUE(ex::distributed_checks().empty());
}
