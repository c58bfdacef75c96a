// Shao 2020 Sec. 5 navigation via flocking and stigmergy (Shao 2020 eq. (12), Shao 2020 eq. (13), Shao 2020 eq. (14), Shao 2020 eq. (15), Shao 2020 eq. (16), Shao 2020 eq. (17), Shao 2020 eq. (18), Shao 2020 eq. (19), Shao 2020 eq. (20), Shao 2020 eq. (21), Shao 2020 eq. (22), Shao 2020 eq. (23), Shao 2020 eq. (24),
// Shao 2020 Algorithm 2), checked against hand-worked numbers.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <utility>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/shao/aco.hpp"
#include "pheromesh/shao/navigation.hpp"

namespace pheromesh::core {
namespace {

using Eigen::Vector2d;
using Values = std::array<float, 3>;  // target, obstacle, path pheromone

constexpr double kTol = 1e-9;

// Pheromones known at a few cells only; every other cell is unknown.
PheromoneLookup sparse(const std::map<std::pair<int32_t, int32_t>, Values>& known) {
  return [known](Cell c) -> std::optional<Values> {
    const auto it = known.find({c.x, c.y});
    if (it == known.end()) {
      return std::nullopt;
    }
    return it->second;
  };
}

// The hand-built neighbourhood of a leader at q = (0, 0):
//   i = (0,0): τ=1            (the leader's own cell, reference of Shao 2020 eq. (12))
//   A = (3,1): τ=6            bearing 18.4° -> sector E
//   B = (0,2): τ=1, ε=eps_b   bearing 90°   -> sector N
//   C = (4,0): τ=1, σ=2       bearing 0°    -> sector E
std::map<std::pair<int32_t, int32_t>, Values> hand_neighbourhood(float eps_b) {
  return {{{0, 0}, {1.0F, 0.0F, 0.0F}},
          {{3, 1}, {6.0F, 0.0F, 0.0F}},
          {{0, 2}, {1.0F, eps_b, 0.0F}},
          {{4, 0}, {1.0F, 0.0F, 2.0F}}};
}

void expect_near(const Vector2d& actual, double x, double y) {
  EXPECT_NEAR(actual.x(), x, kTol);
  EXPECT_NEAR(actual.y(), y, kTol);
}

TEST(ShaoNav, ParametersAreThoseOfTableTwo) {
  const ShaoNavParams p;
  EXPECT_EQ(p.leader_sensor_radius, 5.0);
  EXPECT_EQ(p.rho, 2.0);
  EXPECT_EQ(p.lambda_target, 1.0);
  EXPECT_EQ(p.lambda_obstacle, -0.3);
  EXPECT_EQ(p.lambda_path, 0.3);
  EXPECT_EQ(p.epsilon, 0.1);
  EXPECT_EQ(p.h, 0.5);
  EXPECT_EQ(p.c1, 0.6);
  EXPECT_EQ(p.c2, 0.4);
  EXPECT_EQ(p.follower_range, 4.0);  // not in Shao 2020 Sec. 5; Shao 2020 Table 1's SD
}

TEST(ShaoNav, SigmaNormOfThreeFourIsEquationEighteen) {
  // ‖z‖ = 5: (√(1 + 0.1·25) - 1)/0.1 = (√3.5 - 1)/0.1 = 8.70828693386970...
  EXPECT_NEAR(sigma_norm(Vector2d{3.0, 4.0}, 0.1), 8.70828693386970693, kTol);
  EXPECT_EQ(sigma_norm(Vector2d::Zero(), 0.1), 0.0);
  // Small z: ‖z‖_σ ≈ ‖z‖²/2, without cancellation.
  EXPECT_NEAR(sigma_norm(Vector2d{1e-8, 0.0}, 0.1) / 5e-17, 1.0, 1e-12);
}

TEST(ShaoNav, BumpIsOneUpToHThenCosineDownToZeroAtOne) {
  // h = 0.5: ρh(0.75) = ½(1 + cos(π·0.25/0.5)) = ½(1 + cos(π/2)) = 0.5.
  EXPECT_NEAR(bump(0.0, 0.5), 1.0, kTol);
  EXPECT_NEAR(bump(0.5, 0.5), 1.0, kTol);  // ½(1 + cos 0)
  EXPECT_NEAR(bump(0.75, 0.5), 0.5, kTol);
  EXPECT_NEAR(bump(1.0, 0.5), 0.0, kTol);
  EXPECT_NEAR(bump(1.2, 0.5), 0.0, kTol);
  EXPECT_NEAR(bump(-0.1, 0.5), 0.0, kTol);
}

TEST(ShaoNav, PhiAlphaIsTheInverse) {
  EXPECT_NEAR(phi_alpha(4.0), 0.25, kTol);
  EXPECT_EQ(phi_alpha(0.0), std::numeric_limits<double>::infinity());
}

TEST(ShaoNav, SectorsAreCentredOnTheCompassHeadings) {
  EXPECT_EQ(nav_sector_of(Vector2d{1.0, 0.0}), Heading::E);
  EXPECT_EQ(nav_sector_of(Vector2d{3.0, 1.0}), Heading::E);  // 18.4°
  EXPECT_EQ(nav_sector_of(Vector2d{2.0, 1.0}), Heading::NE);  // 26.6°
  EXPECT_EQ(nav_sector_of(Vector2d{0.0, 2.0}), Heading::N);
  EXPECT_EQ(nav_sector_of(Vector2d{-1.0, -1.0}), Heading::SW);
  EXPECT_EQ(nav_sector_of(Vector2d{1.0, -3.0}), Heading::S);  // -71.6°
}

TEST(ShaoNav, VectorLeaderOfHandBuiltNeighbourhoodMatchesEquationsTwelveToFifteen) {
  const ShaoNavParams p;
  const LeaderStep s = leader_vector_step(Vector2d::Zero(), sparse(hand_neighbourhood(4.0F)), p);
  // Shao 2020 eq. (12), τ_ij = (τ(i) - τ(j))·(q_i - q_j)/‖q_i - q_j‖²:
  //   A: (1 - 6)/10 · (-3, -1) = (1.5, 0.5)        (towards A, more target pheromone)
  //   B: ε: (0 - 4)/4 · (0, -2) = (0, 2)           (towards B, more obstacle pheromone)
  //   C: σ: (0 - 2)/16 · (-4, 0) = (0.5, 0)
  // Shao 2020 eq. (13), Shao 2020 eq. (14) with λ = (1, -0.3, 0.3):
  //   s_E = (1.5, 0.5) + 0.3·(0.5, 0) = (1.65, 0.5), ‖s_E‖ = √2.9725 = 1.72409396...
  //   s_N = -0.3·(0, 2) = (0, -0.6),                 ‖s_N‖ = 0.6
  expect_near(s.sector_sums[static_cast<std::size_t>(Heading::E)], 1.65, 0.5);
  expect_near(s.sector_sums[static_cast<std::size_t>(Heading::N)], 0.0, -0.6);
  EXPECT_NEAR(s.sector_scores[static_cast<std::size_t>(Heading::E)], 1.72409396495666674, kTol);
  EXPECT_EQ(s.sector_cells[static_cast<std::size_t>(Heading::E)], 2);
  EXPECT_EQ(s.sector_cells[static_cast<std::size_t>(Heading::N)], 1);
  for (const Heading h : {Heading::NE, Heading::NW, Heading::W, Heading::SW, Heading::S, Heading::SE}) {
    EXPECT_EQ(s.sector_cells[static_cast<std::size_t>(h)], 0);
    expect_near(s.sector_sums[static_cast<std::size_t>(h)], 0.0, 0.0);
  }
  // Largest ‖s_d‖ is E; Shao 2020 eq. (15): v = 2·(1.65, 0.5)/1.72409396 = (1.91404881, 0.58001479).
  ASSERT_TRUE(s.sector.has_value());
  EXPECT_EQ(*s.sector, Heading::E);
  expect_near(s.v, 1.91404880886694710, 0.58001479056574154);
  EXPECT_NEAR(s.v.norm(), 2.0, kTol);
  expect_near(s.q, 1.91404880886694710, 0.58001479056574154);
  EXPECT_FALSE(s.heading_to_centre);
}

TEST(ShaoNav, StrongObstaclePheromoneDrivesVectorLeaderAwayFromIt) {
  const ShaoNavParams p;
  // ε(B) = 12: ε_iB = (0 - 12)/4 · (0, -2) = (0, 6), s_N = -0.3·(0, 6) = (0, -1.8),
  // ‖s_N‖ = 1.8 > ‖s_E‖ = 1.724: the leader moves v = 2·(0, -1) away from B.
  const LeaderStep s = leader_vector_step(Vector2d::Zero(), sparse(hand_neighbourhood(12.0F)), p);
  ASSERT_TRUE(s.sector.has_value());
  EXPECT_EQ(*s.sector, Heading::N);
  expect_near(s.v, 0.0, -2.0);
  expect_near(s.q, 0.0, -2.0);
}

TEST(ShaoNav, ScalarLeaderOfHandBuiltNeighbourhoodTakesTheBestSectorMean) {
  const ShaoNavParams p;
  const LeaderStep s = leader_scalar_step(Vector2d::Zero(), sparse(hand_neighbourhood(4.0F)), p);
  // Weighted sums λ·(τ, ε, σ): A = 6, C = 1 + 0.3·2 = 1.6 -> mean E = 3.8;
  // B = 1 - 0.3·4 = -0.2 -> mean N = -0.2. The own cell has no bearing and is not used.
  EXPECT_NEAR(s.sector_scores[static_cast<std::size_t>(Heading::E)], 3.8, kTol);
  EXPECT_NEAR(s.sector_scores[static_cast<std::size_t>(Heading::N)], -0.2, kTol);
  ASSERT_TRUE(s.sector.has_value());
  EXPECT_EQ(*s.sector, Heading::E);
  expect_near(s.v, 2.0, 0.0);  // ρ along the sector's bisector
}

TEST(ShaoNav, ProjectionReadingSkipsASectorWhoseVectorPointsBackOutOfIt) {
  ShaoNavParams p;
  p.vector_choice = VectorSectorChoice::Projection;
  // The neighbourhood of StrongObstaclePheromoneDrivesVectorLeaderAwayFromIt:
  // s_E = (1.65, 0.5), s_N = (0, -1.8). Along the bisectors (1, 0) and (0, 1):
  // s_E·u_E = 1.65, s_N·u_N = -1.8 (s_N points back out of N: no candidate).
  const LeaderStep s = leader_vector_step(Vector2d::Zero(), sparse(hand_neighbourhood(12.0F)), p);
  EXPECT_NEAR(s.sector_scores[static_cast<std::size_t>(Heading::E)], 1.65, kTol);
  EXPECT_NEAR(s.sector_scores[static_cast<std::size_t>(Heading::N)], -1.8, kTol);
  ASSERT_TRUE(s.sector.has_value());
  EXPECT_EQ(*s.sector, Heading::E);
  // Shao 2020 eq. (15) along s_E itself, as under the norm reading of the ε = 4 case.
  expect_near(s.v, 1.91404880886694710, 0.58001479056574154);
}

TEST(ShaoNav, ProjectionReadingStaysWhenNoSectorPullsOutwards) {
  ShaoNavParams p;
  p.vector_choice = VectorSectorChoice::Projection;
  // The leader sits on a peak: its one neighbour E has less target pheromone,
  // τ_ij = (2 - 1)/1 · (-1, 0) = (-1, 0) points back out of E (score -1).
  const LeaderStep s =
      leader_vector_step(Vector2d::Zero(), sparse({{{0, 0}, {2.0F, 0.0F, 0.0F}}, {{1, 0}, {1.0F, 0.0F, 0.0F}}}), p);
  EXPECT_NEAR(s.sector_scores[static_cast<std::size_t>(Heading::E)], -1.0, kTol);
  EXPECT_FALSE(s.sector.has_value());
  expect_near(s.v, 0.0, 0.0);
  // The norm reading takes that sector anyway and moves back over the peak.
  const LeaderStep n =
      leader_vector_step(Vector2d::Zero(), sparse({{{0, 0}, {2.0F, 0.0F, 0.0F}}, {{1, 0}, {1.0F, 0.0F, 0.0F}}}), {});
  ASSERT_TRUE(n.sector.has_value());
  expect_near(n.v, -2.0, 0.0);
}

TEST(ShaoNav, GradientVariantFliesAlongTheSumOfAllSectorVectors) {
  const ShaoNavParams p;
  // s_E + s_N = (1.65, 0.5) + (0, -1.8) = (1.65, -1.3), norm √4.4125 = 2.10059515376;
  // v = 2·(1.65, -1.3)/2.10059515376 = (1.57098334446, -1.23774445321).
  const LeaderStep s = leader_gradient_step(Vector2d::Zero(), sparse(hand_neighbourhood(12.0F)), p);
  EXPECT_FALSE(s.sector.has_value());
  expect_near(s.sector_sums[static_cast<std::size_t>(Heading::N)], 0.0, -1.8);
  expect_near(s.v, 1.5709833444550712, -1.2377444532070259);
  expect_near(s.q, 1.5709833444550712, -1.2377444532070259);
  // Shao 2020 Algorithm 2 hands the step to it when asked for the variant.
  const LeaderStep a = leader_algorithm2_step(Vector2d::Zero(), Vector2d{50.0, 50.0}, sparse(hand_neighbourhood(12.0F)),
                                              p, LeaderPheromones::Gradient);
  expect_near(a.v, 1.5709833444550712, -1.2377444532070259);
  // A flat field has no gradient: the leader stays.
  const LeaderStep flat =
      leader_gradient_step(Vector2d::Zero(), sparse({{{0, 0}, {1.0F, 0.0F, 0.0F}}, {{1, 0}, {1.0F, 0.0F, 0.0F}}}), p);
  expect_near(flat.v, 0.0, 0.0);
}

TEST(ShaoNav, PullVariantSumsOnlyTheSectorVectorsThatPullOutwards) {
  const ShaoNavParams p;
  // s_E = (1.65, 0.5) pulls into E (1.65 > 0); s_N = (0, -1.8) pushes back out of N:
  // left out, so v = ρ s_E/‖s_E‖ = (1.91404880886694710, 0.58001479056574154).
  const LeaderStep s = leader_pull_step(Vector2d::Zero(), sparse(hand_neighbourhood(12.0F)), p);
  EXPECT_FALSE(s.sector.has_value());
  EXPECT_NEAR(s.sector_scores[static_cast<std::size_t>(Heading::N)], -1.8, kTol);
  expect_near(s.v, 1.91404880886694710, 0.58001479056574154);
  // Two sectors pull: A = (3,1) τ = 6 gives s_E = (1.5, 0.5); (0,2) τ = 3 gives
  // τ_ij = (1 - 3)/4 · (0, -2) = (0, 1) = s_N. Sum (1.5, 1.5): v = 2·(1, 1)/√2 = (√2, √2).
  const auto two = sparse({{{0, 0}, {1.0F, 0.0F, 0.0F}}, {{3, 1}, {6.0F, 0.0F, 0.0F}}, {{0, 2}, {3.0F, 0.0F, 0.0F}}});
  const LeaderStep t = leader_pull_step(Vector2d::Zero(), two, p);
  expect_near(t.v, std::numbers::sqrt2, std::numbers::sqrt2);
  const LeaderStep a = leader_algorithm2_step(Vector2d::Zero(), Vector2d{50.0, 50.0}, two, p, LeaderPheromones::Pull);
  expect_near(a.v, std::numbers::sqrt2, std::numbers::sqrt2);
  // On a peak nothing pulls outwards: the leader stays.
  const LeaderStep peak =
      leader_pull_step(Vector2d::Zero(), sparse({{{0, 0}, {2.0F, 0.0F, 0.0F}}, {{1, 0}, {1.0F, 0.0F, 0.0F}}}), p);
  expect_near(peak.v, 0.0, 0.0);
}

// Sectors E, N and W with target pheromone only (λTa = 1):
//   E: (4,0) = 5                    -> mean 5, sum 5,  max 5
//   N: (0,2), (0,3), (1,4) = 4 each -> mean 4, sum 12, max 4
//   W: (-2,0) = 8, (-3,0) = 0       -> mean 4, sum 8,  max 8
std::map<std::pair<int32_t, int32_t>, Values> three_sector_neighbourhood() {
  return {{{4, 0}, {5.0F, 0.0F, 0.0F}}, {{0, 2}, {4.0F, 0.0F, 0.0F}},  {{0, 3}, {4.0F, 0.0F, 0.0F}},
          {{1, 4}, {4.0F, 0.0F, 0.0F}}, {{-2, 0}, {8.0F, 0.0F, 0.0F}}, {{-3, 0}, {0.0F, 0.0F, 0.0F}}};
}

TEST(ShaoNav, ScalarSectorScoresMeanSumAndMaxPickDifferentSectors) {
  ShaoNavParams p;
  const auto field = sparse(three_sector_neighbourhood());
  const LeaderStep mean = leader_scalar_step(Vector2d::Zero(), field, p);
  EXPECT_NEAR(mean.sector_scores[static_cast<std::size_t>(Heading::W)], 4.0, kTol);
  ASSERT_TRUE(mean.sector.has_value());
  EXPECT_EQ(*mean.sector, Heading::E);
  p.scalar_score = ScalarSectorScore::Sum;
  const LeaderStep sum = leader_scalar_step(Vector2d::Zero(), field, p);
  EXPECT_NEAR(sum.sector_scores[static_cast<std::size_t>(Heading::N)], 12.0, kTol);
  ASSERT_TRUE(sum.sector.has_value());
  EXPECT_EQ(*sum.sector, Heading::N);
  expect_near(sum.v, 0.0, 2.0);
  p.scalar_score = ScalarSectorScore::Max;
  const LeaderStep max = leader_scalar_step(Vector2d::Zero(), field, p);
  EXPECT_NEAR(max.sector_scores[static_cast<std::size_t>(Heading::W)], 8.0, kTol);
  ASSERT_TRUE(max.sector.has_value());
  EXPECT_EQ(*max.sector, Heading::W);
  expect_near(max.v, -2.0, 0.0);
}

TEST(ShaoNav, ScalarLatticeStepIsOneCellOnAnAxisAndTwoRootTwoHalvesOnADiagonal) {
  ShaoNavParams p;
  p.scalar_step = ScalarLeaderStep::Lattice;
  const LeaderStep axis = leader_scalar_step(Vector2d::Zero(), sparse(three_sector_neighbourhood()), p);
  expect_near(axis.v, 1.0, 0.0);  // E, one cell
  // Only NE known: √2 along 45°, i.e. one cell in x and in y.
  const LeaderStep diag = leader_scalar_step(Vector2d{0.5, 0.0}, sparse({{{2, 2}, {1.0F, 0.0F, 0.0F}}}), p);
  ASSERT_TRUE(diag.sector.has_value());
  EXPECT_EQ(*diag.sector, Heading::NE);
  expect_near(diag.v, 1.0, 1.0);
  expect_near(diag.q, 1.5, 1.0);
}

TEST(ShaoNav, ScalarLeaderIgnoresSectorsWithoutKnownCells) {
  const ShaoNavParams p;
  // Only an obstacle-laden cell north is known: its mean -0.3·4 = -1.2 < 0 still wins over
  // sectors with nothing known (they take no part rather than counting as 0).
  const LeaderStep s = leader_scalar_step(Vector2d::Zero(), sparse({{{0, 2}, {0.0F, 4.0F, 0.0F}}}), p);
  ASSERT_TRUE(s.sector.has_value());
  EXPECT_EQ(*s.sector, Heading::N);
  expect_near(s.v, 0.0, 2.0);
}

TEST(ShaoNav, VectorLeaderIsAttractedUpALinearGradient) {
  const ShaoNavParams p;
  // τ = 100 + x: every τ_ij = (x_j - x_i)·(q_j - q_i)/‖q_j - q_i‖², whose y parts
  // cancel between mirror cells, so the E and W sectors tie at the largest norm
  // (ties go to E) and v = (2, 0).
  const PheromoneLookup east = [](Cell c) -> std::optional<Values> {
    return Values{static_cast<float>(100 + c.x), 0.0F, 0.0F};
  };
  const LeaderStep s = leader_vector_step(Vector2d{10.0, 10.0}, east, p);
  ASSERT_TRUE(s.sector.has_value());
  EXPECT_EQ(*s.sector, Heading::E);
  expect_near(s.v, 2.0, 0.0);
  expect_near(s.q, 12.0, 10.0);
  EXPECT_NEAR(s.sector_scores[static_cast<std::size_t>(Heading::W)],
              s.sector_scores[static_cast<std::size_t>(Heading::E)], kTol);

  // τ = 100 + x + y, mirror-symmetric about the diagonal: v = (√2, √2).
  const PheromoneLookup north_east = [](Cell c) -> std::optional<Values> {
    return Values{static_cast<float>(100 + c.x + c.y), 0.0F, 0.0F};
  };
  const LeaderStep d = leader_vector_step(Vector2d{10.0, 10.0}, north_east, p);
  expect_near(d.v, std::sqrt(2.0), std::sqrt(2.0));

  // Off the lattice and for gradients between the axes the leader still climbs.
  for (const double angle : {0.3, 0.7, 1.2, 2.0, 3.0, 4.0, 5.5}) {
    const Vector2d g{std::cos(angle), std::sin(angle)};
    const PheromoneLookup field = [g](Cell c) -> std::optional<Values> {
      return Values{static_cast<float>(50.0 + g.x() * c.x + g.y() * c.y), 0.0F, 0.0F};
    };
    const LeaderStep t = leader_vector_step(Vector2d{20.3, 19.6}, field, p);
    EXPECT_NEAR(t.v.norm(), 2.0, kTol) << "angle " << angle;
    EXPECT_GT(t.v.dot(g), 2.0 * std::cos(std::numbers::pi / 4.0) - 1e-6) << "angle " << angle;  // within 45°
  }
}

TEST(ShaoNav, LeaderStaysWhenItHasNothingToFollow) {
  const ShaoNavParams p;
  const PheromoneLookup flat = [](Cell) -> std::optional<Values> { return Values{1.0F, 0.0F, 2.0F}; };
  const LeaderStep f = leader_vector_step(Vector2d{5.0, 5.0}, flat, p);
  EXPECT_FALSE(f.sector.has_value());
  expect_near(f.v, 0.0, 0.0);
  expect_near(f.q, 5.0, 5.0);

  // Its own cell unknown: Shao 2020 eq. (12) has no reference value.
  auto known = hand_neighbourhood(4.0F);
  known.erase({0, 0});
  const LeaderStep u = leader_vector_step(Vector2d::Zero(), sparse(known), p);
  EXPECT_FALSE(u.sector.has_value());
  expect_near(u.q, 0.0, 0.0);

  // Nothing known at all, and a non-finite position.
  const LeaderStep n = leader_scalar_step(Vector2d::Zero(), sparse({}), p);
  EXPECT_FALSE(n.sector.has_value());
  const LeaderStep bad = leader_vector_step(Vector2d{std::nan(""), 0.0}, flat, p);
  EXPECT_FALSE(bad.sector.has_value());
}

TEST(ShaoNav, CentreWithinSensorRadiusSwitchesLeaderToGoThereAndBecomeFollower) {
  const ShaoNavParams p;
  const Vector2d centre{50.0, 50.0};
  EXPECT_TRUE(leader_reaches_centre(Vector2d{45.0, 50.0}, centre, p));  // distance 5 = sensorLD
  EXPECT_FALSE(leader_reaches_centre(Vector2d{44.999, 50.0}, centre, p));
  EXPECT_TRUE(leader_reaches_centre(Vector2d{47.0, 46.0}, centre, p));  // distance 5
  EXPECT_FALSE(leader_reaches_centre(Vector2d{std::nan(""), 50.0}, centre, p));

  // A field pulling the other way is ignored once the centre is in range.
  const PheromoneLookup west = [](Cell c) -> std::optional<Values> {
    return Values{static_cast<float>(100 - c.x), 0.0F, 0.0F};
  };
  // Distance 3: ρ = 2 towards the centre, not there yet.
  const LeaderStep a = leader_algorithm2_step(Vector2d{47.0, 50.0}, centre, west, p);
  EXPECT_TRUE(a.heading_to_centre);
  EXPECT_FALSE(a.at_centre);
  expect_near(a.v, 2.0, 0.0);
  expect_near(a.q, 49.0, 50.0);
  // Distance 1: arrives, becomes a follower.
  const LeaderStep b = leader_algorithm2_step(a.q, centre, west, p);
  EXPECT_TRUE(b.at_centre);
  expect_near(b.v, 1.0, 0.0);
  expect_near(b.q, 50.0, 50.0);
  // Out of range: the pheromone step (west here).
  const LeaderStep c = leader_algorithm2_step(Vector2d{40.0, 50.0}, centre, west, p);
  EXPECT_FALSE(c.heading_to_centre);
  expect_near(c.v, -2.0, 0.0);
}

// Not the paper's Shao 2020 Fig. 10 (its field cannot be rebuilt from the text): a
// closed-loop run of Shao 2020 Algorithm 2 on a cone-shaped target field.
TEST(ShaoNav, VectorLeaderClimbsAConeFieldToTheCentreAtSpeedRho) {
  const ShaoNavParams p;
  const Vector2d centre{80.0, 75.0};
  const PheromoneLookup cone = [centre](Cell c) -> std::optional<Values> {
    if (c.x < 0 || c.y < 0 || c.x >= 100 || c.y >= 100) {
      return std::nullopt;
    }
    const double d = (Vector2d{static_cast<double>(c.x), static_cast<double>(c.y)} - centre).norm();
    return Values{static_cast<float>(200.0 - d), 0.0F, 0.0F};
  };
  Vector2d q{10.0, 20.0};
  // Straight line: ‖(70, 55)‖ = 89.02 cells, at least 45 ticks at ρ = 2.
  const int bound = 49;  // within 10 %
  int ticks = 0;
  bool arrived = false;
  while (!arrived && ticks < bound) {
    const LeaderStep s = leader_algorithm2_step(q, centre, cone, p);
    if (!s.heading_to_centre) {
      ASSERT_NEAR(s.v.norm(), 2.0, kTol);
      ASSERT_LT((s.q - centre).norm(), (q - centre).norm());  // every step climbs
    }
    q = s.q;
    arrived = s.at_centre;
    ++ticks;
  }
  EXPECT_TRUE(arrived) << "after " << ticks << " ticks at (" << q.x() << ", " << q.y() << ")";
  expect_near(q, 80.0, 75.0);
}

// Follower k at (0,0) moving (0.5, 0.5); neighbour j at (3,0) moving (1,-1);
// leader at (5,1) moving (2,0); r = 4, ε = 0.1, h = 0.5, c1 = 0.6, c2 = 0.4.
//   ‖q_j - q_k‖_σ = (√1.9 - 1)/0.1 = 3.78404875, φα = 1/3.78404875
//   n_kj = (3, 0)/√1.9 = (2.17642875, 0)
//   gradient = (2.17642875/3.78404875, 0) = (0.57515875, 0)
//   r_σ = (√2.6 - 1)/0.1 = 6.12451550, z = 3.78404875/6.12451550 = 0.61785275
//   a_kj = ½(1 + cos(π(0.61785275 - 0.5)/0.5)) = 0.86906881
//   consensus = a·((1,-1) - (0.5,0.5)) = (0.43453440, -1.30360321)
//   leader = -0.6·((0,0) - (5,1)) - 0.4·((0.5,0.5) - (2,0)) = (3, 0.6) + (0.6, -0.2) = (3.6, 0.4)
//   v = (4.60969315, -0.90360321), q' = q + v (Shao 2020 eq. (24))
const FollowerState kSelf{Vector2d{0.0, 0.0}, Vector2d{0.5, 0.5}};
const FollowerState kLeader{Vector2d{5.0, 1.0}, Vector2d{2.0, 0.0}};
const std::vector<FollowerState> kOneNeighbour{{Vector2d{3.0, 0.0}, Vector2d{1.0, -1.0}}};

TEST(ShaoNav, FollowerWithOneNeighbourAndLeaderMatchesHandWorkedEquationNineteen) {
  const ShaoNavParams p;
  const FollowerStep s = follower_step(kSelf, kOneNeighbour, kLeader, p);
  EXPECT_EQ(s.neighbour_count, 1);
  expect_near(s.gradient, 0.575158750036670557, 0.0);
  expect_near(s.consensus, 0.434534402972186902, -1.30360320891656071);
  expect_near(s.leader, 3.6, 0.4);
  expect_near(s.v, 4.60969315300885746, -0.903603208916560706);
  expect_near(s.q, 4.60969315300885746, -0.903603208916560706);
}

TEST(ShaoNav, FollowerInterpretationSwitchesChangeOnlyTheirOwnTerms) {
  // Literal Shao 2020 eq. (22): z = 3.78404875/4 = 0.94601219, a = ½(1 + cos(π·0.89202438)) = 0.02849199,
  // consensus = a·(0.5, -1.5), v = (0.57515875 + 0.01424599 + 3.6, -0.04273798 + 0.4).
  ShaoNavParams literal;
  literal.adjacency_scale = AdjacencyScale::LiteralRange;
  const FollowerStep l = follower_step(kSelf, kOneNeighbour, kLeader, literal);
  expect_near(l.v, 4.18940474495747304, 0.357262015237592538);

  // Gradient away from the neighbour (the sentence's reading of n_kj).
  ShaoNavParams away;
  away.neighbour_gradient = NeighbourGradient::AwayFromNeighbour;
  const FollowerStep a = follower_step(kSelf, kOneNeighbour, kLeader, away);
  expect_near(a.gradient, -0.575158750036670557, 0.0);
  expect_near(a.v, 3.45937565293551634, -0.903603208916560706);
}

TEST(ShaoNav, FollowerFarFromEveryoneFeelsOnlyTheLeaderTerms) {
  const ShaoNavParams p;
  // One neighbour exactly at r = 4 (N_k is strict) and one far away.
  const std::vector<FollowerState> far{{Vector2d{4.0, 0.0}, Vector2d{-3.0, 1.0}},
                                       {Vector2d{-20.0, 30.0}, Vector2d{1.0, 1.0}}};
  const FollowerStep s = follower_step(kSelf, far, kLeader, p);
  EXPECT_EQ(s.neighbour_count, 0);
  expect_near(s.gradient, 0.0, 0.0);
  expect_near(s.consensus, 0.0, 0.0);
  expect_near(s.v, 3.6, 0.4);  // -c1 (q_k - q_L) - c2 (v_k - v_L), as above
  expect_near(s.q, 3.6, 0.4);
}

TEST(ShaoNav, CoincidentOrCorruptNeighboursAddNoGradient) {
  const ShaoNavParams p;
  // Same position: no direction and φα(0) = ∞, so no gradient; a_kj = ρh(0) = 1 still aligns.
  const std::vector<FollowerState> others{{Vector2d{0.0, 0.0}, Vector2d{1.5, 0.5}},
                                          {Vector2d{std::nan(""), 0.0}, Vector2d{0.0, 0.0}}};
  const FollowerStep s = follower_step(kSelf, others, kLeader, p);
  EXPECT_EQ(s.neighbour_count, 1);
  expect_near(s.gradient, 0.0, 0.0);
  expect_near(s.consensus, 1.0, 0.0);
  expect_near(s.v, 4.6, 0.4);
}

TEST(ShaoNav, LoneFollowerSettlesAtLeaderVelocityTrailingByVelocityOverC1) {
  // Shao 2020 eq. (19) is the new velocity itself: with v_L constant the fixed point is
  // v_k = v_L and q_k - q_L = -v_L/c1 = (-10/3, 0); the error shrinks by
  // √0.4 per tick (eigenvalues ±0.632 of the linear map).
  const ShaoNavParams p;
  FollowerState leader{Vector2d{0.0, 0.0}, Vector2d{2.0, 0.0}};
  FollowerState self{Vector2d{-1.0, 6.0}, Vector2d{0.0, 0.0}};
  for (int t = 0; t < 100; ++t) {
    const FollowerStep s = follower_step(self, {}, leader, p);
    self = FollowerState{s.q, s.v};
    leader.q += leader.v;
  }
  expect_near(self.v, 2.0, 0.0);
  expect_near(self.q - leader.q, -10.0 / 3.0, 0.0);
}

}  // namespace
}  // namespace pheromesh::core
