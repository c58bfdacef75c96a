// Shao 2020 ACO direction choice (Shao 2020 eq. (9), Shao 2020 eq. (10), Shao 2020 eq. (11)), checked against hand-worked numbers.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/rng.hpp"
#include "pheromesh/core/shao_params.hpp"
#include "pheromesh/shao/aco.hpp"

namespace pheromesh::core {
namespace {

using Values = std::array<float, 3>;  // target, obstacle, path pheromone

// A LocalView over an 11 x 11 map: `known` holds the cells the UAV has tiles
// for (every other cell is unknown), `obstacles` the cells known to be blocked.
struct FakeView {
  std::map<std::pair<int32_t, int32_t>, Values> known;
  std::set<std::pair<int32_t, int32_t>> obstacles;
  int32_t width = 11, height = 11;

  [[nodiscard]] LocalView view() const {
    LocalView v;
    v.pheromones = [this](Cell c) -> std::optional<Values> {
      const auto it = known.find({c.x, c.y});
      if (it == known.end()) {
        return std::nullopt;
      }
      return it->second;
    };
    v.blocked = [this](Cell c) {
      return c.x < 0 || c.y < 0 || c.x >= width || c.y >= height || obstacles.count({c.x, c.y}) != 0;
    };
    return v;
  }
};

constexpr Cell kPos{5, 5};

// Index in the candidate array: turn -2..+2 -> 0..4.
constexpr std::size_t kS = 0, kSE = 1, kE = 2, kNE = 3, kN = 4;

// The hand-worked neighbourhood around (5, 5), heading east, sensor radius 2.5
// (cells with dx² + dy² <= 6.25). Offsets and sectors (bearing ±22.5°):
//   E  (0°):  (1,0) (2,0)
//   NE (45°): (1,1) (2,1) [26.6°] (1,2) [63.4°]
//   N  (90°): (0,1) (0,2)
//   S (-90°): (0,-1) (0,-2)
//   SE(-45°): (1,-1) (2,-1) (1,-2)
FakeView hand_built_view() {
  FakeView f;
  auto put = [&f](int32_t dx, int32_t dy, Values v) { f.known[{kPos.x + dx, kPos.y + dy}] = v; };
  put(1, 0, {1.0F, 0.0F, 0.5F});
  put(2, 0, {0.25F, 0.5F, 1.0F});
  put(1, 1, {0.0F, 0.0F, 2.0F});
  put(2, 1, {0.5F, 0.0F, 1.0F});
  // (1,2) unknown: NE averages over two cells.
  put(0, 1, {0.0F, 2.0F, 0.125F});
  // (0,2) unknown; the whole S sector unknown.
  put(1, -1, {0.5F, 0.5F, 0.5F});
  put(2, -1, {0.25F, 0.25F, 0.25F});
  put(1, -2, {0.0F, 0.0F, 0.75F});
  // Ignored: behind the UAV (W sector) and outside the radius ((2,2): d² = 8).
  put(-1, 0, {100.0F, 0.0F, 0.0F});
  put(2, 2, {50.0F, 0.0F, 0.0F});
  return f;
}

ShaoAcoParams hand_params() {
  ShaoAcoParams p;
  p.alpha = 2.0;
  p.beta = 1.0;
  p.lambda_target = 1.0;
  p.lambda_obstacle = -0.3;
  p.lambda_path = 0.3;
  p.sensor_radius = 2.5;
  return p;
}

// Hand-worked numbers for hand_built_view() with hand_params():
// Sector means (τ, ε, σ):
//   E:  ((1 + 0.25)/2, (0 + 0.5)/2, (0.5 + 1)/2)          = (0.625, 0.25, 0.75)
//   NE: ((0 + 0.5)/2, 0, (2 + 1)/2)                         = (0.25, 0, 1.5)
//   N:  (0, 2, 0.125)                                        (one known cell)
//   S:  (0, 0, 0)                                            (no known cell)
//   SE: ((0.5+0.25+0)/3, (0.5+0.25+0)/3, (0.5+0.25+0.75)/3) = (0.25, 0.25, 0.5)
// Attractiveness λTa τ + λTh ε + λTr σ, floored at 1e-6:
//   E:  0.625 - 0.075 + 0.225 = 0.775
//   NE: 0.25  - 0     + 0.45  = 0.7
//   N:  0     - 0.6   + 0.0375 = -0.5625 -> 1e-6
//   S:  0                              -> 1e-6
//   SE: 0.25  - 0.075 + 0.15  = 0.325
// η_ijk (Shao 2020 eq. (10), Shao 2020 eq. (11)): S, N: 1.4/6 (cardinal, 90°); SE, NE: 5/24 (diagonal,
// 45°); E: 1.4/4 = 0.35 (cardinal, straight).
constexpr double kAttrE = 0.775, kAttrNE = 0.7, kAttrSE = 0.325, kFloor = 1e-6;
constexpr double kEtaCardinal90 = 1.4 / 6.0, kEtaDiagonal45 = 5.0 / 24.0, kEtaStraight = 0.35;
// Numerators a^2 · η of Shao 2020 eq. (9):
constexpr double kNumE = kAttrE * kAttrE * kEtaStraight;       // 0.21021875
constexpr double kNumNE = kAttrNE * kAttrNE * kEtaDiagonal45;  // 0.1020833…
constexpr double kNumSE = kAttrSE * kAttrSE * kEtaDiagonal45;  // 0.0220052…
constexpr double kNumN = kFloor * kFloor * kEtaCardinal90;     // 2.33e-13
constexpr double kNumS = kNumN;

TEST(Aco, StepsAndAnglesFollowCompassOrderCounterClockwiseFromEast) {
  EXPECT_EQ(step_of(Heading::E), (Cell{1, 0}));
  EXPECT_EQ(step_of(Heading::NE), (Cell{1, 1}));
  EXPECT_EQ(step_of(Heading::N), (Cell{0, 1}));
  EXPECT_EQ(step_of(Heading::NW), (Cell{-1, 1}));
  EXPECT_EQ(step_of(Heading::W), (Cell{-1, 0}));
  EXPECT_EQ(step_of(Heading::SW), (Cell{-1, -1}));
  EXPECT_EQ(step_of(Heading::S), (Cell{0, -1}));
  EXPECT_EQ(step_of(Heading::SE), (Cell{1, -1}));
  EXPECT_EQ(rotate(Heading::E, 2), Heading::N);
  EXPECT_EQ(rotate(Heading::E, -1), Heading::SE);
  EXPECT_EQ(rotate(Heading::SE, 3), Heading::N);
  EXPECT_EQ(rotate(Heading::N, -10), Heading::E);
  EXPECT_NEAR(heading_angle(Heading::NW), 3.0 * std::numbers::pi / 4.0, 1e-15);
}

TEST(Aco, EtaFactorsAreThoseOfEquationsTenAndEleven) {
  EXPECT_DOUBLE_EQ(eta_distance(1), 1.4);
  EXPECT_DOUBLE_EQ(eta_distance(2), 1.0);
  EXPECT_DOUBLE_EQ(eta_distance(4), 0.0);
  EXPECT_DOUBLE_EQ(eta_turn(0), 1.0 / 4.0);
  EXPECT_DOUBLE_EQ(eta_turn(1), 5.0 / 24.0);
  EXPECT_DOUBLE_EQ(eta_turn(2), 1.0 / 6.0);
  EXPECT_DOUBLE_EQ(eta_turn(3), 0.0);
}

TEST(Aco, DiagonalHeadingGoesStraightDiagonallyAndTurnsOntoCardinalsAtFortyFiveDegrees) {
  const FakeView f;
  const auto c = evaluate_candidates(kPos, Heading::NE, f.view(), ShaoAcoParams{});
  EXPECT_EQ(c[0].heading, Heading::SE);
  EXPECT_EQ(c[1].heading, Heading::E);
  EXPECT_EQ(c[4].heading, Heading::NW);
  EXPECT_EQ(c[2].next, (Cell{6, 6}));
  EXPECT_NEAR(c[0].eta, 1.0 / 6.0, 1e-12);         // SE: diagonal, 90°
  EXPECT_NEAR(c[1].eta, 1.4 * 5.0 / 24.0, 1e-12);  // E: cardinal, 45°
  EXPECT_NEAR(c[2].eta, 1.0 / 4.0, 1e-12);         // NE: diagonal, straight
  EXPECT_NEAR(c[3].eta, 1.4 * 5.0 / 24.0, 1e-12);  // N: cardinal, 45°
  EXPECT_NEAR(c[4].eta, 1.0 / 6.0, 1e-12);         // NW: diagonal, 90°
}

TEST(Aco, SectorMeansOfHandBuiltNeighbourhoodMatchHandWorkedNumbers) {
  const FakeView f = hand_built_view();
  const auto c = evaluate_candidates(kPos, Heading::E, f.view(), hand_params());
  EXPECT_EQ(c[kS].heading, Heading::S);
  EXPECT_EQ(c[kS].next, (Cell{5, 4}));
  EXPECT_EQ(c[kE].next, (Cell{6, 5}));
  EXPECT_EQ(c[kN].next, (Cell{5, 6}));
  EXPECT_NEAR(c[kE].tau, 0.625, 1e-9);
  EXPECT_NEAR(c[kE].eps, 0.25, 1e-9);
  EXPECT_NEAR(c[kE].sigma, 0.75, 1e-9);
  EXPECT_NEAR(c[kNE].tau, 0.25, 1e-9);
  EXPECT_NEAR(c[kNE].eps, 0.0, 1e-9);
  EXPECT_NEAR(c[kNE].sigma, 1.5, 1e-9);
  EXPECT_NEAR(c[kN].eps, 2.0, 1e-9);
  EXPECT_NEAR(c[kN].sigma, 0.125, 1e-9);
  EXPECT_NEAR(c[kS].tau + c[kS].eps + c[kS].sigma, 0.0, 1e-12);
  EXPECT_NEAR(c[kSE].tau, 0.25, 1e-9);
  EXPECT_NEAR(c[kSE].eps, 0.25, 1e-9);
  EXPECT_NEAR(c[kSE].sigma, 0.5, 1e-9);
}

TEST(Aco, ProbabilitiesOfHandBuiltNeighbourhoodMatchHandWorkedNumbers) {
  const FakeView f = hand_built_view();
  const auto c = evaluate_candidates(kPos, Heading::E, f.view(), hand_params());

  EXPECT_NEAR(c[kE].attractiveness, kAttrE, 1e-9);
  EXPECT_NEAR(c[kNE].attractiveness, kAttrNE, 1e-9);
  EXPECT_NEAR(c[kSE].attractiveness, kAttrSE, 1e-9);
  EXPECT_DOUBLE_EQ(c[kN].attractiveness, kFloor);  // negative base clamped
  EXPECT_DOUBLE_EQ(c[kS].attractiveness, kFloor);  // unknown sector

  EXPECT_NEAR(c[kS].eta, kEtaCardinal90, 1e-12);
  EXPECT_NEAR(c[kSE].eta, kEtaDiagonal45, 1e-12);
  EXPECT_NEAR(c[kE].eta, kEtaStraight, 1e-12);
  EXPECT_NEAR(c[kNE].eta, kEtaDiagonal45, 1e-12);
  EXPECT_NEAR(c[kN].eta, kEtaCardinal90, 1e-12);

  // Sum = 0.21021875 + 0.1020833… + 0.0220052… + 4.7e-13 = 0.3343073…
  // P_E ≈ 0.62882, P_NE ≈ 0.30536, P_SE ≈ 0.06582.
  const double sum = kNumE + kNumNE + kNumSE + kNumN + kNumS;
  EXPECT_NEAR(c[kE].probability, kNumE / sum, 1e-9);
  EXPECT_NEAR(c[kNE].probability, kNumNE / sum, 1e-9);
  EXPECT_NEAR(c[kSE].probability, kNumSE / sum, 1e-9);
  EXPECT_NEAR(c[kN].probability, kNumN / sum, 1e-9);
  EXPECT_NEAR(c[kS].probability, kNumS / sum, 1e-9);
  EXPECT_NEAR(c[kE].probability, 0.62882, 1e-5);

  // Random sub-group: η^β only. Σ η = 2·1.4/6 + 2·5/24 + 0.35 = 1.2333…
  const double eta_sum = 2 * kEtaCardinal90 + 2 * kEtaDiagonal45 + kEtaStraight;
  EXPECT_NEAR(c[kE].random_probability, kEtaStraight / eta_sum, 1e-9);
  EXPECT_NEAR(c[kN].random_probability, kEtaCardinal90 / eta_sum, 1e-9);
  EXPECT_NEAR(c[kSE].random_probability, kEtaDiagonal45 / eta_sum, 1e-9);
  for (const Candidate& x : c) {
    EXPECT_TRUE(x.accessible);
  }
}

TEST(Aco, BetaExponentWeighsPhysicalCosts) {
  const FakeView f = hand_built_view();
  ShaoAcoParams p = hand_params();
  p.beta = 2.0;
  const auto c = evaluate_candidates(kPos, Heading::E, f.view(), p);
  // Numerators a^2 · η^2.
  const double e = kNumE * kEtaStraight, ne = kNumNE * kEtaDiagonal45, se = kNumSE * kEtaDiagonal45;
  const double n = kNumN * kEtaCardinal90;
  const double sum = e + ne + se + 2 * n;
  EXPECT_NEAR(c[kE].probability, e / sum, 1e-9);
  EXPECT_NEAR(c[kNE].probability, ne / sum, 1e-9);
  EXPECT_NEAR(c[kSE].probability, se / sum, 1e-9);
}

TEST(Aco, BlockedCandidateGetsZeroProbabilityAndOthersRenormalise) {
  FakeView f = hand_built_view();
  f.obstacles.insert({6, 5});  // straight ahead
  const auto c = evaluate_candidates(kPos, Heading::E, f.view(), hand_params());
  EXPECT_FALSE(c[kE].accessible);
  EXPECT_EQ(c[kE].probability, 0.0);
  EXPECT_EQ(c[kE].random_probability, 0.0);
  const double sum = kNumNE + kNumSE + kNumN + kNumS;
  EXPECT_NEAR(c[kNE].probability, kNumNE / sum, 1e-9);
  EXPECT_NEAR(c[kSE].probability, kNumSE / sum, 1e-9);
  const double eta_sum = 2 * kEtaCardinal90 + 2 * kEtaDiagonal45;
  EXPECT_NEAR(c[kNE].random_probability, kEtaDiagonal45 / eta_sum, 1e-9);
}

TEST(Aco, CandidatesOffTheMapAreNotAccessible) {
  const FakeView f;
  const auto c = evaluate_candidates(Cell{10, 5}, Heading::E, f.view(), ShaoAcoParams{});
  EXPECT_FALSE(c[kSE].accessible);
  EXPECT_FALSE(c[kE].accessible);
  EXPECT_FALSE(c[kNE].accessible);
  EXPECT_TRUE(c[kN].accessible);
  EXPECT_NEAR(c[kN].probability + c[kS].probability, 1.0, 1e-12);
}

TEST(Aco, DecideReturnsNothingWhenEveryCandidateIsBlocked) {
  FakeView f = hand_built_view();
  for (const auto& [dx, dy] : {std::pair{1, 0}, {1, 1}, {0, 1}, {0, -1}, {1, -1}}) {
    f.obstacles.insert({kPos.x + dx, kPos.y + dy});
  }
  Rng rng(7);
  for (const double fraction : {0.0, 1.0}) {
    ShaoAcoParams p = hand_params();
    p.random_fraction = fraction;
    const Decision d = decide(kPos, Heading::E, f.view(), p, rng);
    EXPECT_FALSE(d.chosen.has_value());
    EXPECT_EQ(d.random_group, fraction > 0.5);
  }
}

TEST(Aco, InformationGroupAlwaysTakesTheMostProbableCandidate) {
  const FakeView f = hand_built_view();
  ShaoAcoParams p = hand_params();
  p.random_fraction = 0.0;
  Rng rng(42);
  for (int i = 0; i < 200; ++i) {
    const Decision d = decide(kPos, Heading::E, f.view(), p, rng);
    ASSERT_TRUE(d.chosen.has_value());
    EXPECT_FALSE(d.random_group);
    EXPECT_EQ(d.chosen->heading, Heading::E);
    EXPECT_EQ(d.chosen->next, (Cell{6, 5}));
  }
}

TEST(Aco, TiesBetweenMostProbableCandidatesAreBrokenByTheStream) {
  // Nothing known and straight ahead blocked: N and S (η = 1.4/6) tie above
  // NE and SE (η = 5/24).
  FakeView f;
  f.obstacles.insert({6, 5});
  ShaoAcoParams p;
  p.random_fraction = 0.0;
  Rng rng(3);
  int north = 0, south = 0;
  constexpr int kDraws = 4000;
  for (int i = 0; i < kDraws; ++i) {
    const Decision d = decide(kPos, Heading::E, f.view(), p, rng);
    ASSERT_TRUE(d.chosen.has_value());
    north += d.chosen->heading == Heading::N ? 1 : 0;
    south += d.chosen->heading == Heading::S ? 1 : 0;
  }
  EXPECT_EQ(north + south, kDraws);
  EXPECT_NEAR(static_cast<double>(north) / kDraws, 0.5, 0.05);
}

TEST(Aco, RandomGroupChoosesInProportionToPhysicalCostsOnly) {
  // The pheromones favour E strongly, but the random sub-group ignores them.
  const FakeView f = hand_built_view();
  ShaoAcoParams p = hand_params();
  p.random_fraction = 1.0;
  Rng rng(2020);
  std::array<int, 5> counts{};
  constexpr int kDraws = 20000;
  for (int i = 0; i < kDraws; ++i) {
    const Decision d = decide(kPos, Heading::E, f.view(), p, rng);
    ASSERT_TRUE(d.chosen.has_value());
    EXPECT_TRUE(d.random_group);
    ++counts[static_cast<std::size_t>(d.chosen->turn_eighths + 2)];
  }
  // η proportions: 0.1892, 0.1689, 0.2838, 0.1689, 0.1892; the standard error
  // of each frequency is about 0.003, the bound is five times that.
  const double eta_sum = 2 * kEtaCardinal90 + 2 * kEtaDiagonal45 + kEtaStraight;
  const std::array<double, 5> expected{kEtaCardinal90 / eta_sum, kEtaDiagonal45 / eta_sum, kEtaStraight / eta_sum,
                                       kEtaDiagonal45 / eta_sum, kEtaCardinal90 / eta_sum};
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_NEAR(static_cast<double>(counts[i]) / kDraws, expected[i], 0.015) << "candidate " << i;
  }
}

TEST(Aco, SameSeedGivesTheSameDecisions) {
  const FakeView f = hand_built_view();
  ShaoAcoParams p = hand_params();
  p.random_fraction = 0.5;
  auto run = [&](uint64_t seed) {
    Rng rng(seed);
    std::vector<std::pair<int, bool>> out;
    for (int i = 0; i < 500; ++i) {
      const Decision d = decide(kPos, Heading::E, f.view(), p, rng);
      out.emplace_back(d.chosen ? d.chosen->turn_eighths : 99, d.random_group);
    }
    return out;
  };
  const auto a = run(11);
  EXPECT_EQ(a, run(11));
  EXPECT_NE(a, run(12));
}

}  // namespace
}  // namespace pheromesh::core
