// Our second variant of the Duan 2009 planner, DuanPlanner::SafeLineOfSight
// (planner "safe_line_of_sight", docs/policies/duan.md): a walk is shortcut by
// a straight segment only if the segment raises neither Duan 2009 eq. (3)'s J
// nor Duan 2009 eq. (1)'s exposure. Numbers worked by hand in the comments.
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

std::vector<PointKm> points(const ThreatMesh& m, const std::vector<NodeId>& nodes) {
  std::vector<PointKm> p;
  for (const NodeId n : nodes) p.push_back(m.position(n));
  return p;
}

double exposure(const ThreatMesh& m, const std::vector<NodeId>& nodes) {
  return threat_exposure(m.threats(), points(m, nodes), kSafeShortcutExposureStepKm);
}

bool turns_within(const ThreatMesh& m, const std::vector<NodeId>& p, double limit) {
  return duan_test::turns_within(m, p, std::nullopt, limit);
}

TEST(DuanSafeLineOfSight, AShortcutThatIsCheaperButMoreExposedIsRefused) {
  // Threat at (4, 4.5), radius 2.5, grade 1. The walk (0,0) (2,0) (4,0) (6,0)
  // (8,2) (8,4) keeps at least 4.03 km from it: exposure 0, J = 0.25 · (6 +
  // 2√2 + 2) = 2.707. The straight line (0,0) -> (8,4) (x = 2y) passes
  // h = 5/√5 = √5 km from the centre: a chord of 2·√(6.25 − 5) = 2.236 km
  // inside the range. Exposure ∫ ds / (h² + s²)² over s ∈ [−1.118, 1.118]
  // = 2 · [s / (2h²(h² + s²)) + atan(s/h) / (2h³)] = 2 · (0.017889 + 0.020735)
  // = 0.07725. Its J = 0.75 · J_threat + 0.25 · √80 is below 2.707, so
  // line_of_sight takes it.
  const ThreatMesh m = mesh_of(10.0, 10.0, {{{4.0, 4.5}, 2.5, 1.0}});
  const std::vector<NodeId> walk{at(m, 0, 0), at(m, 2, 0), at(m, 4, 0), at(m, 6, 0), at(m, 8, 2), at(m, 8, 4)};
  ASSERT_EQ(exposure(m, walk), 0.0);
  ASSERT_NEAR(m.path_cost(walk).cost, 0.25 * (8.0 + 2.0 * std::sqrt(2.0)), duan_test::kEps);

  const auto los = line_of_sight_shortcut(m, walk, std::nullopt, kQuarterPi);
  ASSERT_EQ(los, (std::vector<NodeId>{at(m, 0, 0), at(m, 8, 4)}));
  EXPECT_LT(polyline_cost(m, los).cost, m.path_cost(walk).cost);
  EXPECT_NEAR(exposure(m, los), 0.07725, 2e-3);

  // The safe shortcut refuses it. From (0,0): (8,4) raises the exposure;
  // (8,2) turns 76° there; (6,0) costs the same as the walk's stretch and
  // turns 45° into (8,2): taken. From (6,0), heading east, (8,4) turns 63°:
  // the walk's own edges remain.
  const auto safe = safe_line_of_sight_shortcut(m, walk, std::nullopt, kQuarterPi);
  EXPECT_EQ(safe, (std::vector<NodeId>{at(m, 0, 0), at(m, 6, 0), at(m, 8, 2), at(m, 8, 4)}));
  EXPECT_EQ(exposure(m, safe), 0.0);
  EXPECT_NEAR(polyline_cost(m, safe).cost, m.path_cost(walk).cost, duan_test::kEps);

  // Guard: without the threat both shortcuts are the one straight segment.
  const ThreatMesh open = mesh_of(10.0, 10.0);
  EXPECT_EQ(safe_line_of_sight_shortcut(open, walk, std::nullopt, kQuarterPi),
            (std::vector<NodeId>{at(open, 0, 0), at(open, 8, 4)}));
}

TEST(DuanSafeLineOfSight, AShortcutThatLeavesAThreatsRangeIsTaken) {
  // The walk (0,0) (2,2) (4,2) (6,2) (8,0) runs along y = 2, 1.5 km from a
  // threat at (4, 3.5) (radius 2.5): exposed. The straight line y = 0 keeps
  // 3.5 km from it (exposure 0) and is shorter (8 km against 4 + 4√2 =
  // 9.657 km), so both J and exposure fall: taken.
  const ThreatMesh m = mesh_of(10.0, 10.0, {{{4.0, 3.5}, 2.5, 1.0}});
  const std::vector<NodeId> walk{at(m, 0, 0), at(m, 2, 2), at(m, 4, 2), at(m, 6, 2), at(m, 8, 0)};
  ASSERT_GT(exposure(m, walk), 0.0);
  const auto safe = safe_line_of_sight_shortcut(m, walk, std::nullopt, kQuarterPi);
  EXPECT_EQ(safe, (std::vector<NodeId>{at(m, 0, 0), at(m, 8, 0)}));
  EXPECT_EQ(exposure(m, safe), 0.0);
  EXPECT_NEAR(polyline_cost(m, safe).cost, 0.25 * 8.0, duan_test::kEps);
}

TEST(DuanSafeLineOfSight, EveryCandidateOfTheColonyIsNoCostlierAndNoMoreExposedThanItsWalk) {
  // A paper colony's walks, then each walk through the safe shortcut: J and
  // exposure never rise and the turn limit holds. The shortcut must also
  // shorten some walk here (the threat sits between start and goal).
  const ThreatMesh m = mesh_of(30.0, 30.0, {{{14.0, 15.0}, 6.0, 2.0}, {{22.0, 8.0}, 4.0, 1.0}});
  DuanAcoParams paper;
  paper.ants = 10;
  paper.iterations = 8;
  DuanColony colony(m, paper, Rng(5));
  const PathResult r = colony.plan(at(m, 0, 0), at(m, 28, 30), PointPheromone{});
  ASSERT_TRUE(r.found);
  ASSERT_FALSE(r.candidates.empty());
  bool shortened = false;
  for (const Trajectory& t : r.candidates) {
    const auto safe = safe_line_of_sight_shortcut(m, t.nodes, std::nullopt, kQuarterPi);
    EXPECT_EQ(safe.front(), t.nodes.front());
    EXPECT_EQ(safe.back(), t.nodes.back());
    EXPECT_LE(polyline_cost(m, safe).cost, t.cost + duan_test::kEps);
    EXPECT_LE(exposure(m, safe), exposure(m, t.nodes) * (1.0 + 1e-9) + 1e-12);
    EXPECT_TRUE(turns_within(m, safe, kQuarterPi));
    shortened = shortened || polyline_cost(m, safe).length_km < t.length_km - 1e-6;
  }
  EXPECT_TRUE(shortened);

  // The colony with the planner offers such shortcuts as its candidates.
  DuanAcoParams safe_params = paper;
  safe_params.planner = DuanPlanner::SafeLineOfSight;
  DuanColony safe_colony(m, safe_params, Rng(5));
  const PathResult s = safe_colony.plan(at(m, 0, 0), at(m, 28, 30), PointPheromone{});
  ASSERT_TRUE(s.found);
  EXPECT_LE(s.best.cost, r.best.cost + duan_test::kEps);
  EXPECT_TRUE(turns_within(m, s.best.nodes, kQuarterPi));
}

TEST(DuanSafeLineOfSight, ScenarioSelectsThePlannerAndTheDistributedTeamArrivesTogether) {
  const std::string text =
      "map { width: 16 height: 16 tile_size: 4 regions_x: 2 regions_y: 2 }\n"
      "swarm { uavs: 3 }\nrun { ticks: 80 seed: 3 }\n"
      "policy { duan {\n  iterations: 5\n  ants: 6\n  dt_s: 4\n  planner: \"safe_line_of_sight\"\n"
      "  threats { x_km: 10 y_km: 14 radius_km: 5 grade: 1.5 }\n"
      "  popups { x_km: 12 y_km: 14 radius_km: 4 grade: 2.5 appear_tick: 9 }\n"
      "  uavs { start { x: 1 y: 1 } target { x: 2 y: 13 } }\n"
      "  uavs { start { x: 8 y: 1 } target { x: 9 y: 14 } }\n"
      "  uavs { start { x: 13 y: 2 } target { x: 12 y: 14 } }\n} }\n";
  const auto r = parse_scenario(text, "safe.textproto");
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->config_of<DuanConfig>().aco.planner, DuanPlanner::SafeLineOfSight);
  const ScenarioConfig s = r.value();
  Simulator sim(s);
  sim.run();
  const auto f = field_summary(s, [&](int l, Cell c) { return sim.field_value(l, c); });
  EXPECT_EQ(f.at("arrived"), 3.0);
  EXPECT_NEAR(f.at("arrival_spread_s"), 0.0, 1e-3);
  EXPECT_GE(f.at("uav1_planned_km"), std::hypot(2.0, 24.0) - 1e-3);
}

}  // namespace
}  // namespace pheromesh::core
