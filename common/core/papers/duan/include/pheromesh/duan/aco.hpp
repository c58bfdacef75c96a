// Duan, Zhang, Wu, Ma 2009, "Max-Min adaptive ant colony optimization approach
// to multi-UAVs coordinated trajectory replanning in dynamic and uncertain
// environments", J. Bionic Eng. 6:161-173 (doi 10.1016/S1672-6529(08)60113-4).
//
//  * ThreatMesh: the 2-D mesh of Duan 2009 Sec. 2.2 with the edge costs of Duan 2009 eq. (2), Duan 2009 eq. (3).
//  * DuanColony: one Max-Min adaptive ACO colony per UAV (Duan 2009 eq. (9), Duan 2009 eq. (10), Duan 2009 eq. (11), Duan 2009 eq. (12), Duan 2009 eq. (13), Duan 2009 eq. (14), Duan 2009 eq. (15), Duan 2009 eq. (16), Duan 2009 eq. (17), Duan 2009 eq. (18)) with
//    edge pheromone and point pheromone (inter-UAV collision avoidance).
//  * coordinate_eta: ETA for simultaneous arrival (Duan 2009 eq. (4), Duan 2009 eq. (5), Duan 2009 eq. (6), Duan 2009 eq. (7), Duan 2009 eq. (8)).
//  * duan2009_scenario: the data of Duan 2009 Table 1, Duan 2009 Table 2, Duan 2009 Table 3, Duan 2009 Table 4.
// The interpretations of the paper are listed in duan/src/aco.cpp.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <span>
#include <vector>

#include "pheromesh/core/result.hpp"
#include "pheromesh/core/rng.hpp"

namespace pheromesh::core {

// ---------------------------------------------------------------------------
// Threats and the mesh (Duan 2009 Sec. 2.2)
// ---------------------------------------------------------------------------

struct PointKm {
  double x = 0.0;  // [km]
  double y = 0.0;  // [km]
  friend bool operator==(const PointKm&, const PointKm&) = default;
};

// A radar / missile site / gun / pop-up threat (Duan 2009 Table 1 and Duan 2009 Table 4).
struct Threat {
  PointKm centre{};
  double radius_km = 0.0;  // threatened range: beyond it the threat adds no cost
  double grade = 1.0;      // w_k, threat weighting coefficient of Duan 2009 eq. (2)
};

// w_k / d^4 summed over the threats whose range covers p (the integrand of
// Duan 2009 eq. (1)); d is floored at kMinThreatDistanceKm so a sample point on a threat
// centre stays finite.
inline constexpr double kMinThreatDistanceKm = 1e-3;
double threat_intensity(std::span<const Threat> threats, PointKm p);

// Duan 2009 eq. (2): J_threat = L_ab · Σ_k w_k (d_0.1,k^-4 + d_0.3,k^-4 + d_0.5,k^-4 +
// d_0.7,k^-4 + d_0.9,k^-4), i.e. L_ab times the sum of threat_intensity at the
// points 1/10, 3/10, ..., 9/10 of the segment a -> b.
double edge_threat_cost(std::span<const Threat> threats, PointKm a, PointKm b);

// Duan 2009 eq. (3): J = f·J_threat + (1 - f)·J_fuel with J_fuel = L [km].
inline constexpr double kDuanThreatWeight = 0.75;  // f, Duan 2009 Sec. 2.2
double edge_cost(double threat_cost, double length_km, double f = kDuanThreatWeight);

// The task region [x0, x0 + width] x [y0, y0 + height] divided into
// sections_x (m) x sections_y (n) equal sections: (m + 1) x (n + 1) nodes.
// The paper's region (60 km x 70 km, all its coordinates even) uses 2 km.
struct MeshSpec {
  PointKm origin{0.0, 0.0};
  double width_km = 60.0;
  double height_km = 70.0;
  int32_t sections_x = 30;  // m
  int32_t sections_y = 35;  // n
  double f = kDuanThreatWeight;
};

using NodeId = uint32_t;
inline constexpr NodeId kNoNode = std::numeric_limits<NodeId>::max();

// Edges join every node to its (up to) eight neighbours: E, NE, N, NW, W, SW,
// S, SE (direction index 0..7, counter-clockwise from +x).
class ThreatMesh {
 public:
  static constexpr int kDirections = 8;

  // Checks the spec (positive sizes, f in [0, 1], threats with radius > 0 and
  // grade >= 0) and builds the mesh.
  static Result<ThreatMesh> create(const MeshSpec& spec, std::vector<Threat> threats = {});
  // Preconditions as in create() (asserted).
  explicit ThreatMesh(const MeshSpec& spec, std::vector<Threat> threats = {});

  [[nodiscard]] const MeshSpec& spec() const { return spec_; }
  [[nodiscard]] int32_t columns() const { return spec_.sections_x + 1; }  // m + 1
  [[nodiscard]] int32_t rows() const { return spec_.sections_y + 1; }     // n + 1
  [[nodiscard]] std::size_t node_count() const { return positions_.size(); }
  [[nodiscard]] double step_x_km() const { return step_x_; }
  [[nodiscard]] double step_y_km() const { return step_y_; }

  // L_i(x_i, y_j) of the paper is node(i - 1, j - 1).
  [[nodiscard]] NodeId node(int32_t ix, int32_t iy) const;
  [[nodiscard]] int32_t ix(NodeId n) const { return static_cast<int32_t>(n % static_cast<NodeId>(columns())); }
  [[nodiscard]] int32_t iy(NodeId n) const { return static_cast<int32_t>(n / static_cast<NodeId>(columns())); }
  [[nodiscard]] PointKm position(NodeId n) const { return positions_[n]; }
  // Nearest node to p; nullopt if p is outside the region.
  [[nodiscard]] std::optional<NodeId> nearest_node(PointKm p) const;

  // Edge from n in direction dir (0..7); neighbour() is kNoNode off the mesh.
  [[nodiscard]] NodeId neighbour(NodeId n, int dir) const { return edges_[edge_index(n, dir)].to; }
  [[nodiscard]] double edge_length_km(NodeId n, int dir) const { return edges_[edge_index(n, dir)].length_km; }
  [[nodiscard]] double edge_threat_cost(NodeId n, int dir) const { return edges_[edge_index(n, dir)].threat; }
  [[nodiscard]] double edge_cost(NodeId n, int dir) const { return edges_[edge_index(n, dir)].cost; }
  // Direction of the edge a -> b, or -1 if a and b are not neighbours.
  [[nodiscard]] int direction(NodeId a, NodeId b) const;
  [[nodiscard]] static std::size_t edge_index(NodeId n, int dir) {
    return static_cast<std::size_t>(n) * kDirections + static_cast<std::size_t>(dir);
  }

  [[nodiscard]] const std::vector<Threat>& threats() const { return threats_; }
  // Pop-up threats (replanning Step 2): adds them and recomputes the threat
  // cost of the edges in their range.
  void add_threats(std::span<const Threat> popups);

  // Σ of Duan 2009 eq. (3) costs along a node path (consecutive nodes must be neighbours).
  struct PathCost {
    double length_km = 0.0;
    double threat = 0.0;  // Σ J_threat
    double cost = 0.0;    // Σ J
  };
  [[nodiscard]] PathCost path_cost(std::span<const NodeId> nodes) const;

 private:
  struct Edge {
    NodeId to = kNoNode;
    double length_km = 0.0;
    double threat = 0.0;
    double cost = 0.0;
  };
  void recompute_edge(NodeId n, int dir);

  MeshSpec spec_;
  double step_x_ = 0.0, step_y_ = 0.0;  // [km]
  std::vector<Threat> threats_;
  std::vector<PointKm> positions_;
  std::vector<Edge> edges_;  // node_count() * kDirections
};

// Angle [rad, 0..π] between the headings prev -> cur and cur -> next.
double turn_angle_rad(PointKm prev, PointKm cur, PointKm next);
// Duan 2009 Sec. 2.3 (1), Duan 2009 Fig. 4: next is selectable from cur iff the turn is at most max_turn_rad.
bool turn_allowed(PointKm prev, PointKm cur, PointKm next, double max_turn_rad);

// ---------------------------------------------------------------------------
// Max-Min adaptive ACO (Duan 2009 Sec. 3)
// ---------------------------------------------------------------------------

enum class DepositRule : uint8_t {
  BelowAverage,   // Duan 2009 Sec. 3.2 (1) as reconstructed: J_k <= J_ave(t) deposits
  IterationBest,  // the literal "J_k <= J_min(t)": only the iteration-best ants
};

// Which planner turns the colony's walks into candidate trajectories.
enum class DuanPlanner : uint8_t {
  Paper,        // Duan 2009 as printed: the ants' mesh walks are the candidates
  LineOfSight,  // ours ("duan_los", docs/policies/duan.md): each walk shortcut by line_of_sight_shortcut
  // ours (docs/policies/duan.md): as LineOfSight, but a shortcut is taken only
  // if it raises neither Duan 2009 eq. (3)'s J nor Duan 2009 eq. (1)'s exposure
  SafeLineOfSight,
};

struct DuanAcoParams {
  double alpha = 3.0;        // α, trail exponent of Duan 2009 eq. (11)
  double beta = 2.0;         // β, visibility exponent of Duan 2009 eq. (11)
  double rho = 0.7;          // ρ, evaporation of Duan 2009 eq. (12), Duan 2009 eq. (13)
  double q = 10.0;           // Q of Duan 2009 eq. (16), Duan 2009 eq. (17)
  uint32_t iterations = 20;  // Nc_max
  uint32_t ants = 20;        // m
  double tau_min = 0.1;      // Duan 2009 eq. (18)
  double tau_max = 10.0;     // Duan 2009 eq. (18)
  double tau_initial = 10.0;       // edge pheromone at start; not given: τ_max, as in Max-Min AS [24]
  double tau_point_initial = 0.1;  // point pheromone at start; not given: τ_min (no node claimed yet)
  double max_turn_rad = std::numbers::pi / 4.0;  // Duan 2009 Fig. 4 (not given numerically)
  DepositRule deposit = DepositRule::BelowAverage;
  uint32_t candidate_count = 4;  // candidate trajectories per UAV for the ETA (Duan 2009 Sec. 3.3)
  // Not in the paper: our variant shortcuts every walk (the colony's pheromone
  // dynamics stay the paper's; only the candidates change).
  DuanPlanner planner = DuanPlanner::Paper;
};

// Σ_{j≠i} τ^p_{j,u} over the other UAVs of Duan 2009 eq. (10), per node, and their number
// N - 1. Empty (uav_count == 0): a lone UAV, the point-pheromone factor is 1.
struct PointPheromone {
  uint32_t uav_count = 0;
  std::vector<double> sum;  // [node]
  // Adds the point pheromone of one more UAV (size node_count()).
  void add(std::span<const double> tau_p);
};

// Duan 2009 eq. (10): τ_i,su = τ^e_i,su · (N - 1) / Σ_{j≠i} τ^p_{j,u}.
double combined_pheromone(double tau_edge, double others_point_sum, uint32_t others_count);
// Duan 2009 eq. (9): η_su = 1 / (J_su · d_u,target).
double heuristic(double edge_cost, double distance_to_target_km);
// Duan 2009 eq. (11) over the allowed edges of one node: p_u = τ_u^α η_u^β / Σ_v τ_v^α η_v^β.
// All zero if every weight is zero.
std::vector<double> transition_probabilities(std::span<const double> tau, std::span<const double> eta,
                                             double alpha, double beta);
// Duan 2009 eq. (12)/(13) then Duan 2009 eq. (18): clamp((1 - ρ)·τ + Δτ, τ_min, τ_max).
double updated_pheromone(double tau, double delta, double rho, double tau_min, double tau_max);

// ---------------------------------------------------------------------------
// Line-of-sight shortcut (ours, not in the paper; docs/policies/duan.md)
// ---------------------------------------------------------------------------

// Duan 2009 eq. (2) on a straight segment of any length: the segment is cut into
// ceil(L / max_piece_km) equal pieces and Duan 2009 eq. (2) is summed over them, so a long
// segment is sampled at least as densely as a mesh edge (5 points per piece)
// and cannot jump over a threat between two sample points.
double segment_threat_cost(std::span<const Threat> threats, PointKm a, PointKm b, double max_piece_km);

// Σ over a polyline of mesh nodes: consecutive neighbours cost their mesh
// edge (identical to ThreatMesh::path_cost); other pairs cost the straight
// segment by segment_threat_cost with pieces no longer than the mesh spacing
// (min of step_x, step_y), and Duan 2009 eq. (3) with the mesh's f.
ThreatMesh::PathCost polyline_cost(const ThreatMesh& mesh, std::span<const NodeId> nodes);

// Greedy line-of-sight pruning of a walk: from each kept node, jump to the
// farthest later node of the walk whose straight segment costs (Duan 2009 eq. (3), by
// polyline_cost) no more than the stretch of walk it replaces, provided the
// turn limit holds at both ends of the new segment (at the first node against
// `previous` if given, else free, as for the ants). The result keeps the
// walk's first and last node, never costs more, and obeys the turn limit.
std::vector<NodeId> line_of_sight_shortcut(const ThreatMesh& mesh, std::span<const NodeId> walk,
                                           std::optional<NodeId> previous, double max_turn_rad);

// Step of the midpoint rule for the exposure test of safe_line_of_sight_shortcut
// (the same step the duan-table3 experiment measures exposure with).
inline constexpr double kSafeShortcutExposureStepKm = 0.05;

// As line_of_sight_shortcut, but a straight segment must also have a Duan 2009
// Duan 2009 eq. (1) exposure (threat_exposure with kSafeShortcutExposureStepKm) no
// higher than the stretch of walk it replaces: the result never costs more
// and is never more exposed than the walk.
std::vector<NodeId> safe_line_of_sight_shortcut(const ThreatMesh& mesh, std::span<const NodeId> walk,
                                                std::optional<NodeId> previous, double max_turn_rad);

// Threat exposure of a polyline, planner-neutral: Duan 2009 eq. (1)'s line integral of
// Σ w_k / d^4 (inside each range) by the midpoint rule with pieces of at most
// step_km. Used to compare planners whose trajectories Duan 2009 eq. (2) samples
// differently (mesh edges vs long segments).
double threat_exposure(std::span<const Threat> threats, std::span<const PointKm> polyline, double step_km);

struct Trajectory {
  // start ... goal: mesh neighbours (DuanPlanner::Paper) or, after the
  // line-of-sight shortcut, any nodes joined by straight segments.
  std::vector<NodeId> nodes;
  double length_km = 0.0;
  double threat_cost = 0.0;  // Σ J_threat
  double cost = 0.0;         // J_i,k = Σ J_su (Duan 2009 eq. (3) summed)
};

struct PathResult {
  bool found = false;  // false: no ant reached the goal (or start/goal invalid)
  Trajectory best;     // global best over all iterations
  // Up to candidate_count best distinct trajectories, cost ascending
  // (candidates[0] == best); input of coordinate_eta.
  std::vector<Trajectory> candidates;
  // Best-so-far cost after each iteration (Duan 2009 Fig. 14, Duan 2009 Fig. 17); +inf until found.
  std::vector<double> best_cost_history;
};

// One ant colony (sub-population) planning for one UAV. Keeps a reference to
// the mesh: costs changed by ThreatMesh::add_threats are used by the next
// begin()/plan(). The random stream is consumed by plan(), so the same seed
// and the same calls give the same trajectories.
class DuanColony {
 public:
  DuanColony(const ThreatMesh& mesh, const DuanAcoParams& params, Rng rng);

  // Nc_max iterations from start to goal against a fixed point pheromone of
  // the other UAVs. `previous` is the node the UAV came from (replanning): the
  // first step then obeys the turn constraint too.
  PathResult plan(NodeId start, NodeId goal, const PointPheromone& others,
                  std::optional<NodeId> previous = std::nullopt);

  // Step API for colonies that exchange point pheromone every iteration
  // (Duan 2009 Fig. 11 / Step 6; see plan_team). begin() resets the pheromone.
  void begin(NodeId start, NodeId goal, std::optional<NodeId> previous = std::nullopt);
  void iterate(const PointPheromone& others);
  [[nodiscard]] const PathResult& result() const { return result_; }

  [[nodiscard]] const std::vector<double>& edge_pheromone() const { return tau_edge_; }  // [edge_index]
  [[nodiscard]] const std::vector<double>& point_pheromone() const { return tau_point_; }  // [node]
  [[nodiscard]] const DuanAcoParams& params() const { return params_; }

 private:
  // Walks one ant; false if it got stuck (no allowed, unvisited neighbour).
  bool walk(const PointPheromone& others, std::vector<NodeId>& path);
  void offer_candidate(const std::vector<NodeId>& path, double cost);
  // DuanPlanner::LineOfSight: the walk shortcut, memoised per walk (stagnating
  // colonies repeat their walks).
  const std::vector<NodeId>& shortcut_of(const std::vector<NodeId>& walk);

  const ThreatMesh* mesh_;
  DuanAcoParams params_;
  Rng rng_;
  NodeId start_ = kNoNode, goal_ = kNoNode;
  std::optional<NodeId> previous_;
  std::vector<double> tau_edge_, tau_point_;
  std::vector<double> eta_beta_;   // η^β per edge for the current goal
  std::vector<uint32_t> visited_;  // stamp per node
  uint32_t stamp_ = 0;
  std::array<std::array<bool, ThreatMesh::kDirections>, ThreatMesh::kDirections> turn_ok_{};
  std::map<std::vector<NodeId>, std::vector<NodeId>> shortcuts_;  // walk -> shortcut, reset by begin()
  PathResult result_;
};

struct UavTask {
  NodeId start = kNoNode;
  NodeId goal = kNoNode;
  std::optional<NodeId> previous;  // heading at start (replanning)
};

// Duan 2009 Fig. 12: the colonies of all UAVs iterate in lockstep; before each
// iteration every colony receives the summed point pheromone of the others
// from the previous iteration (Step 6). colonies.size() == tasks.size().
// after_iteration(t), if given, is called after lockstep iteration t (0-based)
// of every colony, e.g. to read the candidates as they improve.
std::vector<PathResult> plan_team(std::span<DuanColony> colonies, std::span<const UavTask> tasks,
                                  const std::function<void(uint32_t iteration)>& after_iteration = {});

// ---------------------------------------------------------------------------
// ETA coordination (Duan 2009 Sec. 2.3 (2), 2.4)
// ---------------------------------------------------------------------------

struct SpeedLimits {
  double min_mps = 200.0;  // V_min [m/s], Duan 2009 Sec. 4
  double max_mps = 300.0;  // V_max [m/s]
};

struct TimeInterval {
  double earliest_s = 0.0;  // [s]
  double latest_s = 0.0;    // [s]
};

// Duan 2009 eq. (4): T ∈ [L / V_max, L / V_min].
TimeInterval arrival_interval(double length_km, const SpeedLimits& speeds);

struct EtaCandidate {
  double length_km = 0.0;
  double cost = 0.0;  // J_i,j of Duan 2009 eq. (7)
};

enum class EtaRule : uint8_t {
  EarliestFeasible,     // T_a = min S (Duan 2009 Sec. 2.4, Duan 2009 Fig. 6)
  MinCoordinationCost,  // T_a = argmin over S of Duan 2009 eq. (8) with f1, f2
};

struct EtaOptions {
  EtaRule rule = EtaRule::EarliestFeasible;
  double f1 = 1.0;  // Duan 2009 eq. (7), weight of the trajectory cost
  double f2 = 1.0;  // Duan 2009 eq. (7), weight of the arrival time [1/s]
};

struct EtaPlan {
  double eta_s = 0.0;                // T_a [s]
  std::vector<TimeInterval> window;  // S of Duan 2009 eq. (6), sorted, disjoint
  std::vector<std::size_t> chosen;   // per UAV, index of the candidate flown
  std::vector<double> speed_mps;     // per UAV, V = L / T_a [m/s]
};

// Duan 2009 eq. (5), Duan 2009 eq. (6), Duan 2009 eq. (7), Duan 2009 eq. (8): S_i = ∪_j [L_ij/Vmax, L_ij/Vmin], S = ∩_i S_i, T_a ∈ S by the
// rule; each UAV flies its cheapest candidate feasible at T_a at V = L / T_a.
// Error if S is empty or the input is invalid.
Result<EtaPlan> coordinate_eta(const std::vector<std::vector<EtaCandidate>>& candidates,
                               const SpeedLimits& speeds, const EtaOptions& options = {});
// One trajectory per UAV: T_a = max_i L_i / V_max if it is <= min_i L_i / V_min.
Result<EtaPlan> coordinate_eta(std::span<const double> lengths_km, const SpeedLimits& speeds);

// ---------------------------------------------------------------------------
// The paper's experiment (Duan 2009 Sec. 4)
// ---------------------------------------------------------------------------

struct Duan2009Uav {
  PointKm start{};   // Duan 2009 Table 2
  PointKm target{};  // Duan 2009 Table 2
};

struct Duan2009Scenario {
  MeshSpec mesh;                  // 60 km x 70 km region (Duan 2009 Sec. 4), 2 km mesh
  std::vector<Threat> threats;    // Duan 2009 Table 1
  std::vector<Duan2009Uav> uavs;  // Duan 2009 Table 2 (second experiment, three UAVs)
  std::vector<Threat> popups;     // Duan 2009 Table 4 (time of appearance not given)
  SpeedLimits speeds;             // 200..300 m/s (Duan 2009 Sec. 4)
  DuanAcoParams aco;              // Duan 2009 Sec. 4 parameters
  // Duan 2009 Table 3 (reported results, for comparison; Duan 2009 Fig. 15 text says T_a = 173 s).
  double table3_eta_s = 174.0;
  std::array<double, 3> table3_length_km{51.31, 47.80, 52.14};
  std::array<double, 3> table3_speed_mps{295.0, 275.0, 300.0};
};

Duan2009Scenario duan2009_scenario();

}  // namespace pheromesh::core
