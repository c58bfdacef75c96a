// Liu 2022 (ESUSTPM): TPM update, prior, environmental uncertainty, local
// rules and baselines, checked against hand-worked numbers. Sensor values of
// Liu 2022 Sec. 2.1: Pd = 0.3, Pf = 0.1.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/rng.hpp"
#include "pheromesh/liu/tpm.hpp"
#include "pheromesh/shao/aco.hpp"
#include "unit_support.hpp"

namespace pheromesh::core {
namespace {

using test::kEps;

LiuParams bayes_params() {
  LiuParams p;
  p.miss_update = MissUpdate::kBayes;
  return p;
}

// A whole-map lookup over a row-major 10 x 10 map.
TpmLookup lookup_of(const std::vector<double>& map, int32_t w = 10, int32_t h = 10) {
  return [&map, w, h](Cell c) -> std::optional<double> {
    if (c.x < 0 || c.y < 0 || c.x >= w || c.y >= h) {
      return std::nullopt;
    }
    return map[static_cast<std::size_t>(c.y * w + c.x)];
  };
}

// --- TPM update, Liu 2022 eq. (3), Liu 2022 eq. (4), Liu 2022 eq. (5) ---------------------------------------------

TEST(LiuTpm, DetectionFromAnEvenPriorRaisesItToThreeQuarters) {
  // Liu 2022 eq. (4): 0.3·0.5 / ((0.3 - 0.1)·0.5 + 0.1) = 0.15 / 0.2 = 0.75
  EXPECT_NEAR(tpm_update(0.5, true, LiuParams{}), 0.75, kEps);
  EXPECT_NEAR(tpm_update(0.5, true, bayes_params()), 0.75, kEps);  // Liu 2022 eq. (4) is the same for both
}

TEST(LiuTpm, MissFromAnEvenPriorFollowsThePrintedEquationFive) {
  // printed Liu 2022 eq. (5): 0.7·0.5 / 0.9 = 0.35 / 0.9 = 0.388889
  EXPECT_NEAR(tpm_update(0.5, false, LiuParams{}), 0.35 / 0.9, kEps);
  EXPECT_NEAR(tpm_update(0.5, false, LiuParams{}), 0.388889, 1e-6);
  // Bayesian: 0.35 / ((0.1 - 0.3)·0.5 + 0.9) = 0.35 / 0.8 = 0.4375
  EXPECT_NEAR(tpm_update(0.5, false, bayes_params()), 0.4375, kEps);
}

TEST(LiuTpm, DetectionAndMissFromOneTenthMatchHandWorkedValues) {
  // Liu 2022 eq. (4): 0.03 / (0.2·0.1 + 0.1) = 0.03 / 0.12 = 0.25
  EXPECT_NEAR(tpm_update(0.1, true, LiuParams{}), 0.25, kEps);
  // printed Liu 2022 eq. (5): 0.07 / 0.9 = 0.077778
  EXPECT_NEAR(tpm_update(0.1, false, LiuParams{}), 0.077778, 1e-6);
  // Bayesian: 0.07 / (-0.2·0.1 + 0.9) = 0.07 / 0.88 = 0.079545
  EXPECT_NEAR(tpm_update(0.1, false, bayes_params()), 0.079545, 1e-6);
}

TEST(LiuTpm, DetectionThenMissFromAnEvenPrior) {
  // 0.5 -> 0.75 (Liu 2022 eq. (4)) -> printed: 0.7·0.75 / 0.9 = 0.583333
  EXPECT_NEAR(tpm_update(tpm_update(0.5, true, LiuParams{}), false, LiuParams{}), 0.583333, 1e-6);
  // Bayesian: 0.525 / (-0.2·0.75 + 0.9) = 0.525 / 0.75 = 0.7
  EXPECT_NEAR(tpm_update(tpm_update(0.5, true, bayes_params()), false, bayes_params()), 0.7, kEps);
}

TEST(LiuTpm, RepeatedMissesDriveTheProbabilityDownMonotonically) {
  for (const LiuParams& params : {LiuParams{}, bayes_params()}) {
    double p = 0.5;
    for (int i = 0; i < 50; ++i) {
      const double next = tpm_update(p, false, params);
      EXPECT_LT(next, p);
      EXPECT_GE(next, 0.0);
      p = next;
    }
    EXPECT_LT(p, 1e-4);
  }
  // Printed Liu 2022 eq. (5) is geometric: 0.5·(7/9)^3 = 0.235254
  double p = 0.5;
  for (int i = 0; i < 3; ++i) {
    p = tpm_update(p, false, LiuParams{});
  }
  EXPECT_NEAR(p, 0.235254, 1e-6);
}

TEST(LiuTpm, ATargetIsConfirmedOnlyAboveTheThreshold) {
  // θ = 0.95. Detections from 0.5: 0.75, 0.9 (0.27/0.3), 0.964286 (0.27/0.28).
  const Rect region{0, 0, 10, 10};
  TargetProbabilityMap tpm(region, LiuParams{});
  const Cell target{4, 5};
  ASSERT_TRUE(tpm.observe(target, true));
  EXPECT_NEAR(tpm.probability(target), 0.75, kEps);
  EXPECT_FALSE(tpm.confirmed(target));
  ASSERT_TRUE(tpm.observe(target, true));
  EXPECT_NEAR(tpm.probability(target), 0.9, kEps);
  EXPECT_FALSE(tpm.confirmed(target));
  ASSERT_TRUE(tpm.observe(target, true));
  EXPECT_NEAR(tpm.probability(target), 0.964286, 1e-6);
  EXPECT_TRUE(tpm.confirmed(target));
  ASSERT_EQ(tpm.confirmed_cells().size(), 1U);
  EXPECT_EQ(tpm.confirmed_cells()[0], target);
  // An unobserved cell keeps its value (Liu 2022 eq. (3)).
  EXPECT_NEAR(tpm.probability(Cell{0, 0}), 0.5, kEps);
}

TEST(LiuTpm, ARegionMapIgnoresCellsOutsideItsRegion) {
  TargetProbabilityMap tpm(Rect{5, 0, 5, 5}, LiuParams{});
  EXPECT_EQ(tpm.values().size(), 25U);
  EXPECT_FALSE(tpm.observe(Cell{4, 0}, true));
  EXPECT_FALSE(tpm.find(Cell{4, 0}).has_value());
  EXPECT_FALSE(tpm.confirmed(Cell{4, 0}));
  EXPECT_TRUE(tpm.observe(Cell{9, 4}, false));
  EXPECT_NEAR(tpm.find(Cell{9, 4}).value(), 0.35 / 0.9, kEps);
  EXPECT_NEAR(tpm.values()[24], 0.35 / 0.9, kEps);  // last cell, row-major over the region
}

TEST(LiuTpm, FromMapCutsTheRegionOutOfAWholeMapAndRejectsBadInput) {
  std::vector<double> map(100);
  for (std::size_t i = 0; i < map.size(); ++i) {
    map[i] = static_cast<double>(i) / 100.0;
  }
  const auto tpm = TargetProbabilityMap::from_map(Rect{2, 3, 4, 2}, map, 10, 10, LiuParams{});
  ASSERT_TRUE(tpm.ok()) << tpm.error().message;
  EXPECT_NEAR(tpm->probability(Cell{2, 3}), 0.32, kEps);
  EXPECT_NEAR(tpm->probability(Cell{5, 4}), 0.45, kEps);

  EXPECT_FALSE(TargetProbabilityMap::from_map(Rect{8, 0, 4, 2}, map, 10, 10, LiuParams{}).ok());  // sticks out
  EXPECT_FALSE(TargetProbabilityMap::from_map(Rect{0, 0, 4, 2}, map, 10, 9, LiuParams{}).ok());   // wrong size
  map[0] = 1.5;
  EXPECT_FALSE(TargetProbabilityMap::from_map(Rect{0, 0, 4, 2}, map, 10, 10, LiuParams{}).ok());  // not a probability
  map[0] = std::nan("");
  EXPECT_FALSE(TargetProbabilityMap::from_map(Rect{0, 0, 4, 2}, map, 10, 10, LiuParams{}).ok());
}

TEST(LiuTpm, AWrongPriorIsOvercomeByObservations) {
  // Liu 2022 Sec. 5.3.2 (b): the prior expects a target at (7, 5) only; the real one is at (3, 2).
  const std::vector<GaussianComponent> prior{{7.5, 5.5, 0.7, 0.7, 0.0, 1.0}};
  const std::vector<double> map = gaussian_mixture_prior(10, 10, prior);
  auto tpm = TargetProbabilityMap::from_map(Rect{0, 0, 10, 10}, map, 10, 10, LiuParams{});
  ASSERT_TRUE(tpm.ok());
  const Cell expected{7, 5}, real{3, 2};
  EXPECT_GT(tpm->probability(expected), 0.2);
  EXPECT_LT(tpm->probability(real), 1e-6);
  // The UAVs keep returning to the most probable cells (Liu 2022 Sec. 4).
  for (int i = 0; i < 25; ++i) {
    tpm->observe(expected, false);
    tpm->observe(real, true);
  }
  // 25 misses: × (7/9)^25 = 0.00187. 25 detections multiply the odds by
  // 3^25 = 8.5e11, enough to lift a prior of ~5e-11 above θ.
  EXPECT_LT(tpm->probability(expected), 0.002 * map[57]);
  EXPECT_TRUE(tpm->confirmed(real));
  EXPECT_FALSE(tpm->confirmed(expected));
}

// --- prior, Liu 2022 eq. (1), Liu 2022 eq. (2) ----------------------------------------------------

TEST(LiuPrior, OneComponentSumsToOneAndPeaksAtItsMean) {
  // μ = (4.5, 5.5), σ = 1, ρ = 0: cell (4, 5) holds (Φ(0.5) - Φ(-0.5))² = 0.382925² = 0.146631;
  // the whole map (Φ(5.5) - Φ(-4.5))·(Φ(4.5) - Φ(-5.5)) = 0.999993.
  const std::vector<GaussianComponent> g{{4.5, 5.5, 1.0, 1.0, 0.0, 1.0}};
  const std::vector<double> map = gaussian_mixture_prior(10, 10, g);
  ASSERT_EQ(map.size(), 100U);
  double sum = 0.0;
  std::size_t peak = 0;
  for (std::size_t i = 0; i < map.size(); ++i) {
    sum += map[i];
    if (map[i] > map[peak]) {
      peak = i;
    }
  }
  EXPECT_NEAR(sum, 0.999993, 1e-6);
  EXPECT_EQ(peak, 5U * 10U + 4U);
  EXPECT_NEAR(map[peak], 0.146631, 1e-6);
}

TEST(LiuPrior, AMixtureSumsToItsWeightsAndPeaksAtEveryTarget) {
  // The three targets of Liu 2022 Sec. 5.2 in cell units, α = 0.5, 0.3, 0.2 (Σα = 1).
  const std::vector<GaussianComponent> g{
      {4.5, 5.5, 0.6, 0.6, 0.0, 0.5}, {4.5, 7.5, 0.6, 0.6, 0.0, 0.3}, {7.5, 5.5, 0.6, 0.6, 0.0, 0.2}};
  const std::vector<double> map = gaussian_mixture_prior(10, 10, g);
  double sum = 0.0;
  for (const double v : map) {
    sum += v;
  }
  // Σα = 1 minus what lies beyond the top and right borders: targets 2 and 3
  // are 2.5 cells = 4.1667 σ from them, Φ(-4.1667) = 1.5454e-5, so
  // 1 - (0.3 + 0.2)·1.5454e-5 = 0.9999923.
  EXPECT_NEAR(sum, 0.9999923, 1e-7);
  const auto at = [&map](int32_t x, int32_t y) { return map[static_cast<std::size_t>(y * 10 + x)]; };
  for (const Cell c : {Cell{4, 5}, Cell{4, 7}, Cell{7, 5}}) {
    for (int32_t dy = -1; dy <= 1; ++dy) {
      for (int32_t dx = -1; dx <= 1; ++dx) {
        if (dx != 0 || dy != 0) {
          EXPECT_GT(at(c.x, c.y), at(c.x + dx, c.y + dy)) << c.x << "," << c.y;
        }
      }
    }
  }
  EXPECT_GT(at(4, 5), at(4, 7));
  EXPECT_GT(at(4, 7), at(7, 5));
}

TEST(LiuPrior, CorrelatedIntegrationAgreesWithTheExactProductAsRhoVanishes) {
  const std::vector<GaussianComponent> exact{{3.2, 6.7, 0.8, 1.3, 0.0, 1.0}};
  const std::vector<GaussianComponent> numeric{{3.2, 6.7, 0.8, 1.3, 1e-12, 1.0}};
  const std::vector<double> a = gaussian_mixture_prior(10, 10, exact);
  const std::vector<double> b = gaussian_mixture_prior(10, 10, numeric);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_NEAR(a[i], b[i], 1e-9);
  }
}

TEST(LiuPrior, PositiveCorrelationFavoursTheDiagonalAndKeepsTheMass) {
  // Centred on the corner shared by cells (4,4), (5,4), (4,5), (5,5).
  const std::vector<GaussianComponent> g{{5.0, 5.0, 1.0, 1.0, 0.6, 1.0}};
  const std::vector<double> map = gaussian_mixture_prior(10, 10, g);
  double sum = 0.0;
  for (const double v : map) {
    sum += v;
  }
  EXPECT_NEAR(sum, 1.0, 1e-5);
  EXPECT_NEAR(map[44], map[55], 1e-9);  // point symmetry about the mean
  EXPECT_NEAR(map[45], map[54], 1e-9);
  EXPECT_GT(map[55], map[54]);          // along the correlation
}

TEST(LiuPrior, InvalidComponentsAreReportedAndContributeNothing) {
  EXPECT_FALSE(check_component(GaussianComponent{}).has_value());
  EXPECT_TRUE(check_component(GaussianComponent{1.0, 1.0, 0.0, 1.0, 0.0, 1.0}).has_value());  // σ = 0
  EXPECT_TRUE(check_component(GaussianComponent{1.0, 1.0, 1.0, 1.0, 1.0, 1.0}).has_value());  // |ρ| = 1
  EXPECT_TRUE(check_component(GaussianComponent{1.0, 1.0, 1.0, 1.0, 0.0, -1.0}).has_value());  // α < 0
  const std::vector<GaussianComponent> g{{1.0, 1.0, 0.0, 1.0, 0.0, 1.0}};
  for (const double v : gaussian_mixture_prior(4, 4, g)) {
    EXPECT_EQ(v, 0.0);
  }
}

// --- environmental uncertainty ------------------------------------------

TEST(LiuUncertainty, AnUninformedTenByTenMapHoldsFiftyBits) {
  // 100 cells · (-0.5 log2 0.5) = 100 · 0.5 = 50; the binary entropy would be 100.
  const std::vector<double> map(100, 0.5);
  EXPECT_NEAR(environmental_uncertainty(map), 50.0, kEps);
  EXPECT_NEAR(binary_entropy_bits(map), 100.0, kEps);
}

TEST(LiuUncertainty, ACertainMapHasNoUncertainty) {
  std::vector<double> map(100, 0.0);
  map[3] = 1.0;
  map[47] = 1.0;
  EXPECT_NEAR(environmental_uncertainty(map), 0.0, kEps);
  EXPECT_NEAR(binary_entropy_bits(map), 0.0, kEps);
}

TEST(LiuUncertainty, OneOrTwoMissesPerCellBracketTheMowerValueOfTable2) {
  // Every cell missed once (printed Liu 2022 eq. (5)): P = 0.388889, -P log2 P = 0.529888 -> 52.99;
  // twice: P = 0.302469, 0.521802 -> 52.18. Liu 2022 Table 2's mower (all 100 cells visited): 52.34.
  std::vector<double> once(100, 0.5), twice(100, 0.5);
  for (std::size_t i = 0; i < 100; ++i) {
    once[i] = tpm_update(once[i], false, LiuParams{});
    twice[i] = tpm_update(tpm_update(twice[i], false, LiuParams{}), false, LiuParams{});
  }
  EXPECT_NEAR(environmental_uncertainty(once), 52.9888, 1e-4);
  EXPECT_NEAR(environmental_uncertainty(twice), 52.1802, 1e-4);
  EXPECT_GT(environmental_uncertainty(once), 52.34);
  EXPECT_LT(environmental_uncertainty(twice), 52.34);
}

// --- ESUSTPM local rules, Liu 2022 eq. (6), Liu 2022 eq. (7), Liu 2022 eq. (8), Liu 2022 eq. (9), Liu 2022 eq. (10), Liu 2022 eq. (11) ------------------------------------

TEST(LiuFlocking, TheGainVanishesAtTheGivenDistanceAndMatchesHandValues) {
  const LiuParams p;
  EXPECT_NEAR(liu_gain(0, 120.0, p), 0.0, kEps);
  // d = 100: a = -80·(-20)·exp(-400/1600) = 1600·0.778801 = 1246.081;
  //          g = 5·(1 - exp(-400/100)) = 5·0.981684 = 4.908422; β = 6116.29 (repels)
  EXPECT_NEAR(liu_gain(0, 100.0, p), 6116.29, 1e-2);
  // d = 200: a = -80·80·exp(-4) = -117.220; g = 5·(1 - e^-64) = 5; β = -586.10 (attracts)
  EXPECT_NEAR(liu_gain(1, 200.0, p), -586.10, 1e-2);
  // d = √2·100: a = -80·21.421·exp(-0.28683) = -1286.42; g = 4.949172; β = -6366.71
  EXPECT_NEAR(liu_gain(3, std::sqrt(2.0) * 100.0, p), -6366.71, 1e-2);
}

TEST(LiuFlocking, TheThreeNearestNeighboursAreChosenByDistance) {
  const std::vector<LiuUav> others{
      {{900.0, 900.0}, {}},  // 0: d = 494.97
      {{550.0, 650.0}, {}},  // 1: d = 100
      {{350.0, 350.0}, {}},  // 2: d = 282.84
      {{450.0, 550.0}, {}},  // 3: d = 100 (tie with 1: lower index first)
      {{550.0, 800.0}, {}},  // 4: d = 250
  };
  LiuParams p;
  EXPECT_EQ(nearest_neighbours({550.0, 550.0}, others, p), (std::vector<std::size_t>{1, 3, 4}));
  p.comm_range_m = 200.0;
  EXPECT_EQ(nearest_neighbours({550.0, 550.0}, others, p), (std::vector<std::size_t>{1, 3}));
}

TEST(LiuFlocking, TiesAmongEquallyProbableCellsFollowTheVelocity) {
  const std::vector<double> map(100, 0.5);
  const TpmLookup tpm = lookup_of(map);
  EXPECT_EQ(most_probable_neighbour(Cell{5, 5}, Vec2{}, tpm), (Cell{6, 5}));              // E first
  EXPECT_EQ(most_probable_neighbour(Cell{5, 5}, Vec2{-1.0, 0.1}, tpm), (Cell{4, 5}));     // W
  EXPECT_EQ(most_probable_neighbour(Cell{5, 5}, Vec2{-1.0, -1.1}, tpm), (Cell{4, 4}));    // SW
  EXPECT_EQ(most_probable_neighbour(Cell{0, 0}, Vec2{-1.0, 0.0}, tpm), (Cell{0, 1}));     // W is off the map: N (cos 0) beats NE
  std::vector<double> m2 = map;
  m2[3 * 10 + 6] = 0.6;
  EXPECT_EQ(most_probable_neighbour(Cell{5, 4}, Vec2{-1.0, 0.0}, lookup_of(m2)), (Cell{6, 3}));  // probability first
}

TEST(LiuFlocking, AHandBuiltConfigurationStepsSouthEast) {
  // UAV at the centre of cell (5, 5) = (550, 550) m, at rest. Neighbours:
  //   A (450, 550): d = 100, F = (100, 0)    -> β(100) = 6116.29 · (1, 0)   (repelled east)
  //   B (550, 650): d = 100, F = (0, -100)   -> 6116.29 · (0, -1)            (repelled south)
  //   C (350, 350): d = 282.84, β = -0.0041 (negligible)
  //   D (950, 950): fourth nearest, ignored.
  // TPM: 0.5 everywhere but 0.7 at (6, 4), whose centre (650, 450) is
  //   d = 141.42 away: |β| = 6366.71 along (0.7071, -0.7071) = (4501.94, -4501.94).
  // mvel = 1/4 · (10618.23, -10618.23) = (2654.56, -2654.56): heading SE,
  // |mvel| = 3754 m/s is clipped to 10 m/s: (7.0711, -7.0711); next cell (6, 4).
  const LiuParams p;
  const LiuUav self{{550.0, 550.0}, {}};
  const std::vector<LiuUav> others{
      {{450.0, 550.0}, {}}, {{550.0, 650.0}, {}}, {{350.0, 350.0}, {}}, {{950.0, 950.0}, {}}};
  std::vector<double> map(100, 0.5);
  map[4 * 10 + 6] = 0.7;
  const TpmLookup tpm = lookup_of(map);

  const Vec2 mvel = esustpm_objective_velocity(self, others, tpm, p);
  EXPECT_NEAR(mvel.x, 2654.56, 1e-2);
  EXPECT_NEAR(mvel.y, -2654.56, 1e-2);

  const LiuMove m = esustpm_step(self, others, tpm, p);
  ASSERT_TRUE(m.heading.has_value());
  EXPECT_EQ(*m.heading, Heading::SE);
  EXPECT_EQ(m.next, (Cell{6, 4}));
  EXPECT_NEAR(m.velocity.x, 7.0711, 1e-4);
  EXPECT_NEAR(m.velocity.y, -7.0711, 1e-4);

  // Liu 2022 eq. (10), Liu 2022 eq. (11) in continuous space: one second at that velocity.
  const LiuUav after = advance_uav(self, m.velocity, 1.0, p);
  EXPECT_NEAR(after.position.x, 557.0711, 1e-4);
  EXPECT_NEAR(after.position.y, 542.9289, 1e-4);
}

TEST(LiuFlocking, ALoneUavHeadsForTheMostProbableNeighbouringCell) {
  // Only rule 4: the best cell (5, 6) is 100 m north: mvel = 6116.29 / 4 = 1529.07 north.
  std::vector<double> map(100, 0.2);
  map[6 * 10 + 5] = 0.4;
  const LiuParams p;
  const LiuUav self{{550.0, 550.0}, {10.0, 0.0}};
  const Vec2 mvel = esustpm_objective_velocity(self, {}, lookup_of(map), p);
  EXPECT_NEAR(mvel.x, 0.0, kEps);
  EXPECT_NEAR(mvel.y, 1529.07, 1e-2);
  const LiuMove m = esustpm_step(self, {}, lookup_of(map), p);
  EXPECT_EQ(m.next, (Cell{5, 6}));
  EXPECT_NEAR(m.velocity.y, 10.0, kEps);
}

TEST(LiuFlocking, TheVelocityIsReversedAtTheMapBorder) {
  const LiuParams p;
  const LiuMove m = grid_move({950.0, 550.0}, {10.0, 3.0}, p);  // heading E from the last column
  ASSERT_TRUE(m.heading.has_value());
  EXPECT_EQ(*m.heading, Heading::W);
  EXPECT_EQ(m.next, (Cell{8, 5}));
  EXPECT_NEAR(m.velocity.x, -10.0, kEps);
  EXPECT_NEAR(m.velocity.y, 3.0, kEps);

  const LiuMove corner = grid_move({50.0, 50.0}, {-1.0, -1.0}, p);  // SW from (0, 0) -> NE
  EXPECT_EQ(corner.next, (Cell{1, 1}));

  // Continuous: 30 m past the east border at x = 1000 m reflects to 970 m.
  const LiuUav after = advance_uav(LiuUav{{990.0, 500.0}, {}}, {40.0, 0.0}, 1.0, p);
  EXPECT_NEAR(after.position.x, 970.0, kEps);
  EXPECT_NEAR(after.velocity.x, -40.0, kEps);
  EXPECT_EQ(cell_of(Vec2{1000.0, 1000.0}, p), (Cell{9, 9}));
}

// --- baselines -------------------------------------------------------------

// Steps until every cell of the 10 x 10 grid has been visited by one of `uavs` mowers.
int mower_steps_to_cover(uint32_t uavs) {
  VisitedCells visited(10, 10);
  std::vector<LawnmowerState> s;
  std::vector<Rect> lanes;
  for (uint32_t i = 0; i < uavs; ++i) {
    lanes.push_back(lawnmower_lane(i, uavs, 10, 10));
    s.push_back(lawnmower_start(lanes.back()));
    visited.visit(s.back().cell);
  }
  int steps = 0;
  while (visited.count() < 100 && steps < 1000) {
    ++steps;
    for (std::size_t i = 0; i < s.size(); ++i) {
      s[i] = lawnmower_step(s[i], lanes[i]);
      visited.visit(s[i].cell);
    }
  }
  return steps;
}

TEST(LiuBaselines, TenMowersOfOneRowEachCoverTheGridInNineSteps) {
  // Liu 2022 eq. (14) per row: from x = 0 the 10th cell of the row is reached after 9 steps.
  EXPECT_EQ(mower_steps_to_cover(10), 9);
}

TEST(LiuBaselines, FiveMowersOfTwoRowsEachCoverTheGridInNineteenSteps) {
  // 20 cells per lane from its corner: 20 - 1 = 19 steps.
  EXPECT_EQ(mower_steps_to_cover(5), 19);
  EXPECT_EQ(mower_steps_to_cover(1), 99);
}

TEST(LiuBaselines, AOneRowMowerGoesBackAndForth) {
  const Rect lane{0, 3, 10, 1};
  LawnmowerState s = lawnmower_start(lane);
  for (int i = 0; i < 9; ++i) {
    s = lawnmower_step(s, lane);
  }
  EXPECT_EQ(s.cell, (Cell{9, 3}));
  s = lawnmower_step(s, lane);  // b reversed at the boundary
  EXPECT_EQ(s.cell, (Cell{8, 3}));
  EXPECT_EQ(s.dx, -1);
}

TEST(LiuBaselines, RandomSearchStaysInBoundsAndMovesAtTheConstantStep) {
  const LiuParams p;
  Rng rng(stream_seed(42, "uav", 0));
  for (int i = 0; i < 1000; ++i) {
    const Vec2 d = random_direction(rng);
    EXPECT_NEAR(std::hypot(d.x, d.y), 1.0, 1e-12);
  }
  VisitedCells visited(10, 10);
  for (uint32_t uav = 0; uav < 10; ++uav) {
    LiuUav u{kLiuStartPositions[uav], {}};
    for (int step = 0; step < 2000; ++step) {
      const LiuMove m = random_search_step(u, rng, p);
      ASSERT_GE(m.next.x, 0);
      ASSERT_GE(m.next.y, 0);
      ASSERT_LT(m.next.x, 10);
      ASSERT_LT(m.next.y, 10);
      ASSERT_NEAR(std::hypot(m.velocity.x, m.velocity.y), 10.0, 1e-9);  // S = 10
      visited.visit(m.next);
      u = LiuUav{cell_centre(m.next, p.cell_size_m), m.velocity};
    }
  }
  EXPECT_EQ(visited.count(), 100);
}

TEST(LiuBaselines, BoidsCombineTheThreeRulesAndGuidanceTurnsThem) {
  // UAV at (550, 550). A (450, 550) at 100 m < 120 m: separation (1, 0).
  // B (550, 700) at 150 m: no separation. Mean velocity (0, 10): alignment (0, 1).
  // Centroid (500, 625): cohesion (-50, 75)/90.139 = (-0.5547, 0.8321).
  // Sum (0.4453, 1.8321): 76.3° -> N, next (5, 6).
  // Guided, best cell (6, 4): + (0.7071, -0.7071) = (1.1524, 1.1249): 44.3° -> NE, next (6, 6).
  const LiuParams p;
  const LiuUav self{{550.0, 550.0}, {10.0, 0.0}};
  const std::vector<LiuUav> others{{{450.0, 550.0}, {0.0, 10.0}}, {{550.0, 700.0}, {0.0, 10.0}}};
  const LiuMove plain = boids_step(self, others, p);
  EXPECT_EQ(plain.heading, Heading::N);
  EXPECT_EQ(plain.next, (Cell{5, 6}));
  EXPECT_NEAR(std::hypot(plain.velocity.x, plain.velocity.y), 10.0, 1e-9);
  EXPECT_NEAR(plain.velocity.x, 10.0 * 0.4453 / std::hypot(0.4453, 1.8321), 1e-3);

  std::vector<double> map(100, 0.5);
  map[4 * 10 + 6] = 0.7;
  const LiuMove guided = boids_guided_step(self, others, lookup_of(map), p);
  EXPECT_EQ(guided.heading, Heading::NE);
  EXPECT_EQ(guided.next, (Cell{6, 6}));
}

// --- metrics ----------------------------------------------------------------

TEST(LiuMetrics, VisitedCellsCountsEachCellOnce) {
  VisitedCells v(10, 10);
  EXPECT_TRUE(v.visit(Cell{1, 1}));
  EXPECT_FALSE(v.visit(Cell{1, 1}));
  EXPECT_TRUE(v.visit(Cell{9, 9}));
  EXPECT_FALSE(v.visit(Cell{10, 0}));  // outside
  EXPECT_FALSE(v.visit(Cell{-1, 0}));
  EXPECT_EQ(v.count(), 2);
  EXPECT_TRUE(v.visited(Cell{9, 9}));
  EXPECT_FALSE(v.visited(Cell{0, 0}));
}

TEST(LiuMetrics, StartPositionsOfSection5FallInTheLowerLeftCells) {
  const LiuParams p;
  EXPECT_EQ(cell_of(kLiuStartPositions[0], p), (Cell{1, 1}));
  EXPECT_EQ(cell_of(kLiuStartPositions[9], p), (Cell{2, 5}));
  EXPECT_EQ(cell_of(kLiuTargets[2], p), (Cell{7, 5}));
}

// --- ESUSTPM-disperse (ours, not the paper's) --------------------------------------

TpmLookup no_tpm() {
  return [](Cell) -> std::optional<double> { return std::nullopt; };
}

TEST(LiuDisperse, ANeighbourBeyondTheGivenDistanceNoLongerPulls) {
  // One neighbour 200 m east, no TPM (rule 4 silent). ESUSTPM: β(200) = -586.10
  // along F = (-1, 0) pulls east, mvel = 586.10 / 4 = 146.52 m/s. The variant
  // drops the pull: mvel = 0, and a UAV at rest stays at rest (no heading).
  const LiuParams p;
  const LiuUav self{{550.0, 550.0}, {}};
  const std::vector<LiuUav> others{{{750.0, 550.0}, {}}};
  const Vec2 esustpm = esustpm_objective_velocity(self, others, no_tpm(), p);
  EXPECT_NEAR(esustpm.x, 146.52, 1e-2);
  EXPECT_NEAR(esustpm.y, 0.0, kEps);
  const Vec2 disperse = esustpm_disperse_objective_velocity(self, others, no_tpm(), p);
  EXPECT_NEAR(disperse.x, 0.0, kEps);
  EXPECT_NEAR(disperse.y, 0.0, kEps);
  EXPECT_FALSE(esustpm_disperse_step(self, others, no_tpm(), p).heading.has_value());
  // Moving east at 10 m/s, it keeps that velocity (as esustpm_step does with mvel = 0).
  const LiuMove keep = esustpm_disperse_step({{550.0, 550.0}, {10.0, 0.0}}, others, no_tpm(), p);
  EXPECT_NEAR(keep.velocity.x, 10.0, kEps);
  EXPECT_EQ(keep.next, (Cell{6, 5}));
}

TEST(LiuDisperse, ANeighbourWithinTheGivenDistanceRepelsAsInEsustpm) {
  // Neighbour 100 m west: β(100) = 6116.29 pushes east in both, mvel = 1529.07.
  const LiuParams p;
  const LiuUav self{{550.0, 550.0}, {}};
  const std::vector<LiuUav> others{{{450.0, 550.0}, {}}};
  EXPECT_NEAR(esustpm_objective_velocity(self, others, no_tpm(), p).x, 1529.07, 1e-2);
  EXPECT_NEAR(esustpm_disperse_objective_velocity(self, others, no_tpm(), p).x, 1529.07, 1e-2);
}

TEST(LiuDisperse, RuleFourGuidesAsInEsustpm) {
  // The lone UAV of ALoneUavHeadsForTheMostProbableNeighbouringCell: the best
  // cell 100 m north gives |β(100)| / 4 = 1529.07 north in both.
  std::vector<double> map(100, 0.2);
  map[6 * 10 + 5] = 0.4;
  const LiuParams p;
  const LiuUav self{{550.0, 550.0}, {10.0, 0.0}};
  const Vec2 v = esustpm_disperse_objective_velocity(self, {}, lookup_of(map), p);
  EXPECT_NEAR(v.x, 0.0, kEps);
  EXPECT_NEAR(v.y, 1529.07, 1e-2);
}

// --- the look budget (liu_lowest_eu) ---------------------------------------------------

TEST(LiuLookBudget, LowestEuMatchesHandWorkedAllocations) {
  const LiuParams p;  // q = 0.7 / 0.9 = 7/9, P0 = 0.5
  // Nothing looked at: 100 cells of -0.5 log2 0.5 = 50 bit.
  EXPECT_NEAR(liu_lowest_eu(0, 100, 0, p), 50.0, kEps);
  // One cell, one miss: P = 7/18 = 0.388889, -P log2 P = 0.529888.
  EXPECT_NEAR(liu_lowest_eu(1, 1, 1, p), 0.529888, 1e-6);
  // Two cells, at most three looks: (1, 2) gives 0.529888 + 0.521802 = 1.051690,
  // better than (1, 1) = 1.059777.
  EXPECT_NEAR(liu_lowest_eu(2, 2, 3, p), 1.051690, 1e-6);
  // One of two cells, up to ten looks: all ten on it, P = 0.5 (7/9)^10 = 0.040371,
  // 0.187371 + 0.5 for the other cell.
  EXPECT_NEAR(liu_lowest_eu(1, 2, 10, p), 0.687371, 1e-6);
  // Fewer looks than cells to look at: impossible.
  EXPECT_TRUE(std::isinf(liu_lowest_eu(2, 2, 1, p)));
  EXPECT_TRUE(std::isnan(liu_lowest_eu(3, 2, 5, p)));
}

}  // namespace
}  // namespace pheromesh::core
