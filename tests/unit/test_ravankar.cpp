// Ravankar 2016 uncertainty-aware deposition, checked against hand-worked numbers.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>

#include <Eigen/Core>
#include <Eigen/LU>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/ravankar/model.hpp"
#include "unit_support.hpp"

namespace pheromesh::core {
namespace {

using test::kPi;

Eigen::Matrix2d diag2(double a, double b) {
  Eigen::Matrix2d m = Eigen::Matrix2d::Zero();
  m(0, 0) = a;
  m(1, 1) = b;
  return m;
}

// R(45°) diag(4, 1) R(45°)ᵀ
Eigen::Matrix2d rotated_4_1() {
  Eigen::Matrix2d m;
  m << 2.5, 1.5, 1.5, 2.5;
  return m;
}

double amount_at(const RavankarDeposit& d, Cell c) {
  EXPECT_TRUE(d.rect.contains(c));
  return d.amounts[static_cast<std::size_t>(c.y - d.rect.y0) * static_cast<std::size_t>(d.rect.w) +
                   static_cast<std::size_t>(c.x - d.rect.x0)];
}

double sum_of(const RavankarDeposit& d) {
  double s = 0.0;
  for (double a : d.amounts) {
    s += a;
  }
  return s;
}

// --- motion model and covariance growth ----------------------------------------

TEST(RavankarMotion, EqualWheelsDriveStraight) {
  const Eigen::Vector3d p = ravankar_motion({1.0, 2.0, kPi / 2.0}, 0.5, 0.5, 0.23);
  EXPECT_NEAR(p.x(), 1.0, 1e-12);
  EXPECT_NEAR(p.y(), 2.5, 1e-12);
  EXPECT_NEAR(p.z(), kPi / 2.0, 1e-12);
}

TEST(RavankarMotion, QuarterArcEndsOnTheTurningCircle) {
  // W = 0.5, inner wheel radius R = 1: l = π/2·1, r = π/2·1.5 -> β = π/2, centre
  // radius R + W/2 = 1.25 about C = (0, 1.25): ends at (1.25, 1.25) heading +y.
  const Eigen::Vector3d p = ravankar_motion({0.0, 0.0, 0.0}, kPi / 2.0, 0.75 * kPi, 0.5);
  EXPECT_NEAR(p.x(), 1.25, 1e-12);
  EXPECT_NEAR(p.y(), 1.25, 1e-12);
  EXPECT_NEAR(p.z(), kPi / 2.0, 1e-12);
}

TEST(RavankarMotion, StraightMetreGivesHandWorkedCovariance) {
  // k = 0.01, W = 0.5, l = r = 1 from Σ = 0: V = [[½, ½], [-1, 1], [-2, 2]],
  // M = diag(0.01, 0.01) -> Σxx = 0.005, Σyy = 0.02, Σyθ = 0.04, Σθθ = 0.08.
  const RavankarMotionParams p{0.5, 0.01};
  RavankarBelief b = ravankar_predict(RavankarBelief{}, 1.0, 1.0, p);
  EXPECT_NEAR(b.mean.x(), 1.0, 1e-12);
  EXPECT_NEAR(b.covariance(0, 0), 0.005, 1e-12);
  EXPECT_NEAR(b.covariance(1, 1), 0.02, 1e-12);
  EXPECT_NEAR(b.covariance(1, 2), 0.04, 1e-12);
  EXPECT_NEAR(b.covariance(2, 2), 0.08, 1e-12);
  EXPECT_NEAR(b.covariance(0, 1), 0.0, 1e-12);
  // A second metre: the heading error swings y, Σyy = 0.02 + 2·0.04 + 0.08 + 0.02 = 0.2.
  b = ravankar_predict(b, 1.0, 1.0, p);
  EXPECT_NEAR(b.covariance(0, 0), 0.01, 1e-12);
  EXPECT_NEAR(b.covariance(1, 1), 0.2, 1e-12);
}

TEST(RavankarMotion, UncertaintyGrowsWithoutFixesAndAFixShrinksIt) {
  const RavankarMotionParams p;
  RavankarBelief b;
  double last_det = 0.0;
  for (int i = 0; i < 50; ++i) {
    const bool turn = i % 10 == 9;
    b = ravankar_predict(b, turn ? 0.1 : 0.3, 0.3, p);
    const double det = ravankar_position_covariance(b.covariance).determinant();
    EXPECT_GE(det, last_det);
    last_det = det;
  }
  EXPECT_GT(last_det, 0.0);
  const RavankarBelief fixed = ravankar_correct(b, b.mean.head<2>(), diag2(0.01, 0.01));
  EXPECT_LT(ravankar_position_covariance(fixed.covariance).determinant(), last_det);
}

TEST(RavankarMotion, PositionFixIsTheKalmanUpdate) {
  RavankarBelief b;
  b.covariance = Eigen::Vector3d(1.0, 1.0, 0.5).asDiagonal();
  const RavankarBelief out = ravankar_correct(b, {2.0, 0.0}, diag2(1.0, 1.0));
  EXPECT_NEAR(out.mean.x(), 1.0, 1e-12);
  EXPECT_NEAR(out.mean.y(), 0.0, 1e-12);
  EXPECT_NEAR(out.covariance(0, 0), 0.5, 1e-12);
  EXPECT_NEAR(out.covariance(1, 1), 0.5, 1e-12);
  EXPECT_NEAR(out.covariance(2, 2), 0.5, 1e-12);
}

// --- deposit amount --------------------------------------------------------------

TEST(RavankarDeposit, AmountIsTauOverTheEigenvalueProduct) {
  Eigen::Matrix2d s;
  s << 0.5, 0.1, 0.1, 0.2;  // λ = (0.7 ± √0.13)/2 = 0.530278, 0.169722; product 0.09
  const RavankarEllipse e = ravankar_error_ellipse(s);
  EXPECT_NEAR(e.lambda1, 0.5302775637731995, 1e-12);
  EXPECT_NEAR(e.lambda2, 0.1697224362268005, 1e-12);
  EXPECT_NEAR(ravankar_deposit_amount(s, RavankarDepositParams{}), 0.2 / 0.09, 1e-12);
}

TEST(RavankarDeposit, AmountIsCappedAtHundred) {
  EXPECT_DOUBLE_EQ(ravankar_deposit_amount(diag2(0.01, 0.01), RavankarDepositParams{}), 100.0);  // 0.2/1e-4 = 2000
  EXPECT_DOUBLE_EQ(ravankar_deposit_amount(Eigen::Matrix2d::Zero(), RavankarDepositParams{}), 100.0);
  EXPECT_NEAR(ravankar_deposit_amount(diag2(0.045, 0.045), RavankarDepositParams{}), 98.76543209876543, 1e-9);
}

TEST(RavankarDeposit, EllipseAngleFollowsTheMajorAxis) {
  const RavankarEllipse e = ravankar_error_ellipse(rotated_4_1());
  EXPECT_NEAR(e.lambda1, 4.0, 1e-12);
  EXPECT_NEAR(e.lambda2, 1.0, 1e-12);
  EXPECT_NEAR(e.angle_rad, kPi / 4.0, 1e-12);
}

// --- spread, Ravankar 2016 eq. (14) ---------------------------------------------------------------

TEST(RavankarSpread, PeakModeMatchesEquationFourteenAtCellCentres) {
  // Σ = diag(4, 1): γ = 0.2/4 = 0.05, a = (4, 1) as printed, z_rng = 4 m, 1 m cells.
  const Rect rect{5, 5, 11, 11};
  const RavankarDeposit d = ravankar_spread({10.7, 10.2}, diag2(4.0, 1.0), rect, RavankarDepositParams{});
  EXPECT_EQ(d.centre, (Cell{10, 10}));
  EXPECT_NEAR(d.gamma, 0.05, 1e-12);
  EXPECT_NEAR(amount_at(d, {10, 10}), 0.05, 1e-12);
  EXPECT_NEAR(amount_at(d, {11, 10}), 0.04697065314067379, 1e-12);   // γ e^(-1/16)
  EXPECT_NEAR(amount_at(d, {10, 11}), 0.018393972058572117, 1e-12);  // γ e^(-1)
  EXPECT_NEAR(amount_at(d, {14, 10}), 0.018393972058572117, 1e-12);  // 4 m: at the range, γ e^(-16/16)
  EXPECT_NEAR(amount_at(d, {6, 10}), 0.018393972058572117, 1e-12);
  EXPECT_EQ(amount_at(d, {15, 10}), 0.0);  // 5 m > z_rng
  EXPECT_EQ(amount_at(d, {13, 13}), 0.0);  // 4.24 m > z_rng
  EXPECT_EQ(amount_at(d, {5, 5}), 0.0);
}

TEST(RavankarSpread, RotatedEllipseSpreadsAlongItsMajorAxis) {
  const RavankarDeposit d = ravankar_spread({10.5, 10.5}, rotated_4_1(), {5, 5, 11, 11}, RavankarDepositParams{});
  EXPECT_NEAR(d.gamma, 0.05, 1e-12);
  EXPECT_NEAR(amount_at(d, {11, 11}), 0.044124845129229776, 1e-12);          // u = √2 along v1: γ e^(-2/16)
  EXPECT_NEAR(amount_at(d, {9, 11}), 0.05 * std::exp(-2.0), 1e-12);         // v = √2 along v2: γ e^(-2)
}

TEST(RavankarSpread, StdDevAxesUseTheSquareRootOfTheEigenvalues) {
  RavankarDepositParams p;
  p.axes = RavankarAxes::StdDev;
  const RavankarDeposit d = ravankar_spread({10.5, 10.5}, diag2(4.0, 1.0), {5, 5, 11, 11}, p);
  EXPECT_NEAR(amount_at(d, {11, 10}), 0.05 * std::exp(-0.25), 1e-12);  // a1 = 2
  EXPECT_NEAR(amount_at(d, {10, 11}), 0.05 * std::exp(-1.0), 1e-12);   // a2 = 1
}

TEST(RavankarSpread, CertainPoseDepositsTheCapInOneCell) {
  const RavankarDeposit d = ravankar_spread({3.2, 4.9}, Eigen::Matrix2d::Zero(), {0, 0, 8, 8}, RavankarDepositParams{});
  EXPECT_DOUBLE_EQ(amount_at(d, {3, 4}), 100.0);
  EXPECT_DOUBLE_EQ(sum_of(d), 100.0);
}

TEST(RavankarSpread, TotalModeSumsToGammaOverTheFootprint) {
  RavankarDepositParams p;
  p.spread = RavankarSpread::Total;
  p.axes = RavankarAxes::StdDev;
  const Eigen::Matrix2d s = rotated_4_1();
  const RavankarDeposit whole = ravankar_spread({20.3, 20.6}, s, {10, 10, 21, 21}, p);
  EXPECT_NEAR(sum_of(whole), whole.gamma, 1e-12);
  // Split across two place agents' rects, the halves still sum to γ.
  const RavankarDeposit left = ravankar_spread({20.3, 20.6}, s, {10, 10, 11, 21}, p);
  const RavankarDeposit right = ravankar_spread({20.3, 20.6}, s, {21, 10, 10, 21}, p);
  EXPECT_NEAR(sum_of(left) + sum_of(right), whole.gamma, 1e-12);
  // Nothing beyond z_rng (4 cells): the border of a 12 x 12 ring around it is 0.
  const RavankarDeposit far = ravankar_spread({20.3, 20.6}, s, {14, 14, 13, 13}, p);
  for (int32_t y = 14; y < 27; ++y) {
    for (int32_t x = 14; x < 27; ++x) {
      const double dx = x - 20;
      const double dy = y - 20;
      if (dx * dx + dy * dy > 16.0) {
        EXPECT_EQ(amount_at(far, {x, y}), 0.0) << x << "," << y;
      } else {
        EXPECT_GT(amount_at(far, {x, y}), 0.0) << x << "," << y;
      }
    }
  }
}

TEST(RavankarSpread, GradientMatchesEquationSixteenAndFiniteDifferences) {
  const RavankarDepositParams p;
  const RavankarEllipse axis = ravankar_error_ellipse(diag2(4.0, 1.0));
  const Eigen::Vector2d g = ravankar_gradient({1.0, 0.0}, 0.05, axis, p);
  EXPECT_NEAR(g.x(), -0.005871331642584224, 1e-12);  // -2γ e^(-1/16) / 16
  EXPECT_NEAR(g.y(), 0.0, 1e-15);
  EXPECT_EQ(ravankar_gradient({4.5, 0.0}, 0.05, axis, p), Eigen::Vector2d::Zero());

  const RavankarEllipse e = ravankar_error_ellipse(rotated_4_1());
  auto value = [&](const Eigen::Vector2d& o) {  // Ravankar 2016 eq. (14) in the ellipse axes
    const double u = (o.x() + o.y()) / std::sqrt(2.0);
    const double v = (-o.x() + o.y()) / std::sqrt(2.0);
    return 0.05 * std::exp(-(u * u / 16.0 + v * v / 1.0));
  };
  const Eigen::Vector2d o(0.7, -0.3);
  const double h = 1e-6;
  const Eigen::Vector2d num((value(o + Eigen::Vector2d(h, 0)) - value(o - Eigen::Vector2d(h, 0))) / (2 * h),
                            (value(o + Eigen::Vector2d(0, h)) - value(o - Eigen::Vector2d(0, h))) / (2 * h));
  EXPECT_LT((ravankar_gradient(o, 0.05, e, p) - num).norm(), 1e-8);
}

// --- evaporation ----------------------------------------------------------------------

TEST(RavankarEvaporation, FigureSevenCurveWithoutAmbient) {
  // P0 = 35, K = 0.0057, P_a = 0: 35 e^(-0.0057 t)
  EXPECT_NEAR(ravankar_evaporate(35.0, 0.0, 0.0057, 25.0), 30.351564400228924, 1e-9);
  EXPECT_NEAR(ravankar_evaporate(35.0, 0.0, 0.0057, 50.0), 26.320498901178393, 1e-9);
  EXPECT_NEAR(ravankar_evaporate(35.0, 0.0, 0.0057, 100.0), 19.793390354483797, 1e-9);
}

TEST(RavankarEvaporation, FigureEightAmbientSlowsTheDecay) {
  // P0 = 35, K = 0.0057, P_a = 10: 10 + 25 e^(-0.0057 t)
  EXPECT_NEAR(ravankar_evaporate(35.0, 10.0, 0.0057, 25.0), 31.679688857306374, 1e-9);
  EXPECT_NEAR(ravankar_evaporate(35.0, 10.0, 0.0057, 100.0), 24.138135967488427, 1e-9);
  EXPECT_GT(ravankar_evaporate(35.0, 10.0, 0.0057, 100.0), ravankar_evaporate(35.0, 0.0, 0.0057, 100.0));
  EXPECT_NEAR(ravankar_evaporate(35.0, 10.0, 0.0057, 1e6), 10.0, 1e-9);
}

TEST(RavankarEvaporation, FigureSixCurveAndStepsCompose) {
  EXPECT_NEAR(ravankar_evaporate(50.0, 0.0, 0.0057, 200.0), 15.990951090815193, 1e-9);
  double p = 50.0;
  for (int i = 0; i < 20; ++i) {
    p = ravankar_evaporate(p, 0.0, 0.0057, 10.0);
  }
  EXPECT_NEAR(p, 15.990951090815193, 1e-9);
}

TEST(RavankarEvaporation, ThresholdTimesFromEquationsTwentyThreeToTwentySix) {
  // Ravankar 2016 Fig. 7: 35 -> 18 at K = 0.0057 takes ln(35/18)/K = 116.66 s ("about 116 s").
  const auto t = ravankar_time_to_level(35.0, 0.0, 0.0057, 18.0);
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, 116.66250940232437, 1e-9);
  // Ravankar 2016 eq. (23): K from one observation; Ravankar 2016 eq. (26): same time from (t_m, P_tm).
  const auto k = ravankar_rate_constant(35.0, 0.0, 100.0, 19.793390354483797);
  ASSERT_TRUE(k.has_value());
  EXPECT_NEAR(*k, 0.0057, 1e-12);
  const auto t26 = ravankar_time_to_threshold(35.0, 0.0, 18.0 / 35.0, 100.0, 19.793390354483797);
  ASSERT_TRUE(t26.has_value());
  EXPECT_NEAR(*t26, 116.66250940232437, 1e-9);
  // Ravankar 2016 Fig. 6 text "50 -> 18 in about 300 s" needs K = ln(50/18)/300 = 0.0034055.
  EXPECT_NEAR(*ravankar_rate_constant(50.0, 0.0, 300.0, 18.0), 0.003405504158439938, 1e-12);
  // Never reaches a level at or below the ambient one.
  EXPECT_FALSE(ravankar_time_to_level(35.0, 10.0, 0.0057, 10.0).has_value());
  EXPECT_FALSE(ravankar_rate_constant(35.0, 0.0, 0.0, 20.0).has_value());
}

TEST(RavankarField, DepositsAddUpToTheCapAndEvaporateTowardAmbient) {
  RavankarField field({0, 0, 4, 4});
  const RavankarDeposit d = ravankar_spread({1.5, 1.5}, Eigen::Matrix2d::Zero(), {0, 0, 4, 4}, RavankarDepositParams{});
  field.add(d);
  field.add(d);
  EXPECT_DOUBLE_EQ(*field.value({1, 1}), 100.0);
  EXPECT_DOUBLE_EQ(*field.value({2, 1}), 0.0);
  EXPECT_FALSE(field.value({4, 0}).has_value());

  RavankarDeposit d35 = d;
  d35.amounts.assign(d35.amounts.size(), 0.0);
  d35.amounts[0] = 35.0;  // cell (0, 0)
  d35.amounts[3] = 5.0;   // cell (3, 0)
  field.add(d35);
  field.evaporate(100.0, RavankarEvaporationParams{0.0057, 10.0});
  EXPECT_NEAR(*field.value({0, 0}), 24.138135967488427, 1e-4);
  EXPECT_NEAR(*field.value({1, 1}), 10.0 + 90.0 * std::exp(-0.57), 1e-4);
  EXPECT_DOUBLE_EQ(*field.value({3, 0}), 5.0);  // below P_a: left alone
}

// --- followers -------------------------------------------------------------------------

TEST(RavankarFollower, RejectsTrailsBelowTenPercentOfTheMaximum) {
  const RavankarFollowerParams p;  // δ·P0 = 0.1 · 100 = 10
  EXPECT_TRUE(ravankar_follows(10.0, p));
  EXPECT_FALSE(ravankar_follows(9.999, p));
  EXPECT_TRUE(ravankar_follows(11.35, p));  // location L11
  EXPECT_FALSE(ravankar_follows(8.15, p));  // location L12: leader lost
}

TEST(RavankarFollower, SpeedFollowsTableTwo) {
  const RavankarFollowerParams p;
  EXPECT_DOUBLE_EQ(ravankar_speed(100.0, p), 1.0);
  EXPECT_DOUBLE_EQ(ravankar_speed(60.0, p), 1.0);
  EXPECT_DOUBLE_EQ(ravankar_speed(59.9, p), 0.65);
  EXPECT_DOUBLE_EQ(ravankar_speed(30.0, p), 0.65);
  EXPECT_DOUBLE_EQ(ravankar_speed(29.9, p), 0.45);
  EXPECT_DOUBLE_EQ(ravankar_speed(15.0, p), 0.45);
  EXPECT_DOUBLE_EQ(ravankar_speed(14.9, p), 0.15);
  EXPECT_DOUBLE_EQ(ravankar_speed(0.0, p), 0.15);
  EXPECT_DOUBLE_EQ(ravankar_speed(-1.0, p), 0.15);
}

}  // namespace
}  // namespace pheromesh::core
