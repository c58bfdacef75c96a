// Our variant of the Duan 2009 planner, DuanPlanner::LineOfSight (planner
// "line_of_sight", docs/policies/duan.md): Duan 2009 eq. (2) on long segments, the
// line-of-sight shortcut, the Duan 2009 eq. (1) exposure measure, the colony, the Duan 2009 Table 3
// loop and the distributed policy with it. Numbers worked by hand in the comments.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "duan_test_mesh.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/rng.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"
#include "pheromesh/duan/aco.hpp"
#include "pheromesh/duan/experiment.hpp"
#include "pheromesh/duan/policy.hpp"

namespace pheromesh::core {
namespace {

using duan_test::at;
using duan_test::kQuarterPi;
using duan_test::mesh_of;
using duan_test::turns_within;

TEST(DuanLineOfSight, SegmentThreatCostSumsEquationTwoOverPiecesNoLongerThanTheSpacing) {
  const std::vector<Threat> threats{{{0.0, 0.0}, 10.0, 2.0}};
  // One 2 km piece (0, 2) -> (2, 2): 0.8044118 (worked in test_duan_aco.cpp).
  EXPECT_NEAR(segment_threat_cost(threats, {0.0, 2.0}, {2.0, 2.0}, 2.0), 0.8044118, 1e-7);
  // (0, 2) -> (4, 2) is cut into two pieces; the second, (2, 2) -> (4, 2), samples
  // x = 2.2, 2.6, 3.0, 3.4, 3.8: d² = 8.84, 10.76, 13, 15.56, 18.44, Σ 1/d⁴ =
  // 0.0344222, times w = 2 and L = 2: 0.1376889. Together 0.9421007.
  EXPECT_NEAR(segment_threat_cost(threats, {0.0, 2.0}, {4.0, 2.0}, 2.0), 0.9421007, 1e-7);
  // Why the pieces: a small threat at (3, 0.2), radius 0.5, on a 20 km segment
  // along y = 0. Duan 2009 eq. (2) on the whole segment samples x = 2, 6, 10, 14, 18, all
  // outside the radius: 0. Cut into 2 km pieces, the piece (2, 0) -> (4, 0)
  // samples x = 2.6, 3.0, 3.4 inside it: d² = 0.2, 0.04, 0.2, 1/d⁴ = 25 + 625 + 25,
  // times L = 2: 1350.
  const std::vector<Threat> small{{{3.0, 0.2}, 0.5, 1.0}};
  EXPECT_EQ(edge_threat_cost(small, {0.0, 0.0}, {20.0, 0.0}), 0.0);
  EXPECT_NEAR(segment_threat_cost(small, {0.0, 0.0}, {20.0, 0.0}, 2.0), 1350.0, 1e-6);
}

TEST(DuanLineOfSight, PolylineCostOfMeshNeighboursEqualsThePathCost) {
  const ThreatMesh m = mesh_of(10.0, 10.0, {{{4.0, 4.0}, 5.0, 1.5}});
  const std::vector<NodeId> walk{at(m, 0, 0), at(m, 2, 2), at(m, 4, 2), at(m, 6, 4)};
  const auto a = m.path_cost(walk);
  const auto b = polyline_cost(m, walk);
  EXPECT_DOUBLE_EQ(a.length_km, b.length_km);
  EXPECT_DOUBLE_EQ(a.threat, b.threat);
  EXPECT_DOUBLE_EQ(a.cost, b.cost);
  // A long segment: length by Pythagoras, (0, 0) -> (6, 4) = √52 = 7.2111 km.
  const std::vector<NodeId> seg{at(m, 0, 0), at(m, 6, 4)};
  EXPECT_NEAR(polyline_cost(m, seg).length_km, std::sqrt(52.0), duan_test::kEps);
}

TEST(DuanLineOfSight, OnAnOpenMeshAStaircaseBecomesOneStraightSegment) {
  const ThreatMesh m = mesh_of(10.0, 10.0);
  // (0,0) -> (2,0) -> (4,2) -> (6,2) -> (8,4): 2 + 2.828 + 2 + 2.828 = 9.657 km, 45° turns.
  const std::vector<NodeId> walk{at(m, 0, 0), at(m, 2, 0), at(m, 4, 2), at(m, 6, 2), at(m, 8, 4)};
  const auto cut = line_of_sight_shortcut(m, walk, std::nullopt, kQuarterPi);
  EXPECT_EQ(cut, (std::vector<NodeId>{at(m, 0, 0), at(m, 8, 4)}));
  // √80 = 8.944 km; without threats J = 0.25 · L = 2.236 (Duan 2009 eq. (3)) against 2.414 for the walk.
  EXPECT_NEAR(polyline_cost(m, cut).length_km, std::sqrt(80.0), duan_test::kEps);
  EXPECT_NEAR(polyline_cost(m, cut).cost, 0.25 * std::sqrt(80.0), duan_test::kEps);
  EXPECT_NEAR(m.path_cost(walk).cost, 0.25 * (4.0 + 4.0 * std::sqrt(2.0)), duan_test::kEps);
}

TEST(DuanLineOfSight, AShortcutThroughAThreatIsRefused) {
  // The walk goes along y = 0 and up x = 8, 2 km or more from the threat at
  // (4, 2.5) (radius 1.5): no threat cost. The straight line to (8, 4) passes
  // 0.3 km from the centre.
  const std::vector<Threat> threat{{{4.0, 2.5}, 1.5, 100.0}};
  const ThreatMesh m = mesh_of(10.0, 10.0, threat);
  const std::vector<NodeId> walk{at(m, 0, 0), at(m, 2, 0), at(m, 4, 0), at(m, 6, 0), at(m, 8, 2), at(m, 8, 4)};
  ASSERT_EQ(m.path_cost(walk).threat, 0.0);
  const auto cut = line_of_sight_shortcut(m, walk, std::nullopt, kQuarterPi);
  EXPECT_NE(cut, (std::vector<NodeId>{at(m, 0, 0), at(m, 8, 4)}));
  EXPECT_EQ(cut.front(), walk.front());
  EXPECT_EQ(cut.back(), walk.back());
  EXPECT_LE(polyline_cost(m, cut).cost, m.path_cost(walk).cost + duan_test::kEps);
  EXPECT_LT(polyline_cost(m, cut).threat, 1e-6);
  EXPECT_TRUE(turns_within(m, cut, std::nullopt, kQuarterPi));
  // Guard: the same walk on a threat-free mesh is cut to one segment.
  const ThreatMesh open = mesh_of(10.0, 10.0);
  EXPECT_EQ(line_of_sight_shortcut(open, walk, std::nullopt, kQuarterPi).size(), 2U);
}

TEST(DuanLineOfSight, TheTurnLimitHoldsAgainstThePreviousNode) {
  const ThreatMesh m = mesh_of(10.0, 10.0);
  // Heading east at (2, 0) (previous node (0, 0)); walk (2,0) (4,0) (6,2) (6,4) (6,6).
  const std::vector<NodeId> walk{at(m, 2, 0), at(m, 4, 0), at(m, 6, 2), at(m, 6, 4), at(m, 6, 6)};
  // Free start: straight to (6, 6).
  EXPECT_EQ(line_of_sight_shortcut(m, walk, std::nullopt, kQuarterPi), (std::vector<NodeId>{at(m, 2, 0), at(m, 6, 6)}));
  // From heading east, (2,0) -> (6,6) turns atan(6/4) = 56.3° > 45°: refused;
  // (2,0) -> (6,4) turns 45°, then north at (6,4) turns 45°: kept.
  const auto cut = line_of_sight_shortcut(m, walk, at(m, 0, 0), kQuarterPi);
  EXPECT_EQ(cut, (std::vector<NodeId>{at(m, 2, 0), at(m, 6, 4), at(m, 6, 6)}));
  EXPECT_TRUE(turns_within(m, cut, at(m, 0, 0), kQuarterPi));
}

TEST(DuanLineOfSight, ExposureIsTheMidpointRuleOfEquationOne) {
  const std::vector<Threat> threats{{{0.0, 0.0}, 10.0, 1.0}};
  // (1, 0) -> (3, 0) in 1 km pieces: midpoints 1.5 and 2.5 km: 1/1.5⁴ + 1/2.5⁴ = 0.2231309.
  const std::vector<PointKm> line{{1.0, 0.0}, {3.0, 0.0}};
  EXPECT_NEAR(threat_exposure(threats, line, 1.0), 0.2231309, 1e-7);
  // Finer pieces approach ∫_1^3 x⁻⁴ dx = (1 - 1/27) / 3 = 0.3209877.
  EXPECT_NEAR(threat_exposure(threats, line, 0.001), 0.3209877, 1e-5);
}

TEST(DuanLineOfSight, ColonyWithTheSameSeedNeverDoesWorseThanThePapersAndGoesStraightOnAnOpenMesh) {
  const ThreatMesh m = mesh_of(20.0, 20.0, {{{10.0, 10.0}, 3.0, 2.0}});
  DuanAcoParams paper;
  paper.ants = 8;
  paper.iterations = 6;
  DuanAcoParams los = paper;
  los.planner = DuanPlanner::LineOfSight;
  DuanColony a(m, paper, Rng(11)), b(m, los, Rng(11));
  const PointPheromone none;
  const PathResult ra = a.plan(at(m, 0, 2), at(m, 18, 20), none);
  const PathResult rb = b.plan(at(m, 0, 2), at(m, 18, 20), none);
  ASSERT_TRUE(ra.found);
  ASSERT_TRUE(rb.found);
  // Same draws, same walks (the pheromone is the paper's): every shortcut costs no more.
  EXPECT_LE(rb.best.cost, ra.best.cost + duan_test::kEps);
  EXPECT_EQ(rb.best.nodes.front(), at(m, 0, 2));
  EXPECT_EQ(rb.best.nodes.back(), at(m, 18, 20));
  EXPECT_TRUE(turns_within(m, rb.best.nodes, std::nullopt, kQuarterPi));
  for (std::size_t k = 0; k < ra.best_cost_history.size(); ++k) {
    EXPECT_LE(rb.best_cost_history[k], ra.best_cost_history[k] + duan_test::kEps);
  }
  // Without threats the best candidate is the straight line (0, 2) -> (18, 20).
  const ThreatMesh open = mesh_of(20.0, 20.0);
  DuanColony c(open, los, Rng(11));
  const PathResult rc = c.plan(at(open, 0, 2), at(open, 18, 20), none);
  ASSERT_TRUE(rc.found);
  EXPECT_EQ(rc.best.nodes.size(), 2U);
  EXPECT_NEAR(rc.best.length_km, 18.0 * std::sqrt(2.0), duan_test::kEps);
}

TEST(DuanLineOfSight, TableThreeLoopReplansFromAMeshNodeJustAheadOnTheSegment) {
  Duan2009Scenario sc;
  sc.mesh = MeshSpec{{0.0, 0.0}, 20.0, 20.0, 10, 10, kDuanThreatWeight};
  sc.threats = {Threat{{8.0, 8.0}, 3.0, 2.0}};
  sc.uavs = {Duan2009Uav{{0.0, 0.0}, {16.0, 14.0}}, Duan2009Uav{{0.0, 4.0}, {14.0, 16.0}}};
  sc.popups = {Threat{{10.0, 10.0}, 2.0, 10.0}};
  sc.aco.ants = 8;
  sc.aco.iterations = 6;
  sc.aco.planner = DuanPlanner::LineOfSight;
  DuanTable3Options options;
  options.runs = 2;
  options.popup_time_s = 10.0;
  const DuanTable3Result res = duan_table3(sc, options);
  const ThreatMesh mesh(sc.mesh, sc.threats);
  for (const DuanTable3Run& run : res.runs) {
    ASSERT_TRUE(run.eta_found);
    ASSERT_EQ(run.eta_history.size(), sc.aco.iterations);
    EXPECT_DOUBLE_EQ(run.eta_history.back(), run.plan.eta_s);
    for (const DuanTable3Uav& u : run.uavs) {
      // The position at popup_time_s is at_km along the trajectory; the
      // replanning node is at most one spacing ahead plus half a diagonal off it.
      const double at_km = u.speed_mps * options.popup_time_s / 1000.0;
      EXPECT_NEAR(u.flown_km, at_km + u.offset_km, 1e-9);
      EXPECT_LE(u.offset_km, 2.0 + std::sqrt(2.0) + duan_test::kEps);
      ASSERT_GE(u.flown.size(), 2U);
      EXPECT_EQ(u.replanned_nodes.front(), u.flown.back());
    }
  }
}

TEST(DuanLineOfSight, ScenarioSelectsThePlannerAndTheDistributedTeamArrivesTogether) {
  const std::string text =
      "map { width: 16 height: 16 tile_size: 4 regions_x: 2 regions_y: 2 }\n"
      "swarm { uavs: 3 }\nrun { ticks: 80 seed: 3 }\n"
      "policy { duan {\n  iterations: 5\n  ants: 6\n  dt_s: 4\n  planner: \"line_of_sight\"\n"
      "  popups { x_km: 12 y_km: 14 radius_km: 4 grade: 2.5 appear_tick: 9 }\n"
      "  uavs { start { x: 1 y: 1 } target { x: 2 y: 13 } }\n"
      "  uavs { start { x: 8 y: 1 } target { x: 9 y: 14 } }\n"
      "  uavs { start { x: 13 y: 2 } target { x: 12 y: 14 } }\n} }\n";
  const auto r = parse_scenario(text, "los.textproto");
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->config_of<DuanConfig>().aco.planner, DuanPlanner::LineOfSight);
  const ScenarioConfig s = r.value();
  Simulator sim(s);
  sim.run();
  const auto f = field_summary(s, [&](int l, Cell c) { return sim.field_value(l, c); });
  EXPECT_EQ(f.at("arrived"), 3.0);
  EXPECT_NEAR(f.at("arrival_spread_s"), 0.0, 1e-3);
  // UAV 1 flies (2, 2) -> (4, 26) km: its straight line is 24.08 km; a mesh walk is longer.
  EXPECT_GE(f.at("uav1_planned_km"), std::hypot(2.0, 24.0) - 1e-3);

  std::string bad = text;
  bad.replace(bad.find("line_of_sight"), 13, "dijkstra");
  const auto e = parse_scenario(bad, "los.textproto");
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.error().message.find("los.textproto:8:"), std::string::npos) << e.error().message;
  EXPECT_NE(e.error().message.find("policy.duan.planner"), std::string::npos) << e.error().message;
}

}  // namespace
}  // namespace pheromesh::core
