// shao_search_frontier (ours, docs/policies/shao.md): the nearest unvisited
// cell and the forward step towards it, worked by hand on tiny grids; the
// variant and the "mark on arrival" reading of Shao 2020 Algorithm 1 line 4 in the
// simulator; the scenario fields that select them.
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "pheromesh/core/layers.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"
#include "pheromesh/shao/aco.hpp"
#include "pheromesh/shao/policy.hpp"

using namespace pheromesh::core;

namespace {

VisitedMap all_visited(int32_t w, int32_t h) {
  VisitedMap m;
  m.width = w;
  m.height = h;
  m.visited.assign(static_cast<std::size_t>(w * h), 1);
  return m;
}
void set_unvisited(VisitedMap& m, Cell c) { m.visited[static_cast<std::size_t>(c.y * m.width + c.x)] = 0; }

std::function<bool(Cell)> blocking(std::vector<Cell> cells) {
  return [cells](Cell c) {
    for (const Cell& b : cells) {
      if (b.x == c.x && b.y == c.y) return true;
    }
    return false;
  };
}

// A one-region map with one UAV at `start`, sensor radius `sd` = D0 (as in
// Shao 2020 Table 1, where both are 4), and the given policy lines (text, so the
// scenario is what a file would give).
ScenarioConfig tiny(const std::string& policy, Cell start, int32_t w, int32_t h, double sd,
                    const std::string& extra = "") {
  const std::string text = "name: \"tiny\" map { width: " + std::to_string(w) + " height: " + std::to_string(h) +
                           " tile_size: " + std::to_string(h) + " regions_x: 1 regions_y: 1 " + extra +
                           " } swarm { uavs: 1 start_area { x: " + std::to_string(start.x) +
                           " y: " + std::to_string(start.y) +
                           " w: 1 h: 1 } } run { ticks: 40 seed: 3 } shao { layers { d0: " + std::to_string(sd) +
                           " } aco { sensor_radius: " + std::to_string(sd) + " revisit_period: 1000 } } " + policy;
  auto s = parse_scenario(text, "tiny");
  EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
  return s.value();
}

}  // namespace

TEST(ShaoFrontier, TheNearestUnvisitedCellIsFoundByEightConnectedSteps) {
  // 5 x 5, all visited but (4, 0) (4 steps east: Chebyshev 4) and (0, 4)
  // (4 steps north). From (0, 0) both are 4 steps away; breadth-first order
  // with neighbours E, NE, N, ... reaches (4, 0)'s row first: it wins.
  VisitedMap m = all_visited(5, 5);
  set_unvisited(m, {4, 0});
  set_unvisited(m, {0, 4});
  EXPECT_EQ(nearest_unvisited({0, 0}, m, blocking({})), (Cell{4, 0}));
  // From (1, 3): (0, 4) is 1 step (NW), (4, 0) 3: the near one.
  EXPECT_EQ(nearest_unvisited({1, 3}, m, blocking({})), (Cell{0, 4}));
  // A wall x = 2 for y = 0..3: (4, 0) now needs 8 steps round its end at
  // (2, 4) — (1,1) (1,2) (1,3) (2,4) (3,3) (4,2) (4,1) (4,0) — and (0, 4)
  // still 4: (0, 4) wins.
  EXPECT_EQ(nearest_unvisited({0, 0}, m, blocking({{2, 0}, {2, 1}, {2, 2}, {2, 3}})), (Cell{0, 4}));
  // Nothing unvisited reachable: nullopt.
  const VisitedMap done = all_visited(5, 5);
  EXPECT_EQ(nearest_unvisited({2, 2}, done, blocking({})), std::nullopt);
  VisitedMap walled = all_visited(5, 5);
  set_unvisited(walled, {4, 4});
  EXPECT_EQ(nearest_unvisited({0, 0}, walled, blocking({{3, 4}, {3, 3}, {4, 3}})), std::nullopt);
}

TEST(ShaoFrontier, TheStepThatSeesTheMostNewCellsIsWorkedOutByHand) {
  // 7 x 3, columns 0-2 visited, 3-6 not; sensor radius 1 (the cell and its
  // 4 edge neighbours). At (2, 1) heading E the candidates are S (2,0),
  // SE (3,0), E (3,1), NE (3,2), N (2,2); new cells in range of each:
  // S {(3,0)} 1, SE {(3,0),(4,0),(3,1)} 3, E {(3,1),(4,1),(3,0),(3,2)} 4,
  // NE 3, N 1.
  VisitedMap m = all_visited(7, 3);
  for (int32_t y = 0; y < 3; ++y) {
    for (int32_t x = 3; x < 7; ++x) set_unvisited(m, {x, y});
  }
  EXPECT_EQ(coverage_gain({2, 0}, m, 1), 1);
  EXPECT_EQ(coverage_gain({3, 0}, m, 1), 3);
  EXPECT_EQ(coverage_gain({3, 1}, m, 1), 4);
  EXPECT_EQ(coverage_gain({3, 2}, m, 1), 3);
  EXPECT_EQ(coverage_candidate({2, 1}, Heading::E, m, 1, blocking({})), std::optional<std::size_t>{2});
  // E blocked: SE and NE tie at 3, same |turn|: the clockwise SE.
  EXPECT_EQ(coverage_candidate({2, 1}, Heading::E, m, 1, blocking({{3, 1}})), std::optional<std::size_t>{1});
  // Nothing new anywhere: no candidate (the caller flies to the nearest unvisited cell).
  EXPECT_EQ(coverage_candidate({2, 1}, Heading::E, all_visited(7, 3), 1, blocking({})), std::nullopt);
}

TEST(ShaoFrontier, TheForwardStepTowardsTheGoalIsWorkedOutByHand) {
  // At (2, 2) heading E (N is +y): candidates 0..4 = S (2,1), SE (3,1),
  // E (3,2), NE (3,3), N (2,3).
  // Goal (2, 4): steps from each: S 3, SE 3, E 2, NE 1, N 1. NE and N tie
  // at 1; the smaller turn (NE, +45°) wins.
  EXPECT_EQ(frontier_candidate({2, 2}, Heading::E, {2, 4}, 5, 5, blocking({})), std::optional<std::size_t>{3});
  // With (3, 3) blocked NE is out: N.
  EXPECT_EQ(frontier_candidate({2, 2}, Heading::E, {2, 4}, 5, 5, blocking({{3, 3}})), std::optional<std::size_t>{4});
  // Goal (0, 2), behind: S 2, SE 3, E 3, NE 3, N 2; S and N tie at 2 with
  // the same |turn|: the clockwise turn (S) wins.
  EXPECT_EQ(frontier_candidate({2, 2}, Heading::E, {0, 2}, 5, 5, blocking({})), std::optional<std::size_t>{0});
  // Straight ahead: E.
  EXPECT_EQ(frontier_candidate({2, 2}, Heading::E, {4, 2}, 5, 5, blocking({})), std::optional<std::size_t>{2});
  // Every forward cell blocked: no step.
  EXPECT_EQ(frontier_candidate({2, 2}, Heading::E, {4, 2}, 5, 5, blocking({{2, 1}, {3, 1}, {3, 2}, {3, 3}, {2, 3}})),
            std::nullopt);
  // A goal walled off: no step.
  EXPECT_EQ(frontier_candidate({0, 0}, Heading::E, {4, 4}, 5, 5, blocking({{3, 4}, {3, 3}, {4, 3}})), std::nullopt);
}

TEST(ShaoFrontier, TheScenarioSelectsTheRouteAndTheMarkingAndRejectsOtherNames) {
  EXPECT_EQ(shao_route(tiny("", {0, 0}, 12, 4, 1)), ShaoRoute::Pheromone);
  const ScenarioConfig f = tiny(R"(policy { shao_search { search: "frontier" } })", {0, 0}, 12, 4, 1);
  EXPECT_EQ(shao_route(f), ShaoRoute::Frontier);
  EXPECT_FALSE(shao_mark_on_arrival(f));
  const ScenarioConfig l = tiny(R"(policy { shao_search { search: "lawnmower_transit" } })", {0, 0}, 12, 4, 1);
  EXPECT_EQ(shao_route(l), ShaoRoute::LawnmowerTransit);
  const ScenarioConfig a = tiny(R"(policy { shao_search { mark: "on_arrival" } })", {0, 0}, 12, 4, 1);
  EXPECT_EQ(shao_route(a), ShaoRoute::Pheromone);
  EXPECT_TRUE(shao_mark_on_arrival(a));
  auto bad = parse_scenario(
      "name: \"x\" map { width: 12 height: 4 tile_size: 4 regions_x: 1 regions_y: 1 } "
      "swarm { uavs: 1 start_area { x: 0 y: 0 w: 1 h: 1 } } "
      "policy { shao_search { search: \"spiral\" } }",
      "x");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("search"), std::string::npos) << bad.error().message;
  auto bad_mark = parse_scenario(
      "name: \"x\" map { width: 12 height: 4 tile_size: 4 regions_x: 1 regions_y: 1 } "
      "swarm { uavs: 1 start_area { x: 0 y: 0 w: 1 h: 1 } } "
      "policy { shao_search { mark: \"later\" } }",
      "x");
  ASSERT_FALSE(bad_mark.ok());
}

TEST(ShaoFrontier, ALoneFrontierUavSweepsACorridorInOnePassThenFetchesWhatItMissed) {
  // 20 x 5 corridor, sensor radius 2 = D0, the UAV starts at (0, 2). Each
  // step east along row 2 brings 5 new cells into range, more than any turn
  // away from it: it flies straight to the far end, x = 19, in 19 moves,
  // plus at most 2 if its random first heading points away from east (the
  // five forward headings turn at most 90° a step). Its first turns may
  // leave a few cells near the start out of range (at most a column's 5 of
  // the 100); with nothing new ahead it flies back to them (the
  // nearest-unvisited fallback), well within the 40 ticks of the run.
  const ScenarioConfig s = tiny(R"(policy { shao_search { search: "frontier" } })", {0, 2}, 20, 5, 2);
  Simulator sim(s);
  std::optional<uint32_t> at_end, covered;
  double coverage_at_end = 0;
  int32_t max_x = 0;
  bool went_back_early = false;
  sim.run([&](uint32_t k) {
    const Cell c = sim.uav(0).cell();
    if (!at_end && c.x < max_x) went_back_early = true;
    max_x = std::max(max_x, c.x);
    const double cov = sim.recorder().coverage().coverage();
    if (!at_end && c.x == 19) {
      at_end = k;
      coverage_at_end = cov;
    }
    if (!covered && cov >= 1.0) covered = k;
  });
  ASSERT_TRUE(at_end.has_value());
  EXPECT_GE(*at_end, 19U);
  EXPECT_LE(*at_end, 21U);
  EXPECT_FALSE(went_back_early);
  EXPECT_GE(coverage_at_end, 0.95);
  ASSERT_TRUE(covered.has_value());
  EXPECT_LE(*covered, 40U);
}

TEST(ShaoMarkOnArrival, TheUavMarksATargetOnlyOnceItIsOnItsCell) {
  // Target (4, 2), UAV at (1, 2), sensor radius 4: in range from the start.
  // "in_range" (the default) marks it at once; "on_arrival" flies there
  // first: at least 3 moves (Chebyshev distance 3), and the mark follows the
  // tick the UAV is on the cell.
  const std::string target = "targets { x: 4 y: 2 }";
  auto marked_and_arrived = [&](const std::string& policy) {
    Simulator sim(tiny(policy, {1, 2}, 12, 5, 4, target));
    std::optional<uint32_t> marked, arrived;
    sim.run([&](uint32_t k) {
      const Cell c = sim.uav(0).cell();
      if (!arrived && c.x == 4 && c.y == 2) arrived = k;
      if (!marked && sim.field_value(static_cast<int>(Layer::TargetState), {4, 2}) == kTargetMarked) marked = k;
    });
    return std::make_pair(marked, arrived);
  };
  const auto [m_range, a_range] = marked_and_arrived("");
  ASSERT_TRUE(m_range.has_value());
  EXPECT_LE(*m_range, 1U);
  const auto [m_arrival, a_arrival] = marked_and_arrived(R"(policy { shao_search { mark: "on_arrival" } })");
  ASSERT_TRUE(m_arrival.has_value());
  ASSERT_TRUE(a_arrival.has_value());
  EXPECT_GE(*a_arrival, 3U);
  EXPECT_GE(*m_arrival, *a_arrival);
  EXPECT_LE(*m_arrival, *a_arrival + 1);
}
