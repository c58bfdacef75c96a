// Liu 2022, "Emergent Search of UAV Swarm Guided by the Target
// Probability Map" (ESUSTPM), Appl. Sci. 12, 5086: the pure math.
//  * target probability map (TPM): mixed-Gaussian prior (Liu 2022 eq. (1), Liu 2022 eq. (2)), the
//    per-cell update from an observation (Liu 2022 eq. (3), Liu 2022 eq. (4), Liu 2022 eq. (5)), confirmation threshold θ;
//  * environmental uncertainty (EU), the metric of Liu 2022 Table 2;
//  * the ESUSTPM local rules (Liu 2022 eq. (6), Liu 2022 eq. (7), Liu 2022 eq. (8), Liu 2022 eq. (9), Liu 2022 eq. (10), Liu 2022 eq. (11)) and the four baselines of Liu 2022 Sec. 5
//    (random search Liu 2022 eq. (12), Liu 2022 eq. (13), mower Liu 2022 eq. (14), Boids with and without TPM
//    guidance) as pure step functions;
//  * the visited-cell count of Liu 2022 Table 2.
// Where the paper is silent or self-contradictory, the choice made is written
// beside the code that makes it (see also liu/src/tpm.cpp).
//
// Units: positions [m] in the map frame (x east, y north = +y as in aco.hpp),
// velocities [m/s]. Cell (m, n) covers [m·s, (m+1)·s) x [n·s, (n+1)·s) for
// the cell size s = LiuParams::cell_size_m; the paper's "map(int, P)"
// (Liu 2022 Algorithm 1) is floor(P / s).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/heading.hpp"
#include "pheromesh/core/result.hpp"
#include "pheromesh/core/rng.hpp"

namespace pheromesh::core {

struct Vec2 {
  double x = 0.0;
  double y = 0.0;
  friend bool operator==(const Vec2&, const Vec2&) = default;
};

// How a miss (Liu 2022 eq. (5)) is applied. The paper prints
//   P(t) = (1 - Pd) P(t-1) / (1 - Pf),
// which is not the Bayesian posterior that Liu 2022 eq. (4) is for a detection; the
// posterior would be (1 - Pd) P / ((Pf - Pd) P + 1 - Pf). Both shrink P; the
// printed one by the constant factor (1 - Pd)/(1 - Pf) = 7/9 with Table-1
// sensor values, and it does not keep P = 1 at 1.
enum class MissUpdate : uint8_t {
  kAsPrinted,  // Liu 2022 eq. (5) exactly as printed (default: reproduce the paper)
  kBayes,      // the Bayesian posterior matching Liu 2022 eq. (4)
};

// Every number the paper gives, with where it gives it; values marked "ours"
// are not in the paper.
struct LiuParams {
  // --- sensor and TPM ---------------------------------------------------------
  // Liu 2022 Sec. 2.1: "The two parameters of the UAV sensor are set as 0.3 and 0.1"
  // (detection, false-alarm probability).
  double p_detection = 0.3;    // P_d
  double p_false_alarm = 0.1;  // P_f
  MissUpdate miss_update = MissUpdate::kAsPrinted;
  // θ of Liu 2022 Sec. 2.4 / Liu 2022 Algorithm 1 ("the TEP of a grid is more than the given value").
  // Not given; ours. 0.95 needs three detections from 0.5 (0.75, 0.9, 0.964):
  // a pass or two over a target cell, as the mower makes in Liu 2022 Sec. 5.2.3, does not
  // confirm it ("no target is found"), repeated visits (Liu 2022 Sec. 4) do.
  double confirm_threshold = 0.95;
  // Liu 2022 Sec. 5: "The initial target probability of each grid ... is set as 0.5".
  double initial_probability = 0.5;

  // --- local rules, Liu 2022 Table 1 (the same value for rules i = 1..4) -------------
  std::array<double, 4> k{-80.0, -80.0, -80.0, -80.0};    // k_i, Liu 2022 eq. (8)
  std::array<double, 4> t{5.0, 5.0, 5.0, 5.0};            // t_i, Liu 2022 eq. (7)
  std::array<double, 4> c{120.0, 120.0, 120.0, 120.0};    // c_i [m], Liu 2022 eq. (7), Liu 2022 eq. (8)
  std::array<double, 4> delta{40.0, 40.0, 40.0, 40.0};    // δ_i [m], Liu 2022 eq. (8)
  std::array<double, 4> delta_prime{10.0, 10.0, 10.0, 10.0};  // δ'_i [m], Liu 2022 eq. (7)
  // Liu 2022 Sec. 3.1: "each agent adopts the three closest neighbors".
  std::size_t neighbour_count = 3;
  // Liu 2022 Sec. 2.2 "The detection and communication range of UAV is limited"; the value
  // is not given. Ours: unlimited (the caller passes the UAVs it hears).
  double comm_range_m = std::numeric_limits<double>::infinity();

  // --- scenario, Liu 2022 Sec. 5 ---------------------------------------------------------
  int32_t grid_width = 10;   // [cell] "evenly divided as 10x10 grids"
  int32_t grid_height = 10;  // [cell]
  // Not stated; inferred from the coordinates of Liu 2022 Sec. 5 (starts at multiples of
  // 100 m, targets at (400, 500), (400, 700), (700, 500) on a 10x10 grid).
  double cell_size_m = 100.0;  // [m]
  uint32_t uav_count = 10;     // Liu 2022 Sec. 5 "A total of 10 UAVs"
  uint32_t cycles = 200;       // Liu 2022 Sec. 5 "The total simulation time cycle is 200"
  double max_speed_mps = 10.0; // Liu 2022 Sec. 5 "The maximum velocity of UAV agents is 10 m/s"
  double dt_s = 0.01;          // Δt [s], Liu 2022 Sec. 5 "The simulation interval is 10 ms"
  // Length of one "time cycle" [s]: not given. At 10 m/s and Δt = 10 ms a
  // cycle of one interval would move a UAV 0.1 m, and 200 cycles could not
  // cover a 1 km map as Liu 2022 Fig. 11 and Liu 2022 Fig. 20 show. Ours: 1 s (100 intervals), so a
  // UAV crosses 20 cells in 200 cycles and 10 mowers enter each of the 100
  // cells about twice — which is what Liu 2022 Table 2's mower EU needs (see
  // environmental_uncertainty).
  double cycle_s = 1.0;
  double random_step_mps = 10.0;  // S, Liu 2022 eq. (13) "it equals 10 in this paper"
  double mower_step_mps = 10.0;   // l, Liu 2022 eq. (14) "it equals 10 in this paper"

  // --- Boids baselines, Liu 2022 Sec. 5.1.4, Liu 2022 Sec. 5.1.5 ----------------------------------------
  double boids_safe_distance_m = 120.0;  // "The given safe distance between the agents is 120 m"
  // Rule weights: not given. Ours: equal.
  double boids_separation_weight = 1.0;
  double boids_alignment_weight = 1.0;
  double boids_cohesion_weight = 1.0;
  double boids_guidance_weight = 1.0;  // Boids with guidance only
};

// Liu 2022 Sec. 5: start positions [m] of the 10 UAVs, and the three targets of Liu 2022 Sec. 5.2/5.3.
inline constexpr std::array<Vec2, 10> kLiuStartPositions{{
    {100.0, 100.0}, {100.0, 200.0}, {100.0, 300.0}, {100.0, 400.0}, {100.0, 500.0},
    {200.0, 100.0}, {200.0, 200.0}, {200.0, 300.0}, {200.0, 400.0}, {200.0, 500.0},
}};
inline constexpr std::array<Vec2, 3> kLiuTargets{{{400.0, 500.0}, {400.0, 700.0}, {700.0, 500.0}}};
// Liu 2022 Sec. 5.3.2: wrong priors. (a) the prior's target at (700, 500) does not exist;
// (b) a real target at (300, 200) that the prior does not expect.
inline constexpr Vec2 kLiuAbsentPriorTarget{700.0, 500.0};
inline constexpr Vec2 kLiuUnexpectedTarget{300.0, 200.0};

// ---------------------------------------------------------------------------
// Prior map, Liu 2022 eq. (1), Liu 2022 eq. (2)
// ---------------------------------------------------------------------------

// One target's bivariate Gaussian, in cell units (cell (m, n) covers
// [m, m+1) x [n, n+1); the paper's (400, 500) m is (4, 5) with 100 m cells).
struct GaussianComponent {
  double mu_x = 0.0;     // μ1 [cell]
  double mu_y = 0.0;     // μ2 [cell]
  double sigma_x = 1.0;  // σ1 [cell], > 0 (the paper: σ1 = σ2 = σ0, value not given)
  double sigma_y = 1.0;  // σ2 [cell], > 0
  double rho = 0.0;      // ρ, correlation coefficient, |ρ| < 1
  double weight = 1.0;   // α_i, "the important degree of the target i", >= 0
};

// Error message if a component cannot be a density (σ <= 0, |ρ| >= 1,
// α < 0, non-finite values); nullopt if it is fine.
std::optional<Error> check_component(const GaussianComponent& g);

// Row-major w x h map (index y·w + x) with P_mn = ∬_cell Σ α_i f_i dx dy
// (Liu 2022 eq. (2) and the sentence after it): each cell holds the mixture's mass over
// the cell, clipped to [0, 1]. So the map sums to Σ α_i times the share of
// the mass inside the map — no other normalisation (the paper gives none).
// A "wrong" prior is just components placed where no target is. Components
// that fail check_component contribute nothing.
std::vector<double> gaussian_mixture_prior(int32_t w, int32_t h, std::span<const GaussianComponent> components);

// ---------------------------------------------------------------------------
// TPM update, Liu 2022 eq. (3), Liu 2022 eq. (4), Liu 2022 eq. (5)
// ---------------------------------------------------------------------------

// Liu 2022 eq. (4): P' = Pd P / ((Pd - Pf) P + Pf). Requires 0 <= P <= 1, 0 < Pf < 1.
double tpm_after_detection(double p, double p_detection, double p_false_alarm);
// Liu 2022 eq. (5), printed or Bayesian (see MissUpdate).
double tpm_after_miss(double p, double p_detection, double p_false_alarm, MissUpdate rule);
// One observation of a searched cell (Liu 2022 eq. (4) or Liu 2022 eq. (5)). An unsearched cell keeps
// its value (Liu 2022 eq. (3)): simply do not call this.
double tpm_update(double p, bool detected, const LiuParams& params);

// Per-cell target existing probabilities over a rectangle of the map, so a
// place agent can own its region of the TPM.
class TargetProbabilityMap {
 public:
  // Every cell of `region` at params.initial_probability.
  TargetProbabilityMap(Rect region, const LiuParams& params);
  // `region` cut out of a row-major map_width x map_height map (e.g. from
  // gaussian_mixture_prior). Errors: region not inside the map, wrong size,
  // a value outside [0, 1] or not finite.
  static Result<TargetProbabilityMap> from_map(Rect region, std::span<const double> map, int32_t map_width,
                                               int32_t map_height, const LiuParams& params);

  [[nodiscard]] Rect region() const { return region_; }
  [[nodiscard]] bool contains(Cell c) const { return region_.contains(c); }
  // Precondition: contains(c).
  [[nodiscard]] double probability(Cell c) const;
  // nullopt outside the region (use as a TpmLookup).
  [[nodiscard]] std::optional<double> find(Cell c) const;
  // Applies Liu 2022 eq. (4) (detected) or Liu 2022 eq. (5). Returns false and changes nothing
  // if c is outside the region (a cell from the network is never trusted).
  bool observe(Cell c, bool detected);
  // "find the target when the probability exceeds the threshold θ" (Liu 2022 Sec. 2.4):
  // P > θ. False outside the region.
  [[nodiscard]] bool confirmed(Cell c) const;
  [[nodiscard]] std::vector<Cell> confirmed_cells() const;
  // Row-major over the region.
  [[nodiscard]] std::span<const double> values() const { return p_; }

 private:
  TargetProbabilityMap(Rect region, std::vector<double> values, const LiuParams& params);
  [[nodiscard]] std::size_t index(Cell c) const;

  Rect region_;
  std::vector<double> p_;
  double p_detection_, p_false_alarm_, threshold_;
  MissUpdate miss_update_;
};

// ---------------------------------------------------------------------------
// Environmental uncertainty (Liu 2022 Table 2, Liu 2022 Fig. 12, Liu 2022 Fig. 21, Liu 2022 Fig. 29)
// ---------------------------------------------------------------------------

// EU = -Σ_cells P log2 P (0 log 0 = 0) [bit]. The paper names the metric but
// never defines it. This is the only entropy-like sum we found that fits
// Liu 2022 Table 2: an uninformed 10x10 map (P = 0.5) gives 50; its maximum is
// 100/(e ln 2) = 53.07, above the mower's 52.34, which visits all 100 cells
// once or twice (one miss per cell gives 52.99, two 52.18); random search
// (26 cells visited, 74 untouched = 37.0) gives 43.92 with its few cells
// visited often. The binary Shannon entropy Σ H(P) does not fit: the 74 cells
// random search never visits would alone contribute 74 > 43.92.
double environmental_uncertainty(std::span<const double> probabilities);
// Σ H(P) with H the binary entropy [bit]: 100 for an uninformed 10x10 map.
// Not the paper's metric (see above); kept for comparison.
double binary_entropy_bits(std::span<const double> probabilities);

// The lowest EU (environmental_uncertainty, bit) a search can leave on a map
// of `cells` cells at P0 = params.initial_probability when `looked_cells` of
// them were each looked at at least once and every look was a miss (no
// targets and Liu 2022 Algorithm 1's sensor, or a noisy sensor that never false-alarms),
// with at most `looks` looks in all; the other cells keep P0. A miss is
// printed Liu 2022 eq. (5) (P -> q P, q = (1 - Pd) / (1 - Pf)) whatever params.miss_update
// says. Exact minimum over every allocation of the looks (dynamic
// programming). +inf if looked_cells > looks; needs 0 <= looked_cells <= cells.
// What it is for: the liu-table2 investigation shows that Liu 2022 Table 2's
// ESUSTPM pair (visited cells, EU) cannot be reached with the looks ten UAVs
// make in 200 cycles.
double liu_lowest_eu(int32_t looked_cells, int32_t cells, int32_t looks, const LiuParams& params);

// ---------------------------------------------------------------------------
// UAV state and grid helpers
// ---------------------------------------------------------------------------

struct LiuUav {
  Vec2 position;  // [m]
  Vec2 velocity;  // [m/s]
};

// Centre of a cell [m].
Vec2 cell_centre(Cell c, double cell_size_m);
// floor(P / s) per axis (Liu 2022 Algorithm 1 "map(int, P)"), clamped into the grid
// so a UAV exactly on the far border is in the last cell.
Cell cell_of(Vec2 position, const LiuParams& p);
// Nearest of the eight compass headings to v (sector rule of aco.cpp:
// floor((bearing + 22.5°) / 45°) mod 8); nullopt if |v| < 1e-9.
std::optional<Heading> heading_of(Vec2 v);

// Target existing probability of a cell as the UAV knows it; nullopt for a
// cell outside the map or one it has no value for.
using TpmLookup = std::function<std::optional<double>(Cell)>;

// Indices into `others` of the (at most) params.neighbour_count UAVs nearest
// to `self` within comm_range_m, nearest first; equal distances by index.
// `others` must not hold the UAV itself.
std::vector<std::size_t> nearest_neighbours(Vec2 self, std::span<const LiuUav> others, const LiuParams& params);

// The most probable of the eight cells around `at` that the lookup knows
// (Liu 2022 Sec. 3.1 rule 4, "the nearby grid with the highest target existing
// probability"; the cell under the UAV is not a candidate). Ties (within
// 1e-12) — every cell is 0.5 at the start — go to the cell whose direction is
// closest to `velocity` (keep going), then to the first heading from E
// counter-clockwise. nullopt if no neighbouring cell is known.
std::optional<Cell> most_probable_neighbour(Cell at, Vec2 velocity, const TpmLookup& tpm);

// Liu 2022 eq. (7), Liu 2022 eq. (8), Liu 2022 eq. (9): β_i(d) = a_i(d) g_i(d) for rule i (0-based, 0..3) [m/s per unit direction].
double liu_gain(std::size_t rule, double distance_m, const LiuParams& params);

// A velocity decision, mapped onto the grid.
struct LiuMove {
  Vec2 velocity;                   // [m/s], after clipping to max speed and border reversal
  std::optional<Heading> heading;  // compass heading of the grid step; nullopt = stay
  Cell next;                       // cell after one grid step from the UAV's cell
};

// Maps a velocity onto the grid: the heading nearest to v from the cell of
// `position`; at the map border the offending components of the step and of
// v are reversed (Liu 2022 Sec. 2.2 "When the monomers reach the boundaries of the
// mission area, the velocities are reversed"); if that still leaves the map
// (one-cell-wide map) the UAV stays.
LiuMove grid_move(Vec2 position, Vec2 velocity, const LiuParams& params);

// Liu 2022 eq. (10), Liu 2022 eq. (11) in continuous space: P += v Δt with the same border reversal
// (reflection) on a map of grid_width·cell_size x grid_height·cell_size.
LiuUav advance_uav(const LiuUav& uav, Vec2 velocity, double dt_s, const LiuParams& params);

// ---------------------------------------------------------------------------
// ESUSTPM, Liu 2022 eq. (6), Liu 2022 eq. (7), Liu 2022 eq. (8), Liu 2022 eq. (9)
// ---------------------------------------------------------------------------

// Objective velocity mvel of Liu 2022 eq. (6) before clipping:
//   mvel = 1/4 Σ_{i=1..4} β_i (F_i / |F_i|)
// F_1..F_3 from the three nearest neighbours, F_4 towards the centre of the
// most probable neighbouring cell. Sign convention: with Liu 2022 Table 1's k < 0,
// β(d) > 0 for d < c and < 0 for d > c. Liu 2022 Sec. 5 says agents "repel each other when
// the distance between them is less than the safe distance", so F_i (i <= 3)
// points from the neighbour to the UAV. For rule 4 the same sign would push
// the UAV away from a best cell farther than c = 120 m (a diagonal neighbour
// at 141 m), against "always guides the UAV to grids with the highest target
// existing probability": F_4 points at the cell and is weighted by |β_4|.
// A neighbour at distance 0 gives no direction and adds nothing; fewer than
// three neighbours keep the factor 1/4.
Vec2 esustpm_objective_velocity(const LiuUav& self, std::span<const LiuUav> others, const TpmLookup& tpm,
                                const LiuParams& params);
// One ESUSTPM decision: mvel clipped to max_speed_mps ("mass points with the
// maximum velocity", Liu 2022 Sec. 2.2); if mvel is 0 the UAV keeps its velocity. Then
// grid_move. No randomness: the paper has none here.
LiuMove esustpm_step(const LiuUav& self, std::span<const LiuUav> others, const TpmLookup& tpm,
                     const LiuParams& params);

// ---------------------------------------------------------------------------
// ESUSTPM-disperse: a variant of ours, not the paper's (docs/policies/liu.md)
// ---------------------------------------------------------------------------

// ESUSTPM with the attracting half of the neighbour rules dropped: for the
// three nearest neighbours only β_i(d) > 0 (d < c_i, "repel each other when
// the distance between them is less than the safe distance", Liu 2022 Sec. 5)
// is kept; the pull back towards c_i of a neighbour farther than c_i is 0.
// Rule 4 (the TPM guidance) is ESUSTPM's. Why: with Liu 2022 Table 1's
// constants the pull holds the ten UAVs in a rigid lattice that drifts as one
// body (the liu-table2 investigation), so the swarm enters few new cells;
// without it the UAVs keep their spacing at close range and otherwise follow
// the TPM apart. Same sensor, TPM update and speed as ESUSTPM.
Vec2 esustpm_disperse_objective_velocity(const LiuUav& self, std::span<const LiuUav> others, const TpmLookup& tpm,
                                         const LiuParams& params);
// One ESUSTPM-disperse decision: as esustpm_step with the objective above.
LiuMove esustpm_disperse_step(const LiuUav& self, std::span<const LiuUav> others, const TpmLookup& tpm,
                              const LiuParams& params);

// ---------------------------------------------------------------------------
// Baselines of Liu 2022 Sec. 5
// ---------------------------------------------------------------------------

// Liu 2022 eq. (12): dir = r / |r|, r with two components uniform in [-1, 1) (drawn
// again in the measure-zero case r = 0). As printed this is not uniform in
// angle (diagonals are likelier); kept.
Vec2 random_direction(Rng& rng);
// Liu 2022 eq. (12), Liu 2022 eq. (13): velocity dir · S, then grid_move. The paper's collision
// avoidance of random searchers is not specified and not modelled.
LiuMove random_search_step(const LiuUav& self, Rng& rng, const LiuParams& params);

// Liu 2022 eq. (14) on the grid: P += b l Δt with b reversed at the boundary. Each UAV
// sweeps its own lane (a band of rows) boustrophedon-style: along x, and at
// the lane's end one row up (or down) with b reversed. A one-row lane is
// exactly Liu 2022 eq. (14): back and forth along the row. A lane of W x H cells is
// covered in W·H - 1 steps from its corner.
struct LawnmowerState {
  Cell cell;
  int32_t dx = 1;  // b along x: +1 or -1
  int32_t dy = 1;  // row change at the lane's end: +1 or -1
};
// Lane of UAV `uav` of `uavs` on a w x h grid: rows split into contiguous
// bands as evenly as possible (10 UAVs on 10 rows: one row each). Requires
// 0 < uavs <= h and uav < uavs.
Rect lawnmower_lane(uint32_t uav, uint32_t uavs, int32_t w, int32_t h);
// Start at the lane's lower-left cell, moving +x, then upwards.
LawnmowerState lawnmower_start(Rect lane);
LawnmowerState lawnmower_step(const LawnmowerState& s, Rect lane);

// Boids without guidance (Liu 2022 Sec. 5.1.4): Reynolds' three rules over the three
// nearest neighbours (the paper says "nearby neighbors"; we use the same set
// as ESUSTPM). Each rule contributes a unit vector (or nothing):
//   separation: Σ over neighbours closer than the safe distance (120 m) of
//               the unit vector away from them, normalised;
//   alignment:  the neighbours' mean velocity, normalised;
//   cohesion:   towards the neighbours' centroid, normalised;
// desired = Σ weight · unit vector; velocity = max speed along desired (the
// current velocity if desired is 0). Then grid_move.
LiuMove boids_step(const LiuUav& self, std::span<const LiuUav> others, const LiuParams& params);
// Boids with guidance (Liu 2022 Sec. 5.1.5): the same plus boids_guidance_weight times
// the unit vector towards the centre of most_probable_neighbour.
LiuMove boids_guided_step(const LiuUav& self, std::span<const LiuUav> others, const TpmLookup& tpm,
                          const LiuParams& params);

// ---------------------------------------------------------------------------
// Metrics
// ---------------------------------------------------------------------------

// "Visited grid number" of Liu 2022 Table 2 / Liu 2022 Fig. 11, Liu 2022 Fig. 20: distinct cells that some
// UAV has been in.
class VisitedCells {
 public:
  VisitedCells(int32_t w, int32_t h);
  // Returns true on the first visit of c; cells outside the grid are ignored.
  bool visit(Cell c);
  [[nodiscard]] bool visited(Cell c) const;
  [[nodiscard]] int64_t count() const { return count_; }

 private:
  int32_t w_, h_;
  std::vector<uint8_t> seen_;
  int64_t count_ = 0;
};

}  // namespace pheromesh::core
