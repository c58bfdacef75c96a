// Ravankar, Ravankar, Kobayashi & Emaru 2016, "Avoiding blind leading the
// blind: Uncertainty integration in virtual pheromone deposition by robots",
// IJARS 13(6) ("Ravankar 2016"): a robot deposits less pheromone, spread over
// its position-error ellipse, the less sure it is of where it is (Ravankar 2016 eq. (9), Ravankar 2016 eq. (10), Ravankar 2016 eq. (11), Ravankar 2016 eq. (12), Ravankar 2016 eq. (13), Ravankar 2016 eq. (14), Ravankar 2016 eq. (15), Ravankar 2016 eq. (16));
// pheromone evaporates toward an ambient level (Ravankar 2016 eq. (17), Ravankar 2016 eq. (18), Ravankar 2016 eq. (19), Ravankar 2016 eq. (20), Ravankar 2016 eq. (21), Ravankar 2016 eq. (22), Ravankar 2016 eq. (23), Ravankar 2016 eq. (24), Ravankar 2016 eq. (25), Ravankar 2016 eq. (26)); followers reject
// weak trails and adapt their speed to what they sense (Ravankar 2016 Table 2).
//
// Conventions: positions [m], covariances [m²] (θ entries [rad], [m·rad]),
// time [s]. A map cell c covers [c.x·s, (c.x+1)·s) x [c.y·s, (c.y+1)·s), s =
// cell size; the paper rounds a pose to the nearest integer cell, which is the
// same thing when its integer coordinates are read as cell centres.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "pheromesh/core/grid.hpp"

namespace pheromesh::core {

// ---------------------------------------------------------------------------
// Pose belief and its growth without fixes (Ravankar 2016 eq. (3), Ravankar 2016 eq. (4), Ravankar 2016 eq. (27), Ravankar 2016 eq. (28), Ravankar 2016 eq. (29), Ravankar 2016 eq. (30), Ravankar 2016 eq. (31), Ravankar 2016 eq. (32), Ravankar 2016 eq. (33))

// Mean [x, y, θ] ([m], [m], [rad]) and covariance Σ_t, Ravankar 2016 eq. (9).
struct RavankarBelief {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

struct RavankarMotionParams {
  // W_r, distance between the wheels, Ravankar 2016 eq. (27) [m]. Not given in the paper;
  // 0.23 m is the Kobuki (Turtlebot 2) wheel separation.
  double wheel_separation_m = 0.23;
  // Variance of each wheel's travel per metre that wheel travels [m²/m]
  // (ours; the paper takes Σ from its EKF/PF and gives no noise values).
  // 0.0025 m²/m = 5 cm standard deviation after 1 m.
  double wheel_noise_m2_per_m = 0.0025;
};

// Differential-drive motion, Ravankar 2016 eq. (27), Ravankar 2016 eq. (28), Ravankar 2016 eq. (29), Ravankar 2016 eq. (30), Ravankar 2016 eq. (31), Ravankar 2016 eq. (32), Ravankar 2016 eq. (33): left / right wheel travel l, r [m].
// β = (r - l)/W_r; for r != l the robot moves on an arc about the centre C of
// Ravankar 2016 eq. (29). Ravankar 2016 eq. (31) as printed has a sign slip (it would put P' on the far
// side of C); we use P' = C + (R + W_r/2)·[sin θ', -cos θ'], which tends to
// Ravankar 2016 eq. (33) as β -> 0. θ' is wrapped to [0, 2π) as in Ravankar 2016 eq. (30).
Eigen::Vector3d ravankar_motion(const Eigen::Vector3d& pose, double left_m, double right_m, double wheel_separation_m);

// EKF prediction (Ravankar 2016 eq. (3), Ravankar 2016 eq. (4)) with the motion above: Σ <- G Σ Gᵀ + V M Vᵀ,
// G = ∂g/∂x, V = ∂g/∂(l, r), M = diag(k|l|, k|r|). Without fixes Σ only grows.
RavankarBelief ravankar_predict(const RavankarBelief& b, double left_m, double right_m, const RavankarMotionParams& p);

// A position fix z = [x, y] [m] with covariance R [m²] (a SLAM / landmark
// match): the EKF correction with H = [I₂ 0] (Ravankar 2016 eq. (2) in Kalman form).
RavankarBelief ravankar_correct(const RavankarBelief& b, const Eigen::Vector2d& z, const Eigen::Matrix2d& r);

// Σ_xy, the position block of Σ_t (Ravankar 2016 eq. (11)); orientation is left out because
// a pheromone amount has no direction.
Eigen::Matrix2d ravankar_position_covariance(const Eigen::Matrix3d& sigma);

// Eigen decomposition of Σ_xy: λ1 >= λ2 >= 0 [m²] and the direction of v1
// [rad, counter-clockwise from +x]; v2 is v1 turned by +90°. Negative
// eigenvalues (rounding of a near-singular Σ) are clamped to 0.
struct RavankarEllipse {
  double lambda1 = 0.0;
  double lambda2 = 0.0;
  double angle_rad = 0.0;
};
RavankarEllipse ravankar_error_ellipse(const Eigen::Matrix2d& sigma_xy);

// ---------------------------------------------------------------------------
// Deposit (Ravankar 2016 eq. (12), Ravankar 2016 eq. (13), Ravankar 2016 eq. (14), Ravankar 2016 eq. (15), Ravankar 2016 eq. (16))

// How the a_i in Ravankar 2016 eq. (14), exp(-(u²/a1² + v²/a2²)), are taken from the eigenvalues.
enum class RavankarAxes : uint8_t {
  Eigenvalue = 0,  // a_i = λ_i, as printed (λ is a variance [m²], used as a length [m])
  StdDev = 1,      // a_i = √λ_i, dimensionally consistent alternative
};
// What γ means for the spread of Ravankar 2016 eq. (14).
enum class RavankarSpread : uint8_t {
  Peak = 0,   // as printed: the cell under the robot gets γ, others γ·e^(-q)
  Total = 1,  // normalised so the whole footprint (all cells in range) sums to γ
};

struct RavankarDepositParams {
  double tau = 0.2;              // τ, Ravankar 2016 eq. (12) (the paper's "γ was set to 0.2", simulation) [pheromone·m⁴]
  double max_deposit = 100.0;    // upper limit of γ ("an upper limit of 100 was set") [pheromone]
  double sensor_range_m = 4.0;   // z_rng, Ravankar 2016 eq. (14): URG-04LX 4000 mm, Ravankar 2016 Table 1 [m]
  double cell_size_m = 1.0;      // "cells of unit area" [m]
  RavankarAxes axes = RavankarAxes::Eigenvalue;
  RavankarSpread spread = RavankarSpread::Peak;
};

// γ = τ / (λ1·λ2) = τ / det Σ_xy, Ravankar 2016 eq. (12), capped at max_deposit (a zero
// uncertainty would give an infinite deposit).
double ravankar_deposit_amount(const Eigen::Matrix2d& sigma_xy, const RavankarDepositParams& p);

// Cell under a position (floor of x/s, y/s).
Cell ravankar_cell_of(const Eigen::Vector2d& position_m, double cell_size_m);

// One deposit of Ravankar 2016 eq. (14) evaluated at cell centres, for the cells of `rect`.
// The footprint is centred on the centre of the cell under the estimated
// position (the paper rounds the pose to a cell); (u, v) are a cell centre's
// offset along v1, v2; cells farther than z_rng from the footprint centre get
// 0. A zero axis puts everything on that axis through the centre (the limit).
struct RavankarDeposit {
  Rect rect;                    // the cells asked for
  std::vector<double> amounts;  // row-major over rect [pheromone]
  double gamma = 0.0;           // γ of Ravankar 2016 eq. (12), capped
  Cell centre{};                // cell under the estimated position
};
RavankarDeposit ravankar_spread(const Eigen::Vector2d& position_m, const Eigen::Matrix2d& sigma_xy, const Rect& rect,
                                const RavankarDepositParams& p);

// Ravankar 2016 eq. (16): ∇P_loc at an offset [m] (world axes) from the deposit centre,
// for one deposit of peak γ; 0 beyond z_rng. Returned in world axes [pheromone/m].
Eigen::Vector2d ravankar_gradient(const Eigen::Vector2d& offset_m, double gamma, const RavankarEllipse& e,
                                  const RavankarDepositParams& p);

// ---------------------------------------------------------------------------
// Evaporation toward the ambient level (Ravankar 2016 eq. (17), Ravankar 2016 eq. (18), Ravankar 2016 eq. (19), Ravankar 2016 eq. (20), Ravankar 2016 eq. (21), Ravankar 2016 eq. (22), Ravankar 2016 eq. (23), Ravankar 2016 eq. (24), Ravankar 2016 eq. (25), Ravankar 2016 eq. (26))

struct RavankarEvaporationParams {
  double k_per_s = 0.0057;  // K, Ravankar 2016 eq. (17), Ravankar 2016 Fig. 6, Ravankar 2016 Fig. 7, Ravankar 2016 Fig. 8 [1/s]
  double ambient = 0.0;     // P_a, Ravankar 2016 eq. (17): 0 in Ravankar 2016 Fig. 6, Ravankar 2016 Fig. 7, Ravankar 2016 Fig. 10 in Ravankar 2016 Fig. 8 [pheromone]
};

// Exact solution of dP/dt = -K(P - P_a) over dt (Ravankar 2016 eq. (22) from P0 = p):
// P_a + (p - P_a)·e^(-K·dt). Steps compose exactly.
double ravankar_evaporate(double p, double ambient, double k_per_s, double dt_s);
// K from one observed level, Ravankar 2016 eq. (23): -ln((P_tm - P_a)/(P0 - P_a)) / t_m.
// nullopt unless t_m > 0 and 0 < (P_tm - P_a)/(P0 - P_a) <= 1.
std::optional<double> ravankar_rate_constant(double p0, double ambient, double t_m_s, double p_tm);
// Time for P0 to fall to `level` (δ·P0 in Ravankar 2016 eq. (24)): -ln((level - P_a)/(P0 - P_a)) / K.
// nullopt if it never gets there (level <= P_a, level > P0, K <= 0).
std::optional<double> ravankar_time_to_level(double p0, double ambient, double k_per_s, double level);
// Ravankar 2016 eq. (26): the same time from (t_m, P_tm) instead of K, for threshold δ·P0.
std::optional<double> ravankar_time_to_threshold(double p0, double ambient, double delta, double t_m_s, double p_tm);

// Pheromone over one rectangle of cells: deposits add up to a cap (Ravankar 2016 Fig. 26(b)),
// evaporation follows Ravankar 2016 eq. (22) toward P_a. Cells at or below P_a are left
// alone (Ravankar 2016 eq. (17) would raise them to P_a; the paper only describes decay).
class RavankarField {
 public:
  explicit RavankarField(const Rect& rect, double cap = 100.0);

  [[nodiscard]] const Rect& rect() const { return rect_; }
  [[nodiscard]] std::span<const float> values() const { return v_; }
  [[nodiscard]] std::optional<double> value(Cell c) const;  // nullopt outside rect()

  // Adds the part of `d` that falls in rect(), each cell capped.
  void add(const RavankarDeposit& d);
  void evaporate(double dt_s, const RavankarEvaporationParams& p);

 private:
  Rect rect_;
  double cap_;
  std::vector<float> v_;
};

// ---------------------------------------------------------------------------
// Followers (Ravankar 2016 eq. (24) threshold, Ravankar 2016 Table 2)

struct RavankarSpeedBand {
  double min_pheromone = 0.0;  // band applies from here up to the next band's minimum
  double speed_mps = 0.0;      // [m/s]
};

struct RavankarFollowerParams {
  double reference_deposit = 100.0;  // P0, the largest deposit (the cap) [pheromone]
  double delta = 0.1;                // δ: δ·P0 = 10, the corridor threshold of the real experiment
  // Ravankar 2016 Table 2, highest band first; a band's lower bound is inclusive.
  std::array<RavankarSpeedBand, 4> speed_bands{{{60.0, 1.0}, {30.0, 0.65}, {15.0, 0.45}, {0.0, 0.15}}};
};

// A follower keeps to a trail whose sensed pheromone is at least δ·P0;
// below it, the trail is rejected and the follower explores on its own.
bool ravankar_follows(double sensed, const RavankarFollowerParams& p);
// Speed for a sensed amount, Ravankar 2016 Table 2 [m/s]; below every band the lowest band's speed.
double ravankar_speed(double sensed, const RavankarFollowerParams& p);

}  // namespace pheromesh::core
