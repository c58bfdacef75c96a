// Shostak 2024 Sec. 5 experiments as a library: crossing times and the hovering drone
// against hand-worked numbers, and the swarm loop on a tiny map.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "pheromesh/shostak/model.hpp"
#include "pheromesh/shostak/experiment.hpp"

namespace pheromesh::core {
namespace {

TEST(ShostakExplored, CrossesFromTenToFiveAtFourteenSecondsInWholeSecondSteps) {
  // Shostak 2024 eq. (2) with ρ = 0.05: 10 · 0.95^13 = 5.13 > 5, 10 · 0.95^14 = 4.88 <= 5.
  EXPECT_NEAR(shostak_explored_crossing_s(ShostakLayerParams{}, 10.0, 5.0, 1.0), 14.0, 1e-9);
  // In 0.2 s ticks: half-life ln 0.5 / ln 0.95 = 13.51 s, next tick 13.6 s.
  EXPECT_NEAR(shostak_explored_crossing_s(ShostakLayerParams{}, 10.0, 5.0, 0.2), 13.6, 1e-9);
  // 10 -> 9.5 is one whole second (10 · 0.95 = 9.5 exactly in steps of 1 s, float 9.5).
  EXPECT_NEAR(shostak_explored_crossing_s(ShostakLayerParams{}, 10.0, 9.5, 1.0), 1.0, 1e-9);
}

TEST(ShostakHover, ReachesTheCapAfterElevenDepositsThenOnlyEvaporates) {
  const ShostakLayerParams lp;
  const ShostakHoverTrace h = shostak_hover(lp, 5.0, 50);
  ASSERT_EQ(h.points.size(), 51U);
  EXPECT_EQ(h.points.front(), (std::pair<double, double>{0.0, 0.0}));
  // Before deposit k the level is multiplied by q = 0.95^0.2 = 0.98979, so
  // v_k = (1 - q^k) / (1 - q): v_10 = 9.553 < 10, v_11 = 10.456 -> capped at 10.
  const double q = std::pow(0.95, 0.2);
  EXPECT_NEAR(h.points[10].second, (1.0 - std::pow(q, 10)) / (1.0 - q), 1e-5);
  EXPECT_LT(h.points[10].second, 10.0);
  ASSERT_TRUE(h.full_s.has_value());
  EXPECT_NEAR(*h.full_s, 2.2, 1e-9);
  EXPECT_NEAR(h.points[11].second, 10.0, 1e-6);
  // Held at the cap while hovering (t <= 5 s), then 10 · q^k after leaving.
  EXPECT_NEAR(h.points[25].second, 10.0, 1e-6);
  EXPECT_NEAR(h.points[30].second, 10.0 * std::pow(q, 5), 1e-5);  // t = 6 s: 10 · 0.95
  for (std::size_t k = 26; k < h.points.size(); ++k) {
    EXPECT_LT(h.points[k].second, h.points[k - 1].second);
  }
}

TEST(ShostakHover, NeverFillsWhenTheDroneLeavesBeforeTheCap) {
  const ShostakHoverTrace h = shostak_hover(ShostakLayerParams{}, 1.0, 20);
  EXPECT_FALSE(h.full_s.has_value());
  // Five deposits: (1 - q^5) / (1 - q) = (1 - 0.95) / (1 - 0.95^0.2) = 4.899.
  const double q = std::pow(0.95, 0.2);
  EXPECT_NEAR(h.points[5].second, 0.05 / (1.0 - q), 1e-5);
}

// 2 UAVs on a 12 x 12 map of 5 m cells, short legs, one obstacle, 2 minutes.
ShostakSwarmSetup tiny_setup() {
  ShostakSwarmSetup s;
  s.uavs = 2;
  s.cells = 12;
  s.dispersal_m = 10.0;
  s.obstacles = 1;
  s.target_min_distance_m = 15.0;
  s.search_limit_s = 60.0;
  s.converge_limit_s = 60.0;
  return s;
}

TEST(ShostakSwarm, IsRepeatableForASeedAndDiffersBetweenSeeds) {
  const ShostakSwarmSetup s = tiny_setup();
  const ShostakSwarmRun a = shostak_swarm_run(s, 7);
  const ShostakSwarmRun b = shostak_swarm_run(s, 7);
  const ShostakSwarmRun c = shostak_swarm_run(s, 8);
  EXPECT_EQ(a.tracks, b.tracks);
  EXPECT_EQ(a.coverage, b.coverage);
  EXPECT_EQ(a.detect_s, b.detect_s);
  EXPECT_EQ(a.converge_s, b.converge_s);
  EXPECT_EQ(a.target, b.target);
  EXPECT_NE(a.tracks, c.tracks);
}

TEST(ShostakSwarm, CoverageIsAShareThatNeverShrinksAndTracksMatchTheClock) {
  const ShostakSwarmSetup s = tiny_setup();
  uint32_t detected = 0, converged = 0;
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    const ShostakSwarmRun r = shostak_swarm_run(s, seed);
    const double size_m = s.cells * 5.0;
    // Target on the map (5 m margin) and at least 15 m from the launch point (30, 30).
    EXPECT_GE(r.target.x(), 5.0);
    EXPECT_LE(r.target.x(), size_m - 5.0);
    EXPECT_GE(std::hypot(r.target.x() - 30.0, r.target.y() - 30.0), s.target_min_distance_m);
    EXPECT_EQ(r.obstacles.size(), 1U);

    ASSERT_FALSE(r.coverage.empty());
    for (std::size_t k = 0; k < r.coverage.size(); ++k) {
      EXPECT_NEAR(r.coverage[k].first, static_cast<double>(k + 1), 1e-9);  // one sample per second
      EXPECT_GT(r.coverage[k].second, 0.0);
      EXPECT_LE(r.coverage[k].second, 1.0);
      if (k > 0) {
        EXPECT_GE(r.coverage[k].second, r.coverage[k - 1].second);
      }
    }
    // Two UAVs at 5 m/s cover at most 2 cells per tick: 10 cells per second of 144.
    EXPECT_LE(r.coverage.back().second, 10.0 * static_cast<double>(r.coverage.size()) / 144.0);
    ASSERT_EQ(r.tracks.size(), 2U);
    for (const auto& t : r.tracks) {
      EXPECT_EQ(t.size(), r.coverage.size());
    }
    // One step is 1 m per tick: consecutive 1 s track points are at most 5 m apart.
    for (const auto& t : r.tracks) {
      for (std::size_t k = 1; k < t.size(); ++k) {
        EXPECT_LE(std::hypot(t[k].first - t[k - 1].first, t[k].second - t[k - 1].second), 5.0 + 1e-9);
      }
    }

    if (!r.detect_s) {
      EXPECT_TRUE(r.arrival_s.empty());
      EXPECT_NEAR(r.end_s, s.search_limit_s, 1e-9);
      continue;
    }
    ++detected;
    EXPECT_LE(*r.detect_s, s.search_limit_s);
    EXPECT_LT(r.detector, 2U);
    ASSERT_EQ(r.arrival_s.size(), 1U);
    if (!r.converge_s) continue;
    ++converged;
    // With one other UAV, convergence is its arrival; no faster than flying
    // straight (it may already move in the detection tick: one tick of slack).
    EXPECT_DOUBLE_EQ(*r.converge_s, r.arrival_s[0]);
    EXPECT_GE(*r.converge_s, r.direct_s - 0.2 - 1e-9);
    EXPECT_NEAR(r.end_s, *r.detect_s + *r.converge_s, 1e-9);
  }
  EXPECT_GT(detected, 0U);  // the detection checks above ran
  EXPECT_GT(converged, 0U);
}

}  // namespace
}  // namespace pheromesh::core
