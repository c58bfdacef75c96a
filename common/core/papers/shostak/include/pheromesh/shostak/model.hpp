// Shostak & Petrenko (KPI), "Decentralised coordination of a drone swarm
// through stigmergy and swarm intelligence without GPS" (Ukrainian; here
// "Shostak"): three capped pheromone layers with per-second multiplicative
// evaporation (Shostak 2024 eq. (1), Shostak 2024 eq. (2)), attractiveness φ = b_e·b_h + b_t (Shostak 2024 eq. (3)),
// 20 random 3-D candidates at 15 m (Shostak 2024 eq. (4)) chosen by roulette on
// φ^α·η^β (Shostak 2024 eq. (5), Shostak 2024 eq. (6)), 0°/120°/240° dispersal (Shostak 2024 Sec. 5), and the GPS-denied
// local frame of Shostak 2024 Sec. 4.1 plus a dead-reckoning drift model (ours).
//
// Conventions: positions in metres [m], angles in radians [rad], azimuth
// counter-clockwise from +x, pitch positive up (+z). A map cell c covers
// [c.x·s, (c.x+1)·s) x [c.y·s, (c.y+1)·s) of the world plane, s = cell size.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <numbers>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/rng.hpp"

namespace pheromesh::core {

// ---------------------------------------------------------------------------
// Layers, deposit, evaporation (Shostak 2024 Sec. 2, Shostak 2024 Sec. 3.1, Shostak 2024 Sec. 3.2, Shostak 2024 Sec. 4.2, Shostak 2024 Sec. 5)

enum class ShostakLayer : uint8_t { Explored = 0, Hazard = 1, Target = 2 };
inline constexpr int kShostakLayerCount = 3;
const char* shostak_layer_name(ShostakLayer l);

struct ShostakLayerParams {
  double explored_max = 10.0;        // τmax of explored, Shostak 2024 Sec. 2 / Shostak 2024 eq. (1): range [0, 10]
  double hazard_max = 10.0;          // τmax of hazard, Shostak 2024 Sec. 2: [0, 10]
  double target_max = 100.0;         // τmax of target, Shostak 2024 Sec. 2: [0, 100]
  double explored_increment = 1.0;   // Δτ, Shostak 2024 eq. (1), per deposit
  double hazard_increment = 5.0;     // +5.0 per obstacle detection, Shostak 2024 Sec. 4.2
  double target_increment = 100.0;   // +100.0 per target detection, Shostak 2024 Sec. 5
  double deposit_period_s = 0.2;     // one explored deposit every 0.2 s, Shostak 2024 Sec. 3.1 [s]
  double evaporation_rate = 0.05;    // ρ, Shostak 2024 eq. (2): 5 % per second, multiplicative [1/s]
  double cell_size_m = 5.0;          // 40 x 40 cells of 5 m, Shostak 2024 Sec. 2 [m/cell]
};

// Per-step evaporation factor for a step of dt_s seconds. Shostak 2024 eq. (2) is
// multiplicative per whole second, τ(t+1) = τ(t)·(1-ρ), so a step of dt
// multiplies by (1-ρ)^dt (exactly Shostak 2024 eq. (2) when dt is 1 s, and steps compose:
// five 0.2 s steps equal one 1 s step). Not e^(-ρ·dt).
double shostak_evaporation_factor(double rho, double dt_s);
// Time [s] for a level to halve under Shostak 2024 eq. (2): ln 0.5 / ln(1-ρ); 13.51 s for
// ρ = 0.05. Shostak 2024 Sec. 5 reports "10.0 -> 5.0 in about 14 s" (whole-second
// steps: 10·0.95^13 = 5.13, 10·0.95^14 = 4.88).
double shostak_half_life_s(double rho);
// Number of deposit instants k·period (k integer) in (t0_s, t1_s]; 0 if t1 <= t0.
uint32_t shostak_deposits_due(double t0_s, double t1_s, double period_s);

struct ShostakCellValues {
  double explored = 0.0;  // τ_e
  double hazard = 0.0;    // τ_h
  double target = 0.0;    // τ_t
};

// The three layers over one rectangle of cells (a tile or region), row-major.
class ShostakLayers {
 public:
  ShostakLayers(const Rect& rect, const ShostakLayerParams& params);

  [[nodiscard]] const Rect& rect() const { return rect_; }
  [[nodiscard]] const ShostakLayerParams& params() const { return p_; }
  [[nodiscard]] std::span<const float> layer(ShostakLayer l) const;
  [[nodiscard]] std::span<float> mutable_layer(ShostakLayer l);
  [[nodiscard]] double max_of(ShostakLayer l) const;  // τmax of the layer
  // Layer values at c; nullopt if c is outside rect().
  [[nodiscard]] std::optional<ShostakCellValues> values(Cell c) const;
  [[nodiscard]] float value(ShostakLayer l, Cell c) const;  // c must be in rect()

  // Shostak 2024 eq. (1) for any layer: τ <- min(τ + amount, τmax). Returns false and
  // changes nothing if c is outside rect() or amount is negative or not finite.
  bool deposit(ShostakLayer l, Cell c, double amount);
  bool deposit_explored(Cell c) { return deposit(ShostakLayer::Explored, c, p_.explored_increment); }  // one 0.2 s deposit
  bool mark_hazard(Cell c) { return deposit(ShostakLayer::Hazard, c, p_.hazard_increment); }           // Shostak 2024 Sec. 4.2
  bool mark_target(Cell c) { return deposit(ShostakLayer::Target, c, p_.target_increment); }           // Shostak 2024 Sec. 5

  // Shostak 2024 eq. (2) over dt_s seconds on every layer: τ <- τ·(1-ρ)^dt. dt_s <= 0 does nothing.
  void evaporate(double dt_s);

 private:
  Rect rect_;
  ShostakLayerParams p_;
  std::vector<float> layers_[kShostakLayerCount];
  [[nodiscard]] std::optional<std::size_t> index_of(Cell c) const;
};

// ---------------------------------------------------------------------------
// Attractiveness, candidates, roulette (Shostak 2024 Sec. 3.3, Shostak 2024 Sec. 3.4, Shostak 2024 Sec. 3.5)

struct ShostakAttractivenessParams {
  double explored_scale = 10.0;       // b_e = 1 - min(τ_e / 10, 0.9), Shostak 2024 eq. (3)
  double explored_max_penalty = 0.9;  // so b_e in [0.1, 1]
  double hazard_scale = 10.0;         // b_h = 1 - min(τ_h / 10, 0.95), Shostak 2024 eq. (3)
  double hazard_max_penalty = 0.95;   // so b_h in [0.05, 1]
  double target_gain = 10.0;          // b_t = τ_t · 10, Shostak 2024 eq. (3)
};

struct ShostakAttractiveness {
  double b_e = 0.0;  // exploration bonus
  double b_h = 0.0;  // hazard penalty (a factor)
  double b_t = 0.0;  // target bonus
  double phi = 0.0;  // φ = b_e·b_h + b_t, Shostak 2024 eq. (3)
};
// Shostak 2024 eq. (3). Negative layer values are read as 0 (the layers never hold them).
ShostakAttractiveness shostak_attractiveness(const ShostakCellValues& v, const ShostakAttractivenessParams& p);

struct ShostakAcoParams {
  uint32_t candidate_count = 20;                        // N, Shostak 2024 Sec. 3.4
  double step_m = 15.0;                                 // d, Shostak 2024 eq. (4) [m]
  double pitch_max_rad = std::numbers::pi / 6.0;        // ψ ~ U(-π/6, π/6), Shostak 2024 eq. (4) [rad]
  double alpha = 1.5;                                   // α, Shostak 2024 eq. (5)
  double beta = 3.0;                                    // β, Shostak 2024 eq. (5)
  // η is "the heuristic function" in Shostak 2024 eq. (5), not defined by the paper. Ours:
  // alignment with a preferred azimuth (current heading, or bearing to a
  // reported target, Shostak 2024 Sec. 4.3), η = floor + (1-floor)·(1 + cos Δθ)/2 in [floor, 1];
  // η = 1 for every candidate when there is no preferred azimuth.
  double eta_floor = 0.1;
};

struct ShostakCandidate {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // c_k, world frame [m]
  double azimuth_rad = 0.0;                            // θ in [0, 2π)
  double pitch_rad = 0.0;                              // ψ in [-ψmax, ψmax)
};
// Shostak 2024 eq. (4): c_k = p + d·(cos ψ cos θ, cos ψ sin θ, sin ψ), θ ~ U(0, 2π),
// ψ ~ U(-ψmax, ψmax), N candidates; draws θ then ψ per candidate.
std::vector<ShostakCandidate> shostak_candidates(const Eigen::Vector3d& p, const ShostakAcoParams& params, Rng& rng);

// Our η (see ShostakAcoParams::eta_floor).
double shostak_eta(double candidate_azimuth_rad, std::optional<double> preferred_azimuth_rad, const ShostakAcoParams& p);
// Shostak 2024 eq. (5): s = φ^α · η^β (0 for φ <= 0 or η <= 0).
double shostak_score(double phi, double eta, const ShostakAcoParams& p);
// Shostak 2024 eq. (6): draws index k with probability s_k / Σ s_j. Negative or non-finite
// scores count as 0; nullopt if no score is positive.
std::optional<std::size_t> shostak_roulette(std::span<const double> scores, Rng& rng);

// Cell containing the horizontal projection of a world position (floor).
Cell shostak_cell_of(const Eigen::Vector3d& p_world, double cell_size_m);

// Layer values the UAV knows at a cell (from its tiles); nullopt = unknown or
// outside the map, which scores 0 (the candidate is never taken).
using ShostakLookup = std::function<std::optional<ShostakCellValues>(Cell)>;

struct ShostakChoice {
  ShostakCandidate candidate;
  std::size_t index = 0;     // in the generated list
  double probability = 0.0;  // P(c_k), Shostak 2024 eq. (6)
};
// One decision of Shostak 2024 Sec. 3.4, Shostak 2024 Sec. 3.5 from world position p: generate candidates, score
// each at the cell under it, draw one. nullopt if every candidate scores 0.
std::optional<ShostakChoice> shostak_choose(const Eigen::Vector3d& p_world, std::optional<double> preferred_azimuth_rad,
                                            const ShostakLookup& lookup, double cell_size_m,
                                            const ShostakAcoParams& aco, const ShostakAttractivenessParams& attr,
                                            Rng& rng);

// Initial dispersal, Shostak 2024 Sec. 5: UAV `index` of `count` flies out at 2π·index/count
// (0°, 120°, 240° for the paper's three drones) [rad]; 0 if count == 0.
double shostak_dispersal_heading(uint32_t index, uint32_t count);
// The dispersal waypoint `distance_m` from `start` at that heading, same altitude.
Eigen::Vector3d shostak_dispersal_waypoint(const Eigen::Vector3d& start, uint32_t index, uint32_t count,
                                           double distance_m);

// ---------------------------------------------------------------------------
// GPS-denied local frame (Shostak 2024 Sec. 4.1) and drift (ours)
//
// Shostak 2024 Sec. 4.1: no GPS; each drone works in a local Cartesian frame with its origin
// at the take-off point, the pose coming from VIO / motion capture / LIDAR
// SLAM (ideal in the paper's simulation). Here a UAV knows only its own frame
// (where its origin sits in the shared map frame and its yaw, fixed at take-
// off) and an estimated pose in that frame; pure transforms carry points and
// headings between the two. Rotation is about +z only (the local frame is
// gravity-aligned).

struct ShostakLocalFrame {
  Eigen::Vector3d origin_world = Eigen::Vector3d::Zero();  // local (0,0,0) in the world frame [m]
  double yaw_rad = 0.0;  // rotation local -> world about +z, counter-clockwise [rad]
};
Eigen::Vector3d shostak_local_to_world(const ShostakLocalFrame& f, const Eigen::Vector3d& p_local);
Eigen::Vector3d shostak_world_to_local(const ShostakLocalFrame& f, const Eigen::Vector3d& p_world);
double shostak_heading_local_to_world(const ShostakLocalFrame& f, double heading_local_rad);  // wrapped to [0, 2π)
double shostak_heading_world_to_local(const ShostakLocalFrame& f, double heading_world_rad);  // wrapped to [0, 2π)

// Drift of a dead-reckoned pose (ours; the paper assumes ideal pose). Each
// move of true displacement Δ (local frame, length s = |Δ|) moves the
// estimate by R_z(e_yaw)·Δ + n, n ~ N(0, q_pos·s·I3), and then the yaw error
// does a random walk e_yaw += N(0, q_yaw·s). Errors thus grow with distance
// flown, not with time; with both q = 0 (the default) the estimate is exact.
struct ShostakDriftParams {
  double position_noise_m2_per_m = 0.0;  // q_pos, variance per axis per metre flown [m²/m]
  double yaw_noise_rad2_per_m = 0.0;     // q_yaw, heading variance per metre flown [rad²/m]
};
struct ShostakPoseEstimate {
  Eigen::Vector3d position_local = Eigen::Vector3d::Zero();  // estimated position in the UAV's frame [m]
  double yaw_error_rad = 0.0;                                // heading error of the estimate [rad]
};
ShostakPoseEstimate shostak_drift_step(const ShostakPoseEstimate& est, const Eigen::Vector3d& true_delta_local,
                                       const ShostakDriftParams& p, Rng& rng);

}  // namespace pheromesh::core
