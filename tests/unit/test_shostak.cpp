// Shostak (GPS-denied stigmergy), checked against hand-worked numbers.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/rng.hpp"
#include "pheromesh/shostak/model.hpp"
#include "unit_support.hpp"

namespace pheromesh::core {
namespace {

using test::kPi;

// --- evaporation -------------------------------------------------------------

TEST(ShostakEvaporation, FactorIsPerSecondMultiplicativeAndComposes) {
  // Shostak 2024 eq. (2): one second multiplies by exactly 1 - ρ; five 0.2 s steps equal one second.
  EXPECT_DOUBLE_EQ(shostak_evaporation_factor(0.05, 1.0), 0.95);
  EXPECT_NEAR(shostak_evaporation_factor(0.05, 0.2), 0.98979378168698849, 1e-15);
  EXPECT_NEAR(std::pow(shostak_evaporation_factor(0.05, 0.2), 5), 0.95, 1e-15);
  EXPECT_DOUBLE_EQ(shostak_evaporation_factor(0.05, 0.0), 1.0);
}

TEST(ShostakEvaporation, HalfLifeIsThirteenAndAHalfSeconds) {
  // ln 0.5 / ln 0.95 = 13.5134 s (e^(-0.05 t) would give 13.86 s).
  EXPECT_NEAR(shostak_half_life_s(0.05), 13.513407333964874, 1e-9);
}

TEST(ShostakEvaporation, ExploredTenFallsBelowFiveAtTheFourteenthSecond) {
  // Shostak 2024 Sec. 5: "explored 10.0 -> 5.0 in about 14 s".
  ShostakLayers layers({0, 0, 1, 1}, ShostakLayerParams{});
  ASSERT_TRUE(layers.deposit(ShostakLayer::Explored, {0, 0}, 10.0));
  for (int step = 0; step < 65; ++step) {  // 13 s in 0.2 s steps
    layers.evaporate(0.2);
  }
  EXPECT_NEAR(layers.value(ShostakLayer::Explored, {0, 0}), 5.133420832795048, 1e-4);  // 10·0.95^13
  for (int step = 0; step < 5; ++step) {
    layers.evaporate(0.2);
  }
  EXPECT_NEAR(layers.value(ShostakLayer::Explored, {0, 0}), 4.876749791155295, 1e-4);  // 10·0.95^14
}

TEST(ShostakEvaporation, AppliesToEveryLayer) {
  ShostakLayers layers({0, 0, 2, 1}, ShostakLayerParams{});
  ASSERT_TRUE(layers.mark_hazard({1, 0}));
  ASSERT_TRUE(layers.mark_target({1, 0}));
  layers.evaporate(1.0);
  EXPECT_FLOAT_EQ(layers.value(ShostakLayer::Hazard, {1, 0}), 4.75F);
  EXPECT_FLOAT_EQ(layers.value(ShostakLayer::Target, {1, 0}), 95.0F);
  layers.evaporate(-1.0);  // ignored
  EXPECT_FLOAT_EQ(layers.value(ShostakLayer::Target, {1, 0}), 95.0F);
}

// --- deposit -----------------------------------------------------------------

TEST(ShostakDeposit, ExploredGrowsByOnePerDepositAndStopsAtTen) {
  ShostakLayers layers({10, 20, 3, 3}, ShostakLayerParams{});
  const Cell c{11, 21};
  for (int i = 0; i < 7; ++i) {
    ASSERT_TRUE(layers.deposit_explored(c));
  }
  EXPECT_FLOAT_EQ(layers.value(ShostakLayer::Explored, c), 7.0F);
  for (int i = 0; i < 8; ++i) {
    ASSERT_TRUE(layers.deposit_explored(c));
  }
  EXPECT_FLOAT_EQ(layers.value(ShostakLayer::Explored, c), 10.0F);
  EXPECT_FLOAT_EQ(layers.value(ShostakLayer::Explored, {10, 20}), 0.0F);
}

TEST(ShostakDeposit, HazardAddsFivePerDetectionUpToTen) {
  ShostakLayers layers({0, 0, 2, 2}, ShostakLayerParams{});
  ASSERT_TRUE(layers.mark_hazard({1, 1}));
  EXPECT_FLOAT_EQ(layers.value(ShostakLayer::Hazard, {1, 1}), 5.0F);
  ASSERT_TRUE(layers.mark_hazard({1, 1}));
  ASSERT_TRUE(layers.mark_hazard({1, 1}));
  EXPECT_FLOAT_EQ(layers.value(ShostakLayer::Hazard, {1, 1}), 10.0F);
}

TEST(ShostakDeposit, TargetAddsHundredAndCapsAtHundred) {
  ShostakLayers layers({0, 0, 2, 2}, ShostakLayerParams{});
  ASSERT_TRUE(layers.deposit(ShostakLayer::Target, {0, 1}, 30.0));
  ASSERT_TRUE(layers.mark_target({0, 1}));
  EXPECT_FLOAT_EQ(layers.value(ShostakLayer::Target, {0, 1}), 100.0F);
}

TEST(ShostakDeposit, RejectsCellsOutsideTheRectAndBadAmounts) {
  ShostakLayers layers({0, 0, 2, 2}, ShostakLayerParams{});
  EXPECT_FALSE(layers.deposit_explored({2, 0}));
  EXPECT_FALSE(layers.deposit(ShostakLayer::Hazard, {0, 0}, -1.0));
  EXPECT_FALSE(layers.deposit(ShostakLayer::Hazard, {0, 0}, std::nan("")));
  EXPECT_FALSE(layers.values({-1, 0}).has_value());
  const auto v = layers.values({0, 0});
  ASSERT_TRUE(v.has_value());
  EXPECT_EQ(v->hazard, 0.0);
}

TEST(ShostakDeposit, OneDepositEveryTwoTenthsOfASecond) {
  EXPECT_EQ(shostak_deposits_due(0.0, 1.0, 0.2), 5U);
  EXPECT_EQ(shostak_deposits_due(0.1, 0.3, 0.2), 1U);
  EXPECT_EQ(shostak_deposits_due(0.0, 0.6, 0.2), 3U);  // 0.6/0.2 rounds to 2.999...
  EXPECT_EQ(shostak_deposits_due(0.2, 0.39, 0.2), 0U);
  EXPECT_EQ(shostak_deposits_due(1.0, 0.5, 0.2), 0U);
}

// --- attractiveness and scoring -----------------------------------------------

TEST(ShostakAttractiveness, FreshCellIsOne) {
  const auto a = shostak_attractiveness({0.0, 0.0, 0.0}, ShostakAttractivenessParams{});
  EXPECT_DOUBLE_EQ(a.b_e, 1.0);
  EXPECT_DOUBLE_EQ(a.b_h, 1.0);
  EXPECT_DOUBLE_EQ(a.b_t, 0.0);
  EXPECT_DOUBLE_EQ(a.phi, 1.0);
}

TEST(ShostakAttractiveness, MixedCellMatchesHandWorkedValue) {
  // b_e = 1 - 0.3 = 0.7, b_h = 1 - 0.5 = 0.5, b_t = 0.2·10 = 2 -> φ = 0.35 + 2 = 2.35
  const auto a = shostak_attractiveness({3.0, 5.0, 0.2}, ShostakAttractivenessParams{});
  EXPECT_DOUBLE_EQ(a.b_e, 0.7);
  EXPECT_DOUBLE_EQ(a.b_h, 0.5);
  EXPECT_DOUBLE_EQ(a.b_t, 2.0);
  EXPECT_NEAR(a.phi, 2.35, 1e-12);
}

TEST(ShostakAttractiveness, SaturatedCellKeepsAFloorOfFiveThousandths) {
  // b_e = 1 - min(1, 0.9) = 0.1, b_h = 1 - min(1, 0.95) = 0.05 -> φ = 0.005
  const auto a = shostak_attractiveness({10.0, 10.0, 0.0}, ShostakAttractivenessParams{});
  EXPECT_NEAR(a.b_e, 0.1, 1e-12);
  EXPECT_NEAR(a.b_h, 0.05, 1e-12);
  EXPECT_NEAR(a.phi, 0.005, 1e-12);
}

TEST(ShostakAttractiveness, TargetDominates) {
  // b_t = 100·10 = 1000 on top of b_e·b_h = 0.5·1
  const auto a = shostak_attractiveness({5.0, 0.0, 100.0}, ShostakAttractivenessParams{});
  EXPECT_NEAR(a.phi, 1000.5, 1e-9);
}

TEST(ShostakScore, IsPhiToOneAndAHalfTimesEtaCubed) {
  const ShostakAcoParams p;
  EXPECT_NEAR(shostak_score(2.35, 0.5, p), 0.45031022292970435, 1e-12);  // 2.35^1.5 · 0.5^3
  EXPECT_NEAR(shostak_score(0.005, 1.0, p), 0.00035355339059327376, 1e-15);
  EXPECT_EQ(shostak_score(0.0, 1.0, p), 0.0);
}

TEST(ShostakScore, EtaRewardsAlignmentWithThePreferredAzimuth) {
  const ShostakAcoParams p;  // floor 0.1
  EXPECT_DOUBLE_EQ(shostak_eta(1.0, std::nullopt, p), 1.0);
  EXPECT_DOUBLE_EQ(shostak_eta(0.5, 0.5, p), 1.0);
  EXPECT_NEAR(shostak_eta(kPi, 0.0, p), 0.1, 1e-12);
  EXPECT_NEAR(shostak_eta(kPi / 2.0, 0.0, p), 0.55, 1e-12);
}

// --- candidates and roulette ----------------------------------------------------

TEST(ShostakCandidates, TwentyPointsAtFifteenMetresWithPitchWithinThirtyDegrees) {
  Rng rng(42);
  const Eigen::Vector3d p(100.0, 50.0, 20.0);
  std::array<int, 4> quadrant{};
  for (int round = 0; round < 200; ++round) {
    const auto cands = shostak_candidates(p, ShostakAcoParams{}, rng);
    ASSERT_EQ(cands.size(), 20U);
    for (const auto& c : cands) {
      const Eigen::Vector3d d = c.position - p;
      EXPECT_NEAR(d.norm(), 15.0, 1e-9);
      const double pitch = std::asin(d.z() / 15.0);
      EXPECT_GE(pitch, -kPi / 6.0 - 1e-12);
      EXPECT_LE(pitch, kPi / 6.0 + 1e-12);
      EXPECT_NEAR(pitch, c.pitch_rad, 1e-9);
      EXPECT_GE(c.azimuth_rad, 0.0);
      EXPECT_LT(c.azimuth_rad, 2.0 * kPi);
      EXPECT_NEAR(std::atan2(d.y(), d.x()), std::remainder(c.azimuth_rad, 2.0 * kPi), 1e-9);
      ++quadrant[static_cast<std::size_t>(c.azimuth_rad / (kPi / 2.0))];
    }
  }
  for (int q : quadrant) {  // 4000 azimuths, ~1000 per quadrant
    EXPECT_GT(q, 850);
  }
}

TEST(ShostakRoulette, FrequenciesFollowScoreShares) {
  Rng rng(7);
  const std::vector<double> scores{1.0, 0.0, 2.0, 3.0, 4.0};
  std::array<int, 5> hits{};
  constexpr int kDraws = 40000;
  for (int i = 0; i < kDraws; ++i) {
    const auto k = shostak_roulette(scores, rng);
    ASSERT_TRUE(k.has_value());
    ++hits[*k];
  }
  EXPECT_EQ(hits[1], 0);
  // Expected shares 0.1, 0.2, 0.3, 0.4; sd <= 0.0025, bound 0.01.
  EXPECT_NEAR(hits[0] / double{kDraws}, 0.1, 0.01);
  EXPECT_NEAR(hits[2] / double{kDraws}, 0.2, 0.01);
  EXPECT_NEAR(hits[3] / double{kDraws}, 0.3, 0.01);
  EXPECT_NEAR(hits[4] / double{kDraws}, 0.4, 0.01);
}

TEST(ShostakRoulette, NothingToChooseWhenNoScoreIsPositive) {
  Rng rng(1);
  const std::vector<double> scores{0.0, -1.0, std::nan("")};
  EXPECT_FALSE(shostak_roulette(scores, rng).has_value());
  EXPECT_FALSE(shostak_roulette(std::span<const double>{}, rng).has_value());
}

TEST(ShostakChoose, HeadsForTheMarkedTargetSide) {
  // 5 m cells; every cell east of x = 100 m carries target 100 (φ = 1001),
  // everything else is fresh (φ = 1): east wins by 1001^1.5 ≈ 31 700 : 1.
  const ShostakLookup lookup = [](Cell c) -> std::optional<ShostakCellValues> {
    return ShostakCellValues{0.0, 0.0, c.x >= 20 ? 100.0 : 0.0};
  };
  Rng rng(3);
  const Eigen::Vector3d p(100.0, 100.0, 10.0);
  int east = 0;
  for (int i = 0; i < 200; ++i) {
    const auto ch = shostak_choose(p, std::nullopt, lookup, 5.0, ShostakAcoParams{}, ShostakAttractivenessParams{}, rng);
    ASSERT_TRUE(ch.has_value());
    EXPECT_GT(ch->probability, 0.0);
    EXPECT_LE(ch->probability, 1.0);
    east += ch->candidate.position.x() >= 100.0 ? 1 : 0;
  }
  EXPECT_GE(east, 198);
}

TEST(ShostakChoose, NoChoiceWhenNoCandidateCellIsKnown) {
  const ShostakLookup unknown = [](Cell) -> std::optional<ShostakCellValues> { return std::nullopt; };
  Rng rng(3);
  EXPECT_FALSE(shostak_choose(Eigen::Vector3d::Zero(), 0.0, unknown, 5.0, ShostakAcoParams{},
                              ShostakAttractivenessParams{}, rng)
                   .has_value());
}

TEST(ShostakCells, FloorOfPositionOverCellSize) {
  EXPECT_EQ(shostak_cell_of({12.4, 4.99, 3.0}, 5.0), (Cell{2, 0}));
  EXPECT_EQ(shostak_cell_of({-0.1, 5.0, 0.0}, 5.0), (Cell{-1, 1}));
}

// --- dispersal ---------------------------------------------------------------------

TEST(ShostakDispersal, ThreeDronesLeaveAtZeroOneTwentyAndTwoFortyDegrees) {
  EXPECT_DOUBLE_EQ(shostak_dispersal_heading(0, 3), 0.0);
  EXPECT_NEAR(shostak_dispersal_heading(1, 3), 2.0 * kPi / 3.0, 1e-12);
  EXPECT_NEAR(shostak_dispersal_heading(2, 3), 4.0 * kPi / 3.0, 1e-12);
  EXPECT_DOUBLE_EQ(shostak_dispersal_heading(0, 0), 0.0);
  const Eigen::Vector3d start(10.0, 20.0, 5.0);
  const Eigen::Vector3d w1 = shostak_dispersal_waypoint(start, 1, 3, 15.0);
  EXPECT_NEAR(w1.x(), 10.0 - 7.5, 1e-9);
  EXPECT_NEAR(w1.y(), 20.0 + 12.990381056766580, 1e-9);  // 15·sin 120°
  EXPECT_DOUBLE_EQ(w1.z(), 5.0);
  const Eigen::Vector3d w2 = shostak_dispersal_waypoint(start, 2, 3, 15.0);
  EXPECT_NEAR(w2.y(), 20.0 - 12.990381056766580, 1e-9);
}

// --- local frame and drift -------------------------------------------------------------

TEST(ShostakFrame, QuarterTurnFrameMapsLocalXToWorldY) {
  const ShostakLocalFrame f{Eigen::Vector3d(100.0, 50.0, 0.0), kPi / 2.0};
  const Eigen::Vector3d w = shostak_local_to_world(f, {10.0, 0.0, 3.0});
  EXPECT_NEAR(w.x(), 100.0, 1e-9);
  EXPECT_NEAR(w.y(), 60.0, 1e-9);
  EXPECT_NEAR(w.z(), 3.0, 1e-12);
  EXPECT_NEAR(shostak_heading_local_to_world(f, 0.0), kPi / 2.0, 1e-12);
  EXPECT_NEAR(shostak_heading_world_to_local(f, 0.0), 3.0 * kPi / 2.0, 1e-12);
}

TEST(ShostakFrame, LocalToWorldAndBackRoundTrips) {
  Rng rng(11);
  for (int i = 0; i < 100; ++i) {
    const ShostakLocalFrame f{Eigen::Vector3d(400.0 * rng.uniform01(), 400.0 * rng.uniform01(), 0.0),
                              2.0 * kPi * rng.uniform01()};
    const Eigen::Vector3d p(200.0 * rng.uniform01() - 100.0, 200.0 * rng.uniform01() - 100.0, 50.0 * rng.uniform01());
    EXPECT_LT((shostak_world_to_local(f, shostak_local_to_world(f, p)) - p).norm(), 1e-9);
    EXPECT_LT((shostak_local_to_world(f, shostak_world_to_local(f, p)) - p).norm(), 1e-9);
    const double h = 2.0 * kPi * rng.uniform01();
    EXPECT_NEAR(std::remainder(shostak_heading_world_to_local(f, shostak_heading_local_to_world(f, h)) - h, 2.0 * kPi),
                0.0, 1e-9);
  }
}

TEST(ShostakDrift, WithoutNoiseTheEstimateIsExact) {
  Rng rng(5);
  ShostakPoseEstimate est;
  est = shostak_drift_step(est, {3.0, 4.0, 1.0}, ShostakDriftParams{}, rng);
  est = shostak_drift_step(est, {-1.0, 0.0, 0.0}, ShostakDriftParams{}, rng);
  EXPECT_LT((est.position_local - Eigen::Vector3d(2.0, 4.0, 1.0)).norm(), 1e-12);
  EXPECT_EQ(est.yaw_error_rad, 0.0);
}

TEST(ShostakDrift, HeadingErrorRotatesTheDeadReckonedStep) {
  Rng rng(5);
  ShostakPoseEstimate est;
  est.yaw_error_rad = 0.1;
  est = shostak_drift_step(est, {10.0, 0.0, 0.0}, ShostakDriftParams{}, rng);
  EXPECT_NEAR(est.position_local.x(), 9.950041652780258, 1e-12);  // 10 cos 0.1
  EXPECT_NEAR(est.position_local.y(), 0.9983341664682815, 1e-12);  // 10 sin 0.1
}

TEST(ShostakDrift, PositionVarianceGrowsWithDistanceFlown) {
  // q_pos = 0.01 m²/m over 100 m in 1 m steps -> variance 1 m² per axis.
  const ShostakDriftParams p{0.01, 0.0};
  Rng rng(9);
  constexpr int kRuns = 2000;
  double sum_sq = 0.0;
  for (int r = 0; r < kRuns; ++r) {
    ShostakPoseEstimate est;
    for (int s = 0; s < 100; ++s) {
      est = shostak_drift_step(est, {1.0, 0.0, 0.0}, p, rng);
    }
    const double ey = est.position_local.y();
    sum_sq += ey * ey;
  }
  EXPECT_NEAR(sum_sq / kRuns, 1.0, 0.15);  // sd of the estimate ≈ 0.032
}

}  // namespace
}  // namespace pheromesh::core
