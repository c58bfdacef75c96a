// Duan 2009 Table 3 experiment as a library: the turn-constrained optimum on
// meshes small enough to work by hand, and the Monte Carlo loop on a tiny
// scenario.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <vector>

#include "duan_paths.hpp"
#include "pheromesh/duan/aco.hpp"
#include "pheromesh/duan/experiment.hpp"
#include "unit_support.hpp"

namespace pheromesh::core {
namespace {

using test::kEps;
constexpr double kQuarterTurn = std::numbers::pi / 2.0;
constexpr double kEighthTurn = std::numbers::pi / 4.0;
const double kSqrt2 = std::numbers::sqrt2;

// 3 x 3 nodes, 2 km apart: node(ix, iy) sits at (2·ix, 2·iy) km.
MeshSpec three_by_three() { return MeshSpec{{0.0, 0.0}, 4.0, 4.0, 2, 2, kDuanThreatWeight}; }

// A threat on the centre node (2, 2) km with a 1.5 km range. Which edges it
// touches (Duan 2009 eq. (2) samples at 1/10, 3/10, ..., 9/10 of an edge):
//  * the 8 border edges (2 km, along x = 0, x = 4, y = 0, y = 4) stay >= 2 km
//    away: J_threat = 0, so J = 0.25 · 2 = 0.5 each;
//  * edges into the centre node come within 1e-3 km (floor): huge cost;
//  * a corner-cutting diagonal such as (2, 0) -> (4, 2) km is √2 km from the
//    centre at its midpoint only (the 3/10 and 7/10 points are 1.523 km away),
//    so J_threat = L · 1/(√2)^4 = 2√2 / 4 = √2 / 2 and J = 0.75 · √2/2 + 0.25 · 2√2.
// So the only threat-free way round is the ring of border edges, whose corners
// are 90° turns.
ThreatMesh ring_mesh() { return ThreatMesh(three_by_three(), {Threat{{2.0, 2.0}, 1.5, 1.0}}); }

using testing_duan::max_turn_of;

bool contains(const std::vector<NodeId>& nodes, NodeId n) { return std::find(nodes.begin(), nodes.end(), n) != nodes.end(); }

TEST(DuanTurnConstrainedOptimum, OnAnOpenMeshIsTheStraightDiagonal) {
  const ThreatMesh mesh(three_by_three());
  const DuanOptimum o = duan_turn_constrained_optimum(mesh, mesh.node(0, 0), mesh.node(2, 2), kEighthTurn);
  ASSERT_TRUE(o.found);
  // Two diagonal edges of 2√2 km, no threat: J = 0.25 · 4√2 = √2.
  EXPECT_NEAR(o.length_km, 4.0 * kSqrt2, kEps);
  EXPECT_NEAR(o.cost, kSqrt2, kEps);
  EXPECT_EQ(o.nodes, (std::vector<NodeId>{mesh.node(0, 0), mesh.node(1, 1), mesh.node(2, 2)}));
}

TEST(DuanTurnConstrainedOptimum, WithRightAnglesAllowedGoesRoundTheThreatOnTheRing) {
  const ThreatMesh mesh = ring_mesh();
  const DuanOptimum o = duan_turn_constrained_optimum(mesh, mesh.node(0, 0), mesh.node(2, 2), kQuarterTurn);
  ASSERT_TRUE(o.found);
  // Four border edges: 8 km, J = 4 · 0.5 = 2, one 90° turn at a corner.
  EXPECT_NEAR(o.length_km, 8.0, kEps);
  EXPECT_NEAR(o.cost, 2.0, kEps);
  ASSERT_EQ(o.nodes.size(), 5U);
  EXPECT_FALSE(contains(o.nodes, mesh.node(1, 1)));
  EXPECT_TRUE(contains(o.nodes, mesh.node(2, 0)) || contains(o.nodes, mesh.node(0, 2)));
  EXPECT_NEAR(max_turn_of(mesh, o.nodes), kQuarterTurn, kEps);
  EXPECT_NEAR(mesh.path_cost(o.nodes).cost, o.cost, kEps);
}

TEST(DuanTurnConstrainedOptimum, WithTheFortyFiveDegreeLimitCutsACornerInsteadOfTurningNinetyDegrees) {
  const ThreatMesh mesh = ring_mesh();
  const DuanOptimum o = duan_turn_constrained_optimum(mesh, mesh.node(0, 0), mesh.node(2, 2), kEighthTurn);
  ASSERT_TRUE(o.found);
  // The ring's corner turn is forbidden; the cheapest walk has one
  // corner-cutting diagonal: E, NE, N (or N, NE, E), 2 + 2√2 + 2 km,
  // J = 0.25 · (4 + 2√2) + 0.75 · √2/2 = 1 + √2/2 + 3√2/8 = 2.23744.
  EXPECT_NEAR(o.length_km, 4.0 + 2.0 * kSqrt2, kEps);
  EXPECT_NEAR(o.cost, 1.0 + kSqrt2 / 2.0 + 3.0 * kSqrt2 / 8.0, kEps);
  EXPECT_GT(o.cost, 2.0);  // dearer than the ring it may not fly
  ASSERT_EQ(o.nodes.size(), 4U);
  EXPECT_LE(max_turn_of(mesh, o.nodes), kEighthTurn + kEps);
  EXPECT_FALSE(contains(o.nodes, mesh.node(2, 0)));  // neither 90° corner
  EXPECT_FALSE(contains(o.nodes, mesh.node(0, 2)));
  EXPECT_NEAR(mesh.path_cost(o.nodes).cost, o.cost, kEps);
}

TEST(DuanTurnConstrainedOptimum, ReportsAGoalThatNoAllowedWalkReaches) {
  const ThreatMesh mesh(three_by_three());
  // With no turn allowed a walk is one straight ray from the start; node (1, 2)
  // lies on none of (0, 0)'s rays (E, NE, N).
  const DuanOptimum straight = duan_turn_constrained_optimum(mesh, mesh.node(0, 0), mesh.node(1, 2), 0.0);
  EXPECT_FALSE(straight.found);
  EXPECT_TRUE(std::isinf(straight.cost));
  EXPECT_TRUE(straight.nodes.empty());
  // Guard: with 45° turns it is one diagonal and one straight edge, 2 + 2√2 km.
  const DuanOptimum turned = duan_turn_constrained_optimum(mesh, mesh.node(0, 0), mesh.node(1, 2), kEighthTurn);
  ASSERT_TRUE(turned.found);
  EXPECT_NEAR(turned.length_km, 2.0 + 2.0 * kSqrt2, kEps);
  EXPECT_NEAR(turned.cost, 0.25 * (2.0 + 2.0 * kSqrt2), kEps);
  // A node off the mesh is not found either.
  EXPECT_FALSE(duan_turn_constrained_optimum(mesh, mesh.node(0, 0), 9, kEighthTurn).found);
}

TEST(DuanLastImprovement, IsTheOneBasedIterationOfTheLastDrop) {
  const double inf = std::numeric_limits<double>::infinity();
  // Drops at iterations 2 (inf -> 5) and 4 (5 -> 3): the last is 4.
  EXPECT_EQ(duan_last_improvement({inf, 5.0, 5.0, 3.0, 3.0}), 4.0);
  EXPECT_EQ(duan_last_improvement({7.0, 7.0, 7.0}), 1.0);
  EXPECT_EQ(duan_last_improvement({}), 1.0);
}

TEST(DuanEtaCandidates, AddEachUavsOffsetToItsCandidateLengths) {
  PathResult a, b;
  a.candidates = {Trajectory{{}, 10.0, 0.0, 3.0}, Trajectory{{}, 12.0, 0.0, 4.0}};
  b.candidates = {Trajectory{{}, 20.0, 0.0, 5.0}};
  const auto c = duan_eta_candidates({a, b}, {0.5, 1.5});
  ASSERT_EQ(c.size(), 2U);
  ASSERT_EQ(c[0].size(), 2U);
  EXPECT_DOUBLE_EQ(c[0][0].length_km, 10.5);
  EXPECT_DOUBLE_EQ(c[0][1].length_km, 12.5);
  EXPECT_DOUBLE_EQ(c[0][1].cost, 4.0);
  ASSERT_EQ(c[1].size(), 1U);
  EXPECT_DOUBLE_EQ(c[1][0].length_km, 21.5);
}

// Two UAVs crossing a 16 x 16 km mesh past one threat, a pop-up in the middle,
// small colonies so the test is quick.
Duan2009Scenario tiny_scenario() {
  Duan2009Scenario sc;
  sc.mesh = MeshSpec{{0.0, 0.0}, 16.0, 16.0, 8, 8, kDuanThreatWeight};
  sc.threats = {Threat{{8.0, 6.0}, 3.0, 10.0}};
  sc.uavs = {Duan2009Uav{{0.0, 0.0}, {16.0, 14.0}}, Duan2009Uav{{0.0, 4.0}, {14.0, 16.0}}};
  sc.popups = {Threat{{10.0, 10.0}, 2.0, 10.0}};
  sc.aco.ants = 8;
  sc.aco.iterations = 6;
  return sc;
}

double mesh_length(const Duan2009Scenario& sc, const std::vector<NodeId>& nodes) {
  return ThreatMesh(sc.mesh).path_cost(nodes).length_km;
}

double straight_km(const Duan2009Uav& u) { return std::hypot(u.target.x - u.start.x, u.target.y - u.start.y); }

TEST(DuanTable3, TinyScenarioIsRepeatableAndConsistentWithThePlannerAndTheEta) {
  const Duan2009Scenario sc = tiny_scenario();
  DuanTable3Options options;
  options.runs = 3;
  options.popup_time_s = 10.0;  // 2-3 km flown: still far from the goals
  std::vector<uint32_t> progress;
  const DuanTable3Result a = duan_table3(sc, options, [&](uint32_t done, uint32_t total) {
    EXPECT_EQ(total, 3U);
    progress.push_back(done);
  });
  const DuanTable3Result b = duan_table3(sc, options);
  EXPECT_EQ(progress, (std::vector<uint32_t>{1, 2, 3}));

  ASSERT_EQ(a.optimum.size(), 2U);
  for (std::size_t i = 0; i < 2; ++i) {
    ASSERT_TRUE(a.optimum[i].found);
    EXPECT_GE(a.optimum[i].length_km, straight_km(sc.uavs[i]) - kEps);
  }
  ASSERT_EQ(a.runs.size(), 3U);
  ASSERT_EQ(b.runs.size(), 3U);
  uint32_t replanned_runs = 0;
  for (std::size_t r = 0; r < a.runs.size(); ++r) {
    const DuanTable3Run& run = a.runs[r];
    EXPECT_EQ(run.seed, r + 1);
    // Same seed, same numbers.
    EXPECT_EQ(run.eta_found, b.runs[r].eta_found);
    EXPECT_EQ(run.plan.eta_s, b.runs[r].plan.eta_s);
    EXPECT_EQ(run.eta_after_replan_s, b.runs[r].eta_after_replan_s);
    ASSERT_EQ(run.uavs.size(), 2U);
    if (!run.eta_found) continue;
    for (std::size_t i = 0; i < 2; ++i) {
      const DuanTable3Uav& u = run.uavs[i];
      EXPECT_EQ(u.length_km, b.runs[r].uavs[i].length_km);
      EXPECT_EQ(u.flown, b.runs[r].uavs[i].flown);
      EXPECT_EQ(u.replanned_nodes, b.runs[r].uavs[i].replanned_nodes);
      // A colony walk obeys the same turn limit on the same costs: never cheaper than J*.
      EXPECT_GE(u.cost_over_optimum, 1.0 - kEps);
      EXPECT_GE(u.length_km, straight_km(sc.uavs[i]) - kEps);
      // V = L / T_a within the speed limits (Duan 2009 eq. (4)).
      EXPECT_NEAR(u.speed_mps, 1000.0 * u.length_km / run.plan.eta_s, 1e-6);
      EXPECT_GE(u.speed_mps, sc.speeds.min_mps - 1e-6);
      EXPECT_LE(u.speed_mps, sc.speeds.max_mps + 1e-6);
      EXPECT_GE(u.last_improvement, 1.0);
      EXPECT_LE(u.last_improvement, static_cast<double>(sc.aco.iterations));
      // The flown part is the start of the planned trajectory, ending where the replanning starts.
      const auto& planned = u.planned.candidates[run.plan.chosen[i]].nodes;
      ASSERT_GE(u.flown.size(), 2U);
      EXPECT_TRUE(std::equal(u.flown.begin(), u.flown.end(), planned.begin()));
      // Replanning starts at the first node at or past the position at popup_time_s.
      const double at_km = u.speed_mps * options.popup_time_s / 1000.0;
      EXPECT_GE(u.flown_km, at_km - kEps);
      EXPECT_NEAR(u.offset_km, u.flown_km - at_km, kEps);
      EXPECT_NEAR(mesh_length(sc, u.flown), u.flown_km, kEps);
    }
    if (!run.replan_eta_found) continue;
    ++replanned_runs;
    EXPECT_DOUBLE_EQ(run.eta_after_replan_s, options.popup_time_s + run.replan.eta_s);
    double new_threat = 0.0;
    for (std::size_t i = 0; i < 2; ++i) {
      const DuanTable3Uav& u = run.uavs[i];
      ASSERT_FALSE(u.replanned_nodes.empty());
      EXPECT_EQ(u.replanned_nodes.front(), u.flown.back());
      EXPECT_EQ(u.replanned_nodes.back(), u.planned.best.nodes.back());  // same goal
      EXPECT_GE(u.length_after_replan_km, straight_km(sc.uavs[i]) - kEps);
      new_threat += u.replanned.candidates[run.replan.chosen[i]].threat_cost;
    }
    EXPECT_DOUBLE_EQ(run.new_threat_sum, new_threat);
    EXPECT_DOUBLE_EQ(run.old_threat_sum, run.uavs[0].old_remaining_threat + run.uavs[1].old_remaining_threat);
  }
  EXPECT_GT(replanned_runs, 0U);  // the checks above were not all skipped
}

}  // namespace
}  // namespace pheromesh::core
