// The Duan 2009 policy (common/core/papers/duan/src/policy.cpp): the place model's
// point-pheromone sum and reports, Duan 2009 eq. (10)'s Σ_{j≠i} from the published sum,
// the ETA from broadcast intervals (Duan 2009 eq. (4), Duan 2009 eq. (5), Duan 2009 eq. (6), Duan 2009 Fig. 6), the
// UAV's planning phase, deposits and flight, and the scenario parser's errors.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "pheromesh/core/place_core.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"
#include "pheromesh/core/uav_core.hpp"
#include "pheromesh/duan/policy.hpp"
#include "unit_support.hpp"

namespace pheromesh::core {
namespace {

using namespace duan_detail;  // NOLINT: the policy's test hooks

using test::source_path;

// A 16 x 16 mesh, 2 x 2 regions of 8 x 8, `uavs` UAVs.
std::string small_text(int uavs, const std::string& extra = "") {
  std::string t = "map { width: 16 height: 16 tile_size: 4 regions_x: 2 regions_y: 2 }\n"
                  "swarm { uavs: " + std::to_string(uavs) + " }\nrun { ticks: 80 seed: 3 }\n"
                  "policy { duan {\n  iterations: 5\n  ants: 6\n  dt_s: 4\n" + extra;
  const char* missions[] = {"  uavs { start { x: 1 y: 1 } target { x: 2 y: 13 } }\n",
                            "  uavs { start { x: 8 y: 1 } target { x: 9 y: 14 } }\n",
                            "  uavs { start { x: 13 y: 2 } target { x: 12 y: 14 } }\n"};
  for (int i = 0; i < uavs; ++i) t += missions[i];
  return t + "} }\n";
}

ScenarioConfig parse_duan(const std::string& text) {
  auto r = parse_scenario(text, "duan-test.textproto");
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
  return r.ok() ? r.value() : ScenarioConfig{};
}

DepositMsg deposit(uint32_t uav, uint32_t seq, DepositKind kind, Cell c, float amount, uint8_t layer = 0,
                   RegionId region = 0) {
  DepositMsg d;
  d.uav = uav;
  d.seq = seq;
  d.region = region;
  d.kind = static_cast<uint8_t>(kind);
  d.cell = c;
  d.amount = amount;
  d.layer = layer;
  return d;
}

// --- Duan 2009 eq. (10) input -----------------------------------------------------------

TEST(DuanPolicy, OthersPointSumIsThePublishedSumMinusTheOwnShare) {
  // Three UAVs; at this node the others hold 0.1 and 0.2, this UAV 10:
  // the place publishes 10.3 (as a float), Σ_{j≠i} = 10.3f - 10 = 0.3 (to float rounding).
  EXPECT_NEAR(others_point_sum(10.3F, 10.0, 0.1), 0.3, 1e-6);
  // This UAV sent nothing here (τ = τ_min): the place counted it as τ_min.
  EXPECT_NEAR(others_point_sum(0.3F, 0.1, 0.1), 0.2, 1e-7);
  // The own share is the float that was sent: 2.7 is not a float.
  EXPECT_DOUBLE_EQ(others_point_sum(static_cast<float>(2.7) + 0.5F, 2.7, 0.1),
                   static_cast<double>(static_cast<float>(2.7) + 0.5F) - static_cast<double>(static_cast<float>(2.7)));
  // A stale tile never gives a negative sum.
  EXPECT_EQ(others_point_sum(1.0F, 5.0, 0.1), 0.0);
}

// --- ETA (Duan 2009 eq. (4), Duan 2009 eq. (5), Duan 2009 eq. (6), Duan 2009 Fig. 6) ------------------------------------------------

TEST(DuanPolicy, EtaBroadcastCarriesThePhaseThenEquationFourIntervals) {
  const auto v = eta_broadcast(2, {52.14, 60.0}, SpeedLimits{200.0, 300.0});
  ASSERT_EQ(v.size(), 5U);
  EXPECT_EQ(v[0], 2.0);
  EXPECT_NEAR(v[1], 173.8, 1e-9);  // 52140 m / 300 m/s
  EXPECT_NEAR(v[2], 260.7, 1e-9);  // 52140 m / 200 m/s
  EXPECT_NEAR(v[3], 200.0, 1e-9);
  EXPECT_NEAR(v[4], 300.0, 1e-9);
}

TEST(DuanPolicy, TableThreeLengthsAgreeOnTheEtaFromTheBroadcastsAlone) {
  const SpeedLimits sp{200.0, 300.0};
  std::map<uint32_t, std::vector<double>> in;
  const std::vector<std::vector<double>> lengths{{51.31}, {47.80}, {52.14}};
  for (uint32_t i = 0; i < 3; ++i) {
    const auto b = eta_broadcast(1, lengths[i], sp);
    in[i].assign(b.begin() + 1, b.end());
  }
  // S = [max T_min, min T_max] = [52.14/0.3, 47.80/0.2] = [173.8, 239] s; T_a = min S.
  const double speeds[] = {51310.0 / 173.8, 47800.0 / 173.8, 300.0};  // 295.2, 275.0, 300 m/s (Duan 2009 Table 3)
  for (uint32_t i = 0; i < 3; ++i) {
    const auto d = decide_eta(in, i, lengths[i], sp);
    ASSERT_TRUE(d);
    EXPECT_TRUE(d->agreed);
    EXPECT_NEAR(d->eta_s, 173.8, 1e-6);
    EXPECT_EQ(d->chosen, 0U);
    EXPECT_NEAR(d->speed_mps, speeds[i], 1e-6);
  }
  EXPECT_FALSE(decide_eta(in, 0, {}, sp));  // no candidates, nothing to fly
}

TEST(DuanPolicy, EtaPicksTheCheapestCandidateFeasibleAtTa) {
  const SpeedLimits sp{200.0, 300.0};
  std::map<uint32_t, std::vector<double>> in;
  // UAV 0: 50 km [166.7, 250] s or 70 km [233.3, 350] s; UAV 1: 80 km [266.7, 400] s;
  // UAV 2 takes no part (phase number only). S = [266.7, 350], T_a = 266.7 s:
  // UAV 0 must fly its second (dearer) candidate at 70000 / 266.67 = 262.5 m/s.
  const auto b0 = eta_broadcast(1, {50.0, 70.0}, sp);
  const auto b1 = eta_broadcast(1, {80.0}, sp);
  in[0].assign(b0.begin() + 1, b0.end());
  in[1].assign(b1.begin() + 1, b1.end());
  in[2] = {};
  const auto d = decide_eta(in, 0, {50.0, 70.0}, sp);
  ASSERT_TRUE(d);
  EXPECT_NEAR(d->eta_s, 80000.0 / 300.0, 1e-6);
  EXPECT_EQ(d->chosen, 1U);
  EXPECT_NEAR(d->speed_mps, 262.5, 1e-6);
}

TEST(DuanPolicy, EmptyWindowFallsBackToTheLatestEarliestArrival) {
  const SpeedLimits sp{200.0, 300.0};
  std::map<uint32_t, std::vector<double>> in;
  in[0] = {100.0, 150.0};  // 30 km
  in[1] = {200.0, 300.0};  // 60 km: S_0 ∩ S_1 = ∅
  const auto d = decide_eta(in, 0, {30.0}, sp);
  ASSERT_TRUE(d);
  EXPECT_FALSE(d->agreed);
  EXPECT_DOUBLE_EQ(d->eta_s, 200.0);
  EXPECT_DOUBLE_EQ(d->speed_mps, 200.0);  // 150 m/s clamped to V_min
}

// --- threat layer --------------------------------------------------------------

TEST(DuanPolicy, ThreatLayerIsTheMeanEquationTwoCostOfTheNodesEdges) {
  // Threat at (0, 0) km, radius 10, grade 1; node (1, 0) of a 3 x 1 mesh at 1 km.
  const Threat t{{0.0, 0.0}, 10.0, 1.0};
  auto inv4 = [](double d) { return 1.0 / (d * d * d * d); };
  const double west = inv4(0.9) + inv4(0.7) + inv4(0.5) + inv4(0.3) + inv4(0.1);  // edge (1,0) -> (0,0), L = 1
  const double east = inv4(1.1) + inv4(1.3) + inv4(1.5) + inv4(1.7) + inv4(1.9);  // edge (1,0) -> (2,0)
  EXPECT_NEAR(node_threat(std::span<const Threat>(&t, 1), 1, 0, 3, 1, 1.0), (west + east) / 2.0, 1e-9);
  EXPECT_NEAR((west + east) / 2.0, 5073.2865, 1e-3);
}

// --- place model ---------------------------------------------------------------

TEST(DuanPlace, PointSumCountsEveryUavWithTauMinUntilItSetsAValue) {
  const ScenarioConfig s = parse_duan(small_text(3));
  PlaceCore p(s, 0);
  std::vector<TargetEventMsg> ev;
  const Cell c{2, 3};
  auto sum = [&] { return p.value(kPointSum, c); };
  p.finish_tick();
  EXPECT_FLOAT_EQ(sum(), 0.3F);  // 3 x τ_min
  std::vector<DepositMsg> ds{deposit(0, 1, DepositKind::PointSet, c, 5.0F), deposit(1, 1, DepositKind::PointSet, c, 2.0F)};
  p.begin_tick(ds, 1, ev);
  p.finish_tick();
  EXPECT_FLOAT_EQ(sum(), 7.1F);  // 5 + 2 + 0.1
  // UAV 0 clears and sets elsewhere; UAV 7 does not exist.
  ds = {deposit(0, 2, DepositKind::PointClear, {0, 0}, 0.0F), deposit(0, 3, DepositKind::PointSet, {4, 4}, 1.0F),
        deposit(7, 1, DepositKind::PointSet, c, 1.0F)};
  p.begin_tick(ds, 2, ev);
  p.finish_tick();
  EXPECT_FLOAT_EQ(sum(), 2.2F);
  EXPECT_FLOAT_EQ(p.value(kPointSum, {4, 4}), 1.2F);
  EXPECT_EQ(p.ledger().applied, 4U);
  EXPECT_EQ(p.ledger().rejected(), 1U);
}

TEST(DuanPlace, TheSumDoesNotDependOnTheOrderDepositsArriveIn) {
  const ScenarioConfig s = parse_duan(small_text(3));
  PlaceCore a(s, 0), b(s, 0);
  std::vector<TargetEventMsg> ev;
  std::vector<DepositMsg> ds;
  for (uint32_t u = 0; u < 3; ++u) {
    for (int32_t k = 0; k < 5; ++k) ds.push_back(deposit(u, static_cast<uint32_t>(k + 1), DepositKind::PointSet, {k, k}, 0.37F * static_cast<float>(u + 1) + 0.11F * static_cast<float>(k)));
  }
  std::vector<DepositMsg> reversed(ds.rbegin(), ds.rend());
  a.begin_tick(ds, 0, ev);
  b.begin_tick(reversed, 0, ev);
  a.finish_tick();
  b.finish_tick();
  for (int32_t k = 0; k < 5; ++k) EXPECT_EQ(a.value(kPointSum, {k, k}), b.value(kPointSum, {k, k}));
}

TEST(DuanPlace, ReportsKeepTheLargestValueAndOtherLayersTakeNone) {
  const ScenarioConfig s = parse_duan(small_text(2));
  PlaceCore p(s, 0);
  std::vector<TargetEventMsg> ev;
  std::vector<DepositMsg> ds{deposit(0, 1, DepositKind::LayerAdd, {1, 1}, 120.0F, kArrivalS),
                             deposit(1, 1, DepositKind::LayerAdd, {1, 1}, 118.0F, kArrivalS),
                             deposit(1, 2, DepositKind::LayerAdd, {1, 1}, 5.0F, kPointSum),
                             deposit(1, 3, DepositKind::PathVisit, {1, 1}, 1.0F)};
  p.begin_tick(ds, 0, ev);
  p.finish_tick();
  EXPECT_FLOAT_EQ(p.value(kArrivalS, {1, 1}), 120.0F);
  EXPECT_EQ(p.ledger().applied, 2U);
  EXPECT_EQ(p.ledger().rejected(), 2U);
}

TEST(DuanPlace, PopUpThreatEntersTheThreatLayerAtItsTick) {
  const ScenarioConfig s = parse_duan(small_text(1, "  popups { x_km: 4 y_km: 4 radius_km: 3 grade: 2 appear_tick: 5 }\n"));
  PlaceCore p(s, 0);
  std::vector<TargetEventMsg> ev;
  std::vector<DepositMsg> none;
  const Cell c{2, 2};  // the pop-up's centre node
  p.begin_tick(none, 4, ev);
  p.finish_tick();
  EXPECT_EQ(p.value(kThreat, c), 0.0F);
  p.begin_tick(none, 5, ev);
  p.finish_tick();
  const Threat t{{4.0, 4.0}, 3.0, 2.0};
  EXPECT_FLOAT_EQ(p.value(kThreat, c),
                  static_cast<float>(node_threat(std::span<const Threat>(&t, 1), 2, 2, 16, 16, 2.0)));
  EXPECT_GT(p.value(kThreat, c), 0.0F);
}

// --- UAV -----------------------------------------------------------------------

TEST(DuanUav, PlansOneIterationPerTickThenBroadcastsAndFliesAtLengthOverEta) {
  const ScenarioConfig s = parse_duan(small_text(1));
  const MapGeometry geo = s.geometry();
  const World world(geo, {}, {});
  UavCore u(s, world, 0);
  UavCore::Output out;
  // Tick 0: iteration 1, point pheromone sent (no clear yet), no broadcast.
  u.step(0, out);
  ASSERT_FALSE(out.deposits.empty());
  for (const auto& d : out.deposits) EXPECT_EQ(d.kind, static_cast<uint8_t>(DepositKind::PointSet));
  EXPECT_FALSE(out.broadcast);
  // Tick 1: clears the regions it set, then sets again.
  u.step(1, out);
  ASSERT_FALSE(out.deposits.empty());
  EXPECT_EQ(out.deposits.front().kind, static_cast<uint8_t>(DepositKind::PointClear));
  for (uint32_t k = 2; k < 5; ++k) u.step(k, out);
  // Tick 4 = iteration Nc_max = 5: the candidates' intervals.
  ASSERT_TRUE(out.broadcast);
  const BroadcastMsg b = *out.broadcast;
  EXPECT_EQ(b.kind, static_cast<uint8_t>(BroadcastKind::EtaIntervals));
  ASSERT_GE(b.values.size(), 3U);
  EXPECT_EQ(b.values[0], 1.0);  // phase 1
  // Tick 5: alone, T_a = min S = the shortest candidate's L / V_max, flown at V_max.
  u.receive_broadcast(b);
  u.step(5, out);
  EXPECT_EQ(out.state.x, 1.0);
  EXPECT_EQ(out.state.y, 1.0);
  u.step(6, out);
  const double step_cells = 300.0 * 4.0 / 2000.0;  // V dt / spacing = 0.6 cell
  EXPECT_NEAR(std::hypot(out.state.vx, out.state.vy), step_cells, 1e-9);
}

TEST(DuanUav, ALoneUavPlansExactlyLikeTheColonyItWraps) {
  // N = 1: Duan 2009 eq. (10) is the edge pheromone alone, so the distributed colony
  // must consume its random stream exactly like DuanColony::plan.
  const ScenarioConfig s = parse_duan(small_text(1));
  Simulator sim(s);
  sim.run();
  const ThreatMesh mesh(MeshSpec{{0.0, 0.0}, 30.0, 30.0, 15, 15, s.config_of<DuanConfig>().f}, s.config_of<DuanConfig>().threats);
  DuanColony colony(mesh, s.config_of<DuanConfig>().aco, Rng(stream_seed(s.seed, "duan-uav", 0)));
  const PathResult r = colony.plan(mesh.node(1, 1), mesh.node(2, 13), PointPheromone{});
  ASSERT_TRUE(r.found);
  std::vector<std::vector<EtaCandidate>> c(1);
  for (const auto& t : r.candidates) c[0].push_back({t.length_km, 0.0});
  const auto plan = coordinate_eta(c, s.config_of<DuanConfig>().speeds);
  ASSERT_TRUE(plan.ok());
  const Cell target{2, 13};
  EXPECT_FLOAT_EQ(sim.field_value(kEtaS, target), static_cast<float>(plan->eta_s));
  EXPECT_FLOAT_EQ(sim.field_value(kPlannedKm, target), static_cast<float>(r.candidates[plan->chosen[0]].length_km));
  EXPECT_NEAR(sim.field_value(kArrivalS, target), plan->eta_s, 1e-3);
  const auto& st = sim.recorder().uavs().at(0).last;
  EXPECT_EQ(st.x, 2.0);
  EXPECT_EQ(st.y, 13.0);
}

TEST(DuanUav, TeamArrivesTogetherAfterAPopUpReplan) {
  const ScenarioConfig s = parse_duan(small_text(3, "  popups { x_km: 12 y_km: 14 radius_km: 4 grade: 2.5 appear_tick: 9 }\n"));
  Simulator sim(s);
  sim.run();
  const auto f = field_summary(s, [&](int l, Cell c) { return sim.field_value(l, c); });
  EXPECT_EQ(f.at("arrived"), 3.0);
  EXPECT_NEAR(f.at("arrival_spread_s"), 0.0, 1e-3);
  for (int i = 1; i <= 3; ++i) {
    const std::string p = "uav" + std::to_string(i) + "_";
    EXPECT_GE(f.at(p + "speed_mps"), 200.0 - 1e-3);
    EXPECT_LE(f.at(p + "speed_mps"), 300.0 + 1e-3);
    EXPECT_GT(f.at(p + "arrival_s"), f.at(p + "eta_s") - 1e-3);  // the replan came after take-off
  }
}

// --- scenario ------------------------------------------------------------------

TEST(DuanScenarioFile, PaperScenarioLoadsTables) {
  const auto r = load_scenario(source_path("scenarios/duan2009-table3.textproto"));
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->policy, "duan");
  EXPECT_EQ(r->width, 31);
  EXPECT_EQ(r->height, 36);
  EXPECT_EQ(r->config_of<DuanConfig>().threats.size(), 5U);
  ASSERT_EQ(r->config_of<DuanConfig>().popups.size(), 2U);
  EXPECT_EQ(r->config_of<DuanConfig>().popups[0].threat.grade, 2.5);
  ASSERT_EQ(r->config_of<DuanConfig>().uavs.size(), 3U);
  EXPECT_EQ(r->config_of<DuanConfig>().uavs[1].target, (Cell{20, 30}));
  EXPECT_EQ(r->config_of<DuanConfig>().aco.alpha, 3.0);
  EXPECT_EQ(r->config_of<DuanConfig>().aco.rho, 0.7);
  EXPECT_EQ(r->config_of<DuanConfig>().aco.iterations, 20U);
  EXPECT_NEAR(r->config_of<DuanConfig>().aco.max_turn_rad, std::acos(-1.0) / 4.0, 1e-12);
  EXPECT_TRUE(load_scenario(source_path("scenarios/duan2009-small.textproto")).ok());
}

void expect_duan_error(const std::string& text, int line, const std::string& field) {
  const auto r = parse_scenario(text, "bad-duan.textproto");
  ASSERT_FALSE(r.ok()) << text;
  const std::string& m = r.error().message;
  EXPECT_NE(m.find("bad-duan.textproto:" + std::to_string(line) + ":"), std::string::npos) << m;
  EXPECT_NE(m.find("field '" + field + "'"), std::string::npos) << m;
}

TEST(DuanScenarioFile, ErrorsNameTheLineAndTheField) {
  // Line 4 of small_text is "policy { duan {", the extra lines start at 8.
  expect_duan_error(small_text(2, "  rho: 1.5\n"), 8, "policy.duan.rho");
  expect_duan_error(small_text(2, "  popups { x_km: 1 y_km: 1 radius_km: 2 }\n"), 8, "policy.duan.popups[0].appear_tick");
  expect_duan_error(small_text(2, "  threats { x_km: 1 y_km: 1 radius_km: 2 appear_tick: 3 }\n"), 8,
               "policy.duan.threats[0].appear_tick");
  expect_duan_error(small_text(2, "  threats { x_km: 1 y_km: 1 radius_km: 0 }\n"), 8, "policy.duan.threats[0].radius_km");
  expect_duan_error(small_text(2, "  deposit_rule: \"best\"\n"), 8, "policy.duan.deposit_rule");
  expect_duan_error(small_text(2, "  candidates: 40\n"), 8, "policy.duan.candidates");
  expect_duan_error(small_text(2, "  uavs { start { x: 16 y: 1 } target { x: 2 y: 2 } }\n"), 8,
               "policy.duan.uavs[0].start.x");  // and one entry too many
}

}  // namespace
}  // namespace pheromesh::core
