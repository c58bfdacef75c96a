// The Liu 2022 (ESUSTPM) policy (liu/src/policy.cpp): the place model's TPM
// update and confirmation, the UAV's decision from its view and its
// deposits, the field summary, the scenario parser, and a distributed run
// against run_liu_swarm where both are deterministic.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"
#include "pheromesh/core/world.hpp"
#include "pheromesh/liu/policy.hpp"
#include "pheromesh/liu/swarm.hpp"
#include "pheromesh/liu/tpm.hpp"
#include "unit_support.hpp"

namespace pheromesh::core {
namespace {

constexpr int kTpm = 0;
constexpr int kVisited = 1;
constexpr int kConfirmed = 2;

using test::source_path;

ScenarioConfig parse_ok(const std::string& text) {
  auto r = parse_scenario(text, "liu.textproto");
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
  return r.ok() ? r.value() : ScenarioConfig{};
}

// 10 x 10 cells of 100 m, 2 x 2 regions of one 5 x 5 tile, `uavs` UAVs in `start`.
std::string scenario_text(const std::string& liu, int uavs = 1, const std::string& start = "x: 2 y: 2 w: 1 h: 1",
                          const std::string& targets = "targets { x: 4 y: 5 }") {
  return "map { width: 10 height: 10 tile_size: 5 regions_x: 2 regions_y: 2 " + targets + " }\n" +
         "swarm { uavs: " + std::to_string(uavs) + " start_area { " + start + " } }\n" + "run { ticks: 20 }\n" +
         "policy { liu { " + liu + " } }\n";
}

DepositMsg observation(Cell c, RegionId region, float amount, uint32_t seq) {
  DepositMsg d;
  d.uav = 0;
  d.seq = seq;
  d.region = region;
  d.kind = static_cast<uint8_t>(DepositKind::Observation);
  d.cell = c;
  d.amount = amount;
  return d;
}

// Every tile of every layer, with values from `f`.
void fill_cache(TileCache& cache, const MapGeometry& geo, const std::function<float(int, Cell)>& f) {
  for (int32_t ty = 0; ty < geo.tiles_y(); ++ty) {
    for (int32_t tx = 0; tx < geo.tiles_x(); ++tx) {
      const Rect r = geo.tile_rect({tx, ty});
      for (int l = 0; l < cache.layers(); ++l) {
        TileMsg m;
        m.layer = static_cast<uint8_t>(l);
        m.tile = {tx, ty};
        m.width = static_cast<uint16_t>(r.w);
        m.height = static_cast<uint16_t>(r.h);
        for (int32_t y = r.y0; y < r.y0 + r.h; ++y) {
          for (int32_t x = r.x0; x < r.x0 + r.w; ++x) m.values.push_back(f(l, {x, y}));
        }
        cache.update(m);
      }
    }
  }
}

// --- place model -------------------------------------------------------------

TEST(LiuPlace, DetectionAndMissFollowEquationsFourAndFive) {
  const ScenarioConfig s = parse_ok(scenario_text(""));
  const MapGeometry geo = s.geometry();
  const RegionId r = geo.region_of({7, 6});
  auto place = make_liu_place(s, geo, r);
  std::vector<TargetEventMsg> events;
  EXPECT_FLOAT_EQ(place->value(kTpm, {7, 6}), 0.5F);  // Liu 2022 Sec. 5 uniform prior
  EXPECT_FLOAT_EQ(place->value(kVisited, {7, 6}), 0.0F);
  // Liu 2022 eq. (4): 0.3 · 0.5 / ((0.3 - 0.1) · 0.5 + 0.1) = 0.75.
  EXPECT_FALSE(place->apply(observation({7, 6}, r, 1.0F, 1), 3, events));
  EXPECT_FLOAT_EQ(place->value(kTpm, {7, 6}), 0.75F);
  EXPECT_FLOAT_EQ(place->value(kVisited, {7, 6}), 1.0F);
  // Liu 2022 eq. (5) as printed: (1 - 0.3) · 0.5 / (1 - 0.1) = 0.388889.
  EXPECT_FALSE(place->apply(observation({8, 6}, r, 0.0F, 2), 3, events));
  EXPECT_NEAR(place->value(kTpm, {8, 6}), 0.3888889F, 1e-6);
  // Liu 2022 eq. (3): an unsearched cell keeps its value, also over ticks.
  std::vector<TargetEventMsg> none;
  const HaloRing ring = place->begin_step(3, none);
  EXPECT_TRUE(ring.target.empty());
  EXPECT_TRUE(ring.obstacle.empty());
  place->finish_step();
  EXPECT_FLOAT_EQ(place->value(kTpm, {9, 9}), 0.5F);
  EXPECT_FLOAT_EQ(place->value(kTpm, {7, 6}), 0.75F);
  EXPECT_TRUE(events.empty());
}

TEST(LiuPlace, ThirdDetectionConfirmsTheCellOnceAndEmitsFirstMarked) {
  const ScenarioConfig s = parse_ok(scenario_text(""));
  const MapGeometry geo = s.geometry();
  const RegionId r = geo.region_of({4, 5});
  auto place = make_liu_place(s, geo, r);
  std::vector<TargetEventMsg> events;
  // 0.5 -> 0.75 -> 0.9 -> 0.964286 > θ = 0.95.
  place->apply(observation({4, 5}, r, 1.0F, 1), 10, events);
  place->apply(observation({4, 5}, r, 1.0F, 2), 11, events);
  EXPECT_NEAR(place->value(kTpm, {4, 5}), 0.9F, 1e-6);
  EXPECT_FLOAT_EQ(place->value(kConfirmed, {4, 5}), 0.0F);
  EXPECT_TRUE(events.empty());
  place->apply(observation({4, 5}, r, 1.0F, 3), 12, events);
  EXPECT_NEAR(place->value(kTpm, {4, 5}), 0.9642857F, 1e-6);
  EXPECT_FLOAT_EQ(place->value(kConfirmed, {4, 5}), 1.0F);
  ASSERT_EQ(events.size(), 1U);
  EXPECT_EQ(events[0].kind, 0);  // FirstMarked
  EXPECT_EQ(events[0].tick, 12U);
  EXPECT_EQ(events[0].region, r);
  EXPECT_EQ(events[0].cell, (Cell{4, 5}));
  // Misses lower P below θ again; the confirmation stays latched, no new event.
  for (uint32_t k = 0; k < 3; ++k) place->apply(observation({4, 5}, r, 0.0F, 4 + k), 13, events);
  EXPECT_LT(place->value(kTpm, {4, 5}), 0.95F);
  place->apply(observation({4, 5}, r, 1.0F, 8), 14, events);
  EXPECT_FLOAT_EQ(place->value(kConfirmed, {4, 5}), 1.0F);
  EXPECT_EQ(events.size(), 1U);
}

TEST(LiuPlace, RejectsAmountsOtherThanZeroOrOneAndForeignKinds) {
  const ScenarioConfig s = parse_ok(scenario_text(""));
  const MapGeometry geo = s.geometry();
  auto place = make_liu_place(s, geo, 0);
  std::vector<TargetEventMsg> events;
  EXPECT_TRUE(place->apply(observation({1, 1}, 0, 0.5F, 1), 0, events));
  EXPECT_FLOAT_EQ(place->value(kTpm, {1, 1}), 0.5F);
  DepositMsg d = observation({1, 1}, 0, 1.0F, 2);
  d.kind = static_cast<uint8_t>(DepositKind::PathVisit);
  EXPECT_TRUE(place->apply(d, 0, events));
  d.kind = static_cast<uint8_t>(DepositKind::LayerAdd);
  d.layer = kTpm;
  EXPECT_TRUE(place->apply(d, 0, events));
  d.layer = kVisited;  // the start cell: visited, not observed
  EXPECT_FALSE(place->apply(d, 0, events));
  EXPECT_FLOAT_EQ(place->value(kVisited, {1, 1}), 1.0F);
  EXPECT_FLOAT_EQ(place->value(kTpm, {1, 1}), 0.5F);
  d.cell = {7, 7};  // owned by another region
  EXPECT_TRUE(place->apply(d, 0, events));
}

TEST(LiuPlace, EveryRegionHoldsItsPartOfTheWholeMapPrior) {
  const ScenarioConfig s = parse_ok(scenario_text("prior: \"accurate\"", 1, "x: 2 y: 2 w: 1 h: 1",
                                                  "targets { x: 4 y: 5 } targets { x: 4 y: 7 } targets { x: 7 y: 5 }"));
  const MapGeometry geo = s.geometry();
  const std::vector<double> whole = liu_prior_map(liu_swarm_config_of(s.config_of<LiuConfig>(), s.targets));
  for (RegionId r = 0; r < geo.region_count(); ++r) {
    auto place = make_liu_place(s, geo, r);
    const Rect rect = geo.region_rect(r);
    for (int32_t y = rect.y0; y < rect.y0 + rect.h; ++y) {
      for (int32_t x = rect.x0; x < rect.x0 + rect.w; ++x) {
        EXPECT_FLOAT_EQ(place->value(kTpm, {x, y}), static_cast<float>(whole[geo.index({x, y})])) << x << "," << y;
      }
    }
  }
  // Liu 2022 eq. (2) with σ0 = 1 cell, α = 1, components at the cell centres: cell
  // (4, 7) holds its own target's mass (Φ(0.5) - Φ(-0.5))² = 0.146631, plus
  // (Φ(0.5) - Φ(-0.5)) (Φ(2.5) - Φ(1.5)) = 0.023205 from (4, 5) and
  // (Φ(-2.5) - Φ(-3.5)) (Φ(2.5) - Φ(1.5)) = 0.000362 from (7, 5): 0.170198.
  auto place = make_liu_place(s, geo, geo.region_of({4, 7}));
  EXPECT_NEAR(place->value(kTpm, {4, 7}), 0.170198, 1e-6);
  EXPECT_LT(place->value(kTpm, {0, 0}), 1e-6F);
}

// --- field summary -----------------------------------------------------------

TEST(LiuFieldSummary, CountsVisitedConfirmedAndRealTargetsAndSumsTheUncertainty) {
  const ScenarioConfig s = parse_ok(scenario_text("", 1, "x: 2 y: 2 w: 1 h: 1", "targets { x: 4 y: 5 } targets { x: 4 y: 7 }"));
  const auto summary = liu_field_summary(s, [](int layer, Cell c) -> float {
    if (layer == kTpm) return c == Cell{4, 5} ? 1.0F : (c == Cell{0, 0} ? 0.25F : 0.5F);
    if (layer == kVisited) return c.x < 3 ? 1.0F : 0.0F;
    return (c == Cell{4, 5} || c == Cell{9, 9}) ? 1.0F : 0.0F;
  });
  EXPECT_DOUBLE_EQ(summary.at("visited_cells"), 30.0);
  // EU = -Σ P log2 P: 98 cells at 0.5 (0.5 bit each), one at 1 (0), one at 0.25 (0.5 bit).
  EXPECT_DOUBLE_EQ(summary.at("environmental_uncertainty"), 49.5);
  EXPECT_DOUBLE_EQ(summary.at("confirmed_cells"), 2.0);
  EXPECT_DOUBLE_EQ(summary.at("real_targets_confirmed"), 1.0);
  EXPECT_DOUBLE_EQ(summary.at("false_confirmations"), 1.0);
}

// --- UAV -----------------------------------------------------------------------

struct UavFixture {
  ScenarioConfig s;
  MapGeometry geo;
  World world;
  explicit UavFixture(const std::string& text) : s(parse_ok(text)), geo(s.geometry()), world(geo, s.obstacles, s.targets) {}
};

TEST(LiuUav, TickZeroMarksTheStartCellVisitedAndReportsTheCornerInCellUnits) {
  UavFixture f(scenario_text("start_point: \"corner\" start_velocity: \"rest\""));
  auto uav = make_liu_uav(f.s, f.geo, f.world, 0);
  EXPECT_EQ(uav->cell(), (Cell{2, 2}));
  TileCache cache(f.geo, 3);
  UavActions out;
  uav->step(UavView{0, &cache, {}, {}}, out);
  ASSERT_EQ(out.deposits.size(), 1U);
  EXPECT_EQ(out.deposits[0].kind, static_cast<uint8_t>(DepositKind::LayerAdd));
  EXPECT_EQ(out.deposits[0].layer, kVisited);
  EXPECT_EQ(out.deposits[0].cell, (Cell{2, 2}));
  EXPECT_EQ(out.deposits[0].region, f.geo.region_of({2, 2}));
  // (200, 200) m is the corner of cell (2, 2): 200/100 - 0.5 = 1.5 cell units,
  // nudged inside the cell so that the state rounds to the cell it is over.
  EXPECT_NEAR(out.state.x, 1.5, 1e-8);
  EXPECT_NEAR(out.state.y, 1.5, 1e-8);
  EXPECT_EQ(std::lround(out.state.x), 2);
  EXPECT_DOUBLE_EQ(out.state.vx, 0.0);
}

TEST(LiuUav, EsustpmVelocityFromANeighbourInCellUnitsAndTheMostProbableCell) {
  // One UAV at the centre (250, 250) m of cell (2, 2), at rest; a neighbour
  // reported at (2.6, 2.0) cell units = (310, 250) m, 60 m east; the TPM
  // 0.9 in the cell north (2, 3), 0.5 elsewhere.
  UavFixture f(scenario_text("start_velocity: \"rest\" sensor: \"algorithm1\"", 2, "x: 2 y: 2 w: 1 h: 2"));
  auto uav = make_liu_uav(f.s, f.geo, f.world, 0);
  TileCache cache(f.geo, 3);
  fill_cache(cache, f.geo, [](int layer, Cell c) {
    if (layer == kTpm) return c == Cell{2, 3} ? 0.9F : 0.5F;
    return 0.0F;
  });
  UavStateMsg n;
  n.uav = 1;
  n.x = 2.6;
  n.y = 2.0;
  const std::vector<UavStateMsg> neighbours{n};
  UavActions out;
  uav->step(UavView{1, &cache, neighbours, {}}, out);
  // Liu 2022 eq. (7), Liu 2022 eq. (8), Liu 2022 eq. (9), Liu 2022 Table 1: β_1(60 m) = 2529.58 (F_1 from the neighbour to the
  // UAV, westwards); β_4(100 m) = 6116.29 (F_4 towards (250, 350) m, north).
  // Liu 2022 eq. (6): mvel = (-2529.58, 6116.29) / 4 = (-632.40, 1529.07) m/s, clipped
  // to 10 m/s: (-3.82184, 9.24086) m/s = (-0.0382184, 0.0924086) cell/tick.
  EXPECT_NEAR(out.state.vx, -0.0382184318, 1e-9);
  EXPECT_NEAR(out.state.vy, 0.0924086115, 1e-9);
  // Flown for one 1 s cycle (Liu 2022 eq. (10), Liu 2022 eq. (11)): (246.178, 259.241) m, still cell (2, 2).
  EXPECT_NEAR(out.state.x, 2.46178157 - 0.5, 1e-7);
  EXPECT_NEAR(out.state.y, 2.59240861 - 0.5, 1e-7);
  EXPECT_EQ(uav->cell(), (Cell{2, 2}));
  EXPECT_TRUE(out.deposits.empty());
  EXPECT_EQ(out.state.heading, heading_of_velocity(-3.82, 9.24, 0));
}

TEST(LiuUav, ConfirmedCellsNoLongerGuide) {
  // The same UAV alone; (2, 3) is the best cell but confirmed: the next best
  // (tie at 0.5) is the first heading from E, the cell (3, 2) east.
  UavFixture f(scenario_text("start_velocity: \"rest\""));
  auto uav = make_liu_uav(f.s, f.geo, f.world, 0);
  TileCache cache(f.geo, 3);
  fill_cache(cache, f.geo, [](int layer, Cell c) {
    if (layer == kTpm) return c == Cell{2, 3} ? 0.99F : 0.5F;
    if (layer == kConfirmed) return c == Cell{2, 3} ? 1.0F : 0.0F;
    return 0.0F;
  });
  UavActions out;
  uav->step(UavView{1, &cache, {}, {}}, out);
  EXPECT_NEAR(out.state.vx, 0.1, 1e-12);  // 10 m/s east = 0.1 cell/tick
  EXPECT_NEAR(out.state.vy, 0.0, 1e-12);
}

TEST(LiuUav, SendsOneObservationPerCellEnteredToTheOwningRegion) {
  // Guided east at 10 m/s from (250, 250) m with the Liu 2022 Algorithm 1 sensor: the
  // UAV crosses x = 300 m (cell (3, 2)) in cycle 5 and x = 400, 500 m in
  // cycles 15 and 25; cell (4, 2) is in region 0, (5, 2) in region 1.
  UavFixture f(scenario_text("start_velocity: \"rest\" sensor: \"algorithm1\"", 1, "x: 2 y: 2 w: 1 h: 1",
                             "targets { x: 3 y: 2 }"));
  auto uav = make_liu_uav(f.s, f.geo, f.world, 0);
  TileCache cache(f.geo, 3);
  fill_cache(cache, f.geo, [](int layer, Cell c) { return layer == kTpm ? (c.y == 2 ? 0.6F : 0.5F) : 0.0F; });
  std::vector<DepositMsg> all;
  std::vector<DetectionMsg> detections;
  for (uint32_t tick = 1; tick <= 26; ++tick) {
    UavActions out;
    uav->step(UavView{tick, &cache, {}, {}}, out);
    for (auto& d : out.deposits) {
      d.tick = tick;
      all.push_back(d);
    }
    for (auto& d : out.detections) detections.push_back(d);
  }
  ASSERT_EQ(all.size(), 3U);
  EXPECT_EQ(all[0].cell, (Cell{3, 2}));
  EXPECT_FLOAT_EQ(all[0].amount, 1.0F);  // the target's cell: Liu 2022 Algorithm 1 uses Liu 2022 eq. (4)
  EXPECT_EQ(all[1].cell, (Cell{4, 2}));
  EXPECT_FLOAT_EQ(all[1].amount, 0.0F);
  EXPECT_EQ(all[1].region, 0U);
  EXPECT_EQ(all[2].cell, (Cell{5, 2}));
  EXPECT_EQ(all[2].region, 1U);
  for (const auto& d : all) EXPECT_EQ(d.kind, static_cast<uint8_t>(DepositKind::Observation));
  EXPECT_NEAR(all[0].tick, 5, 1);
  EXPECT_NEAR(all[2].tick, 25, 1);
  ASSERT_EQ(detections.size(), 1U);
  EXPECT_EQ(detections[0].target, 0);
}

TEST(LiuTraits, LayersAndAViewThatHoldsEveryNeighbourWithANonNegligibleGain) {
  const ScenarioConfig s = parse_ok(scenario_text(""));
  const PolicyTraits t = liu_traits(s);
  EXPECT_EQ(t.layers, (std::vector<std::string>{"tpm", "visited", "confirmed"}));
  // Liu 2022 Table 1: |β(d)| < 1e-3 m/s beyond about 290 m = 2.9 cells of 100 m.
  EXPECT_DOUBLE_EQ(t.view_radius, 3.0);
  EXPECT_LT(std::abs(liu_gain(0, 300.0, s.config_of<LiuConfig>().params)), 1e-3);
  EXPECT_GT(std::abs(liu_gain(0, 250.0, s.config_of<LiuConfig>().params)), 1e-3);
  const ScenarioConfig fine = parse_ok(scenario_text("cell_size_m: 50"));
  EXPECT_DOUBLE_EQ(liu_traits(fine).view_radius, 6.0);
  const ScenarioConfig set = parse_ok(scenario_text("view_radius: 9"));
  EXPECT_DOUBLE_EQ(liu_traits(set).view_radius, 9.0);
}

// --- distributed run ---------------------------------------------------------

TEST(LiuSimulation, LawnmowerWithAlgorithm1SensorMatchesRunLiuSwarm) {
  // The mower with the Liu 2022 Algorithm 1 sensor has no randomness and no neighbour
  // rule: the distributed run must visit and update the same cells as
  // run_liu_swarm. Only the float tiles separate the EU.
  auto loaded = load_scenario(source_path("scenarios/liu2022-table2.textproto"));
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  ScenarioConfig s = loaded.value();
  LiuConfig mower = s.config_of<LiuConfig>();
  mower.search = LiuPolicy::kLawnmower;
  mower.sensor = LiuSensor::kAlgorithm1;
  s.set_policy_config(mower);
  Simulator sim(s);
  sim.run();
  LiuSwarmConfig c = liu_swarm_config_of(s.config_of<LiuConfig>(), s.targets);
  c.params.grid_width = s.width;
  c.params.grid_height = s.height;
  c.params.uav_count = s.uavs;
  c.params.cycles = s.ticks;
  auto ref = run_liu_swarm(c, s.seed);
  ASSERT_TRUE(ref.ok());
  const auto& field = sim.recorder().field_summary();
  EXPECT_DOUBLE_EQ(field.at("visited_cells"), static_cast<double>(ref.value().visited_cells));
  EXPECT_NEAR(field.at("environmental_uncertainty"), ref.value().final_eu, 1e-4);
  EXPECT_DOUBLE_EQ(field.at("real_targets_confirmed"), ref.value().targets_found);
  EXPECT_DOUBLE_EQ(field.at("false_confirmations"), ref.value().false_confirmations);
}

TEST(LiuSimulation, TheDisperseSearchFliesAsTheDistributedPolicyAndSpreadsWiderThanEsustpm) {
  // ESUSTPM-disperse (ours) on the real-swarm path: the place agents apply
  // every observation, and with Liu 2022 Algorithm 1's sensor (no noise) seed 1 visits more
  // cells than ESUSTPM (liu-table2, 10 seeds: 98.5 vs 58.4).
  auto loaded = load_scenario(source_path("scenarios/liu2022-table2-disperse.textproto"));
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  const auto visited = [](ScenarioConfig s, LiuPolicy search) {
    LiuConfig c = s.config_of<LiuConfig>();
    c.search = search;
    c.sensor = LiuSensor::kAlgorithm1;
    s.set_policy_config(c);
    Simulator sim(s);
    sim.run();
    uint64_t applied = 0;
    for (const auto& [region, h] : sim.recorder().health()) applied += h.deposits_applied;
    EXPECT_EQ(sim.recorder().deposits_sent(), applied);
    return sim.recorder().field_summary().at("visited_cells");
  };
  const double disperse = visited(loaded.value(), LiuPolicy::kEsustpmDisperse);
  const double esustpm = visited(loaded.value(), LiuPolicy::kEsustpm);
  EXPECT_GT(disperse, esustpm + 15.0);
}

TEST(LiuSimulation, SmallScenarioAppliesEveryDepositAndLowersTheUncertainty) {
  auto loaded = load_scenario(source_path("scenarios/liu2022-small.textproto"));
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  Simulator sim(loaded.value());
  sim.run();
  const auto& rec = sim.recorder();
  uint64_t applied = 0;
  uint64_t rejected = 0;
  for (const auto& [region, h] : rec.health()) {
    applied += h.deposits_applied;
    rejected += h.deposits_rejected;
  }
  EXPECT_GT(rec.deposits_sent(), 4U);
  EXPECT_EQ(rec.deposits_sent(), applied);
  EXPECT_EQ(rejected, 0U);
  const auto& field = rec.field_summary();
  EXPECT_GE(field.at("visited_cells"), 4.0);
  const std::vector<double> prior = liu_prior_map(liu_swarm_config_of(loaded.value().config_of<LiuConfig>(), loaded.value().targets));
  EXPECT_NE(field.at("environmental_uncertainty"), environmental_uncertainty(prior));
}

// --- scenario --------------------------------------------------------------------

TEST(LiuScenario, Table2LoadsWithTable1Parameters) {
  auto r = load_scenario(source_path("scenarios/liu2022-table2.textproto"));
  ASSERT_TRUE(r.ok()) << r.error().message;
  const ScenarioConfig& s = r.value();
  EXPECT_EQ(s.policy, "liu");
  EXPECT_EQ(s.config_of<LiuConfig>().search, LiuPolicy::kEsustpm);
  EXPECT_EQ(s.config_of<LiuConfig>().start_point, LiuStartPoint::kCorner);
  EXPECT_EQ(s.uavs, 10U);
  EXPECT_EQ(s.ticks, 200U);
  EXPECT_EQ(s.targets.size(), 3U);
  EXPECT_DOUBLE_EQ(s.config_of<LiuConfig>().params.k[3], -80.0);
  EXPECT_DOUBLE_EQ(s.config_of<LiuConfig>().params.c[0], 120.0);
  EXPECT_DOUBLE_EQ(s.config_of<LiuConfig>().params.p_detection, 0.3);
  EXPECT_DOUBLE_EQ(s.config_of<LiuConfig>().params.dt_s, 0.01);
  EXPECT_TRUE(load_scenario(source_path("scenarios/liu2022-small.textproto")).ok());
}

void expect_error(const std::string& text, int line, const std::string& field) {
  const auto r = parse_scenario(text, "bad.textproto");
  ASSERT_FALSE(r.ok()) << "expected an error for field " << field;
  EXPECT_NE(r.error().message.find("bad.textproto:" + std::to_string(line) + ":"), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find("field '" + field + "'"), std::string::npos) << r.error().message;
}

TEST(LiuScenario, ErrorsNameTheLineAndTheField) {
  const std::string head = "map { width: 10 height: 10 }\nswarm { uavs: 4 }\npolicy { liu {\n";
  expect_error(head + "search: \"spiral\"\n} }\n", 4, "policy.liu.search");
  expect_error(head + "p_false_alarm: 1\n} }\n", 4, "policy.liu.p_false_alarm");
  expect_error(head + "sensor: \"perfect\"\n} }\n", 4, "policy.liu.sensor");
  expect_error(head + "\ndt_s: 2\n} }\n", 5, "policy.liu.dt_s");
  expect_error(head + "prior: \"wrong\"\nwrong_prior_cells { x: 3 y: 12 }\n} }\n", 5, "policy.liu.wrong_prior_cells[0].y");
  expect_error(head + "delta: 0\n} }\n", 4, "policy.liu.delta");
  expect_error(head + "view_radius: nan\n} }\n", 4, "policy.liu.view_radius");
  expect_error("map { width: 10 height: 4 }\nswarm { uavs: 5 }\npolicy { liu {\nsearch: \"lawnmower\"\n} }\n", 4,
               "policy.liu.search");
  const auto r = parse_scenario(head + "prior: \"wrong\"\n} }\n", "bad.textproto");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("wrong_prior_cells"), std::string::npos) << r.error().message;
}

}  // namespace
TEST(LiuScenario, TheDisperseVariantLoadsAsItsOwnSearchWithTable1Parameters) {
  auto r = load_scenario(source_path("scenarios/liu2022-table2-disperse.textproto"));
  ASSERT_TRUE(r.ok()) << r.error().message;
  const ScenarioConfig& s = r.value();
  EXPECT_EQ(s.config_of<LiuConfig>().search, LiuPolicy::kEsustpmDisperse);
  EXPECT_DOUBLE_EQ(s.config_of<LiuConfig>().params.k[0], -80.0);
  EXPECT_DOUBLE_EQ(s.config_of<LiuConfig>().params.c[3], 120.0);
  EXPECT_EQ(s.uavs, 10U);
  EXPECT_EQ(s.targets.size(), 3U);
  // The paper's table2 scenario is unchanged: ESUSTPM.
  auto paper = load_scenario(source_path("scenarios/liu2022-table2.textproto"));
  ASSERT_TRUE(paper.ok());
  EXPECT_EQ(paper.value().config_of<LiuConfig>().search, LiuPolicy::kEsustpm);
}

}  // namespace pheromesh::core
