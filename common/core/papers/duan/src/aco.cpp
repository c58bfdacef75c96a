// Duan 2009, Max-Min adaptive ACO trajectory (re)planning.
//
// Reading of the paper (the text is partly mangled; figures are missing):
//  * Mesh (Duan 2009 Sec. 2.2, Duan 2009 Fig. 2). OX is cut into m and OY into n equal
//    sections; the (m+1)(n+1) crossings L_i(x_i, y_j) are the nodes. Paths
//    {B, L_i1, ..., A} are read as walks on this grid with 8-neighbour edges:
//    the lengths of Duan 2009 Table 3 are all of the form 2·(a + b·√2) km (51.31 =
//    2(20 + 4√2), 47.80 = 2(14 + 7√2), 52.14 = 2(19 + 5√2)) and every
//    coordinate of Duan 2009 Table 1, Duan 2009 Table 2, Duan 2009 Table 4 is even, so the paper's mesh is the 60 x 70
//    km region with 2 km spacing (m = 30, n = 35) and straight + diagonal edges. Edges are directed for the pheromone
//    (start -> goal walks); costs are symmetric.
//  * Duan 2009 eq. (1) is not used; Duan 2009 eq. (2) is implemented as printed: L_ij times the sum
//    of w_k / d^4 at the 1/10, 3/10, ..., 9/10 points (not L/5 times it), with
//    d in km. N_t ("threats that can pose threat to the edge") is read per
//    sample point: threat k adds w_k / d^4 at a point only if d <= R_k, so the
//    radius of Duan 2009 Table 1/4 is the threatened range and the grade is w_k.
//    d is floored at 1 m so a point on a threat centre stays finite.
//    With d in km the cost only bites within ~3 km of a centre, which matches
//    Duan 2009 Table 3: UAV-3's 52.14 km is the octile-shortest length although every
//    such path touches the ranges of threats 1 and 2.
//  * Duan 2009 eq. (3): J = f·J_threat + (1 - f)·L with f = 0.75; J_fuel = L [km].
//  * Turn constraint (Duan 2009 Fig. 4, figure missing): the next node must not turn the
//    heading by more than max_turn_rad (default 45°: the three nodes "ahead"
//    of the previous waypoint (b)). At the start of a plan every neighbour is
//    allowed unless a previous node is given (replanning).
//  * Ant walks: tabu list (no node twice); an ant with no allowed neighbour is
//    dropped for the iteration (no cost, no deposit). When the goal is an
//    allowed neighbour the ant takes it: η -> ∞ as d_u,target -> 0 in Duan 2009 eq. (9),
//    so Duan 2009 eq. (11) gives it probability 1.
//  * Duan 2009 eq. (10): τ_i,su = τ^e_i,su · (N-1) / Σ_{j≠i} τ^p_{j,u}: a node rich in
//    the other UAVs' point pheromone (their good paths) is penalised, a node
//    they left at τ_min is favoured; N = 1 gives a factor of 1.
//  * Duan 2009 eq. (12), Duan 2009 eq. (13), Duan 2009 eq. (14), Duan 2009 eq. (15), Duan 2009 eq. (16), Duan 2009 eq.
//  (17): evaporation with ρ on every edge and node, then deposits
//    Q / J_i,k by the ants allowed by Duan 2009 Sec. 3.2 (1) on every edge and every
//    node (start and goal included) of their walk. Duan 2009 Sec. 3.2 (1) defines the
//    average J_ave(t) and then says "J_k(t) <= J_min(t)"; we read J_ave
//    (DepositRule::BelowAverage: the better half deposits), the literal
//    reading is DepositRule::IterationBest. This selection is the "adaptive"
//    part: the deposit threshold follows each iteration's costs; the paper
//    gives no schedule for ρ, so ρ stays 0.7.
//  * Duan 2009 eq. (18): after the update both edge and point pheromone are clamped to
//    [τ_min, τ_max]. Initial pheromone is not given: τ_max, as in MMAS [24].
//  * Candidates (Duan 2009 Sec. 3.3): the best `candidate_count` (4) distinct walks
//    over all iterations feed the ETA.
//  * Replanning (Duan 2009 Sec. 2.5, steps 1-4): add the pop-up threats to the mesh
//    (edge costs recomputed) and plan again from the current node with a fresh
//    pheromone, passing the previous node so the turn constraint holds.
//  * ETA (Duan 2009 eq. (4), Duan 2009 eq. (5), Duan 2009 eq. (6), Duan 2009 eq. (7), Duan 2009 eq. (8)): S_i is the
//  union of the candidates' intervals, S the
//    intersection; T_a = min S (Duan 2009 Fig. 6), or optionally the T in S minimising
//    Duan 2009 eq. (8) = Σ_i (f1·J_i + f2·T) with each UAV's cheapest feasible candidate
//    (Duan 2009 eq. (8) sums over j too, which we read as the candidate actually flown).
//    Only interval lower bounds can be optimal, so only they are tried.
//  * Not the paper: DuanPlanner::LineOfSight (policy name "duan_los") shortcuts
//    each ant's walk before it is offered as a candidate; the colony's
//    pheromone (deposits on the walk's edges and nodes, costs of the walk) is
//    left as the paper's. See line_of_sight_shortcut below.
//  * Not the paper: DuanPlanner::SafeLineOfSight (planner "safe_line_of_sight")
//    does the same but takes a shortcut only if it does not raise the Duan 2009
//    Duan 2009 eq. (1) exposure either. See safe_line_of_sight_shortcut below.
#include "pheromesh/duan/aco.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <string>
#include <utility>

namespace pheromesh::core {

namespace {

constexpr std::array<int32_t, ThreatMesh::kDirections> kDx{1, 1, 0, -1, -1, -1, 0, 1};
constexpr std::array<int32_t, ThreatMesh::kDirections> kDy{0, 1, 1, 1, 0, -1, -1, -1};
constexpr std::array<double, 5> kSampleFractions{0.1, 0.3, 0.5, 0.7, 0.9};  // Duan 2009 eq. (2)
constexpr double kTurnTolerance = 1e-9;   // [rad]
constexpr double kMinEdgeCost = 1e-12;    // keeps η of Duan 2009 eq. (9) finite (f = 1, no threat)
constexpr double kTimeTolerance = 1e-9;   // relative, for interval membership
constexpr double kCostTolerance = 1e-12;  // relative, for the deposit threshold

double distance_km(PointKm a, PointKm b) { return std::hypot(a.x - b.x, a.y - b.y); }

std::optional<Error> check_spec(const MeshSpec& spec, std::span<const Threat> threats) {
  if (!(spec.width_km > 0.0) || !(spec.height_km > 0.0)) {
    return Error{"duan mesh: width_km and height_km must be > 0"};
  }
  if (spec.sections_x < 1 || spec.sections_y < 1) {
    return Error{"duan mesh: sections_x and sections_y must be >= 1"};
  }
  if ((int64_t{spec.sections_x} + 1) * (int64_t{spec.sections_y} + 1) >= int64_t{kNoNode} / ThreatMesh::kDirections) {
    return Error{"duan mesh: too many nodes"};
  }
  if (!(spec.f >= 0.0 && spec.f <= 1.0)) {
    return Error{"duan mesh: f must be in [0, 1]"};
  }
  for (std::size_t k = 0; k < threats.size(); ++k) {
    if (!(threats[k].radius_km > 0.0) || !(threats[k].grade >= 0.0)) {
      return Error{"duan mesh: threat " + std::to_string(k) + " needs radius_km > 0 and grade >= 0"};
    }
  }
  return std::nullopt;
}

}  // namespace

// ----------------------------------------------------------------- threats

double threat_intensity(std::span<const Threat> threats, PointKm p) {
  double sum = 0.0;
  for (const Threat& t : threats) {
    const double d = distance_km(p, t.centre);
    if (d <= t.radius_km) {
      const double d2 = std::max(d, kMinThreatDistanceKm) * std::max(d, kMinThreatDistanceKm);
      sum += t.grade / (d2 * d2);
    }
  }
  return sum;
}

double edge_threat_cost(std::span<const Threat> threats, PointKm a, PointKm b) {
  double sum = 0.0;
  for (const double s : kSampleFractions) {
    sum += threat_intensity(threats, PointKm{a.x + s * (b.x - a.x), a.y + s * (b.y - a.y)});
  }
  return distance_km(a, b) * sum;  // Duan 2009 eq. (2)
}

double edge_cost(double threat_cost, double length_km, double f) {
  return f * threat_cost + (1.0 - f) * length_km;  // Duan 2009 eq. (3)
}

// --------------------------------------------------- line-of-sight shortcut

double segment_threat_cost(std::span<const Threat> threats, PointKm a, PointKm b, double max_piece_km) {
  const double length = distance_km(a, b);
  const double pieces = std::max(1.0, std::ceil(length / max_piece_km - 1e-9));
  double sum = 0.0;
  for (double k = 0.0; k < pieces; k += 1.0) {
    const double s0 = k / pieces, s1 = (k + 1.0) / pieces;
    sum += edge_threat_cost(threats, PointKm{a.x + s0 * (b.x - a.x), a.y + s0 * (b.y - a.y)},
                            PointKm{a.x + s1 * (b.x - a.x), a.y + s1 * (b.y - a.y)});  // Duan 2009 eq. (2) per piece
  }
  return sum;
}

ThreatMesh::PathCost polyline_cost(const ThreatMesh& mesh, std::span<const NodeId> nodes) {
  ThreatMesh::PathCost c;
  const double piece = std::min(mesh.step_x_km(), mesh.step_y_km());
  for (std::size_t i = 1; i < nodes.size(); ++i) {
    const int d = mesh.direction(nodes[i - 1], nodes[i]);
    double length = 0.0, threat = 0.0;
    if (d >= 0) {
      length = mesh.edge_length_km(nodes[i - 1], d);
      threat = mesh.edge_threat_cost(nodes[i - 1], d);
    } else {
      length = distance_km(mesh.position(nodes[i - 1]), mesh.position(nodes[i]));
      threat = segment_threat_cost(mesh.threats(), mesh.position(nodes[i - 1]), mesh.position(nodes[i]), piece);
    }
    c.length_km += length;
    c.threat += threat;
    c.cost += edge_cost(threat, length, mesh.spec().f);  // Duan 2009 eq. (3)
  }
  return c;
}

namespace {

// Both shortcut planners: `keep_exposure` adds the exposure test of
// safe_line_of_sight_shortcut.
std::vector<NodeId> shortcut_walk(const ThreatMesh& mesh, std::span<const NodeId> walk, std::optional<NodeId> previous,
                                  double max_turn_rad, bool keep_exposure) {
  if (walk.size() < 3) return {walk.begin(), walk.end()};
  const double piece = std::min(mesh.step_x_km(), mesh.step_y_km());
  // prefix[i]: J of the walk from walk[0] to walk[i].
  std::vector<double> prefix(walk.size(), 0.0);
  // exposed[i]: Duan 2009 eq. (1) exposure of the walk from walk[0] to walk[i] (only if keep_exposure).
  std::vector<double> exposed(walk.size(), 0.0);
  for (std::size_t i = 1; i < walk.size(); ++i) {
    prefix[i] = prefix[i - 1] + polyline_cost(mesh, walk.subspan(i - 1, 2)).cost;
    if (keep_exposure) {
      const std::array<PointKm, 2> edge{mesh.position(walk[i - 1]), mesh.position(walk[i])};
      exposed[i] = exposed[i - 1] + threat_exposure(mesh.threats(), edge, kSafeShortcutExposureStepKm);
    }
  }
  auto turn_ok = [&](std::optional<NodeId> a, NodeId b, NodeId c) {
    return !a || *a == b || turn_allowed(mesh.position(*a), mesh.position(b), mesh.position(c), max_turn_rad);
  };
  std::vector<NodeId> out{walk[0]};
  std::size_t i = 0;
  const std::size_t last = walk.size() - 1;
  while (i < last) {
    const std::optional<NodeId> before = out.size() >= 2 ? std::optional<NodeId>(out[out.size() - 2]) : previous;
    std::size_t next = i + 1;  // the walk's own edge: its turns were checked by the ant
    for (std::size_t j = last; j >= i + 2; --j) {
      const PointKm a = mesh.position(walk[i]), b = mesh.position(walk[j]);
      if (!turn_ok(before, walk[i], walk[j])) continue;
      if (j < last && !turn_ok(walk[i], walk[j], walk[j + 1])) continue;
      const double length = distance_km(a, b);
      const double cost = edge_cost(segment_threat_cost(mesh.threats(), a, b, piece), length, mesh.spec().f);
      if (!(cost <= prefix[j] - prefix[i])) continue;
      if (keep_exposure) {
        // Relative slack: a segment that retraces the walk's own edges must
        // not fail on rounding of the two sums.
        const std::array<PointKm, 2> segment{a, b};
        const double exposure = threat_exposure(mesh.threats(), segment, kSafeShortcutExposureStepKm);
        if (exposure > (exposed[j] - exposed[i]) * (1.0 + 1e-12)) continue;
      }
      next = j;
      break;
    }
    out.push_back(walk[next]);
    i = next;
  }
  return out;
}

}  // namespace

std::vector<NodeId> line_of_sight_shortcut(const ThreatMesh& mesh, std::span<const NodeId> walk,
                                           std::optional<NodeId> previous, double max_turn_rad) {
  return shortcut_walk(mesh, walk, previous, max_turn_rad, false);
}

std::vector<NodeId> safe_line_of_sight_shortcut(const ThreatMesh& mesh, std::span<const NodeId> walk,
                                                std::optional<NodeId> previous, double max_turn_rad) {
  return shortcut_walk(mesh, walk, previous, max_turn_rad, true);
}

double threat_exposure(std::span<const Threat> threats, std::span<const PointKm> polyline, double step_km) {
  double sum = 0.0;
  for (std::size_t i = 1; i < polyline.size(); ++i) {
    const PointKm a = polyline[i - 1], b = polyline[i];
    const double length = distance_km(a, b);
    const double pieces = std::max(1.0, std::ceil(length / step_km - 1e-9));
    for (double k = 0.0; k < pieces; k += 1.0) {
      const double s = (k + 0.5) / pieces;  // midpoint of the piece
      sum += threat_intensity(threats, PointKm{a.x + s * (b.x - a.x), a.y + s * (b.y - a.y)}) * length / pieces;
    }
  }
  return sum;  // Duan 2009 eq. (1)
}

// -------------------------------------------------------------------- mesh

Result<ThreatMesh> ThreatMesh::create(const MeshSpec& spec, std::vector<Threat> threats) {
  if (auto err = check_spec(spec, threats)) {
    return *err;
  }
  return ThreatMesh(spec, std::move(threats));
}

ThreatMesh::ThreatMesh(const MeshSpec& spec, std::vector<Threat> threats)
    : spec_(spec), threats_(std::move(threats)) {
  assert(!check_spec(spec_, threats_).has_value());
  step_x_ = spec_.width_km / static_cast<double>(spec_.sections_x);
  step_y_ = spec_.height_km / static_cast<double>(spec_.sections_y);
  const auto count = static_cast<std::size_t>(columns()) * static_cast<std::size_t>(rows());
  positions_.resize(count);
  edges_.resize(count * kDirections);
  for (int32_t y = 0; y < rows(); ++y) {
    for (int32_t x = 0; x < columns(); ++x) {
      positions_[node(x, y)] = PointKm{spec_.origin.x + step_x_ * x, spec_.origin.y + step_y_ * y};
    }
  }
  for (NodeId n = 0; n < count; ++n) {
    for (int d = 0; d < kDirections; ++d) {
      const int32_t x = ix(n) + kDx[static_cast<std::size_t>(d)];
      const int32_t y = iy(n) + kDy[static_cast<std::size_t>(d)];
      Edge& e = edges_[edge_index(n, d)];
      if (x < 0 || y < 0 || x >= columns() || y >= rows()) {
        continue;
      }
      e.to = node(x, y);
      e.length_km = distance_km(positions_[n], positions_[e.to]);
      recompute_edge(n, d);
    }
  }
}

NodeId ThreatMesh::node(int32_t x, int32_t y) const {
  assert(x >= 0 && y >= 0 && x < columns() && y < rows());
  return static_cast<NodeId>(y) * static_cast<NodeId>(columns()) + static_cast<NodeId>(x);
}

std::optional<NodeId> ThreatMesh::nearest_node(PointKm p) const {
  const double fx = (p.x - spec_.origin.x) / step_x_;
  const double fy = (p.y - spec_.origin.y) / step_y_;
  constexpr double kEdgeSlack = 1e-9;
  if (fx < -kEdgeSlack || fy < -kEdgeSlack || fx > spec_.sections_x + kEdgeSlack ||
      fy > spec_.sections_y + kEdgeSlack) {
    return std::nullopt;
  }
  const auto x = std::clamp(static_cast<int32_t>(std::lround(fx)), int32_t{0}, spec_.sections_x);
  const auto y = std::clamp(static_cast<int32_t>(std::lround(fy)), int32_t{0}, spec_.sections_y);
  return node(x, y);
}

int ThreatMesh::direction(NodeId a, NodeId b) const {
  for (int d = 0; d < kDirections; ++d) {
    if (edges_[edge_index(a, d)].to == b) {
      return d;
    }
  }
  return -1;
}

void ThreatMesh::recompute_edge(NodeId n, int dir) {
  Edge& e = edges_[edge_index(n, dir)];
  e.threat = core::edge_threat_cost(threats_, positions_[n], positions_[e.to]);
  e.cost = core::edge_cost(e.threat, e.length_km, spec_.f);
}

void ThreatMesh::add_threats(std::span<const Threat> popups) {
  threats_.insert(threats_.end(), popups.begin(), popups.end());
  // Only edges with a sample point in range of a pop-up change (Step 2).
  for (NodeId n = 0; n < node_count(); ++n) {
    for (int d = 0; d < kDirections; ++d) {
      const Edge& e = edges_[edge_index(n, d)];
      if (e.to == kNoNode) {
        continue;
      }
      const bool touched = std::any_of(popups.begin(), popups.end(), [&](const Threat& t) {
        return distance_km(positions_[n], t.centre) <= t.radius_km + e.length_km;
      });
      if (touched) {
        recompute_edge(n, d);
      }
    }
  }
}

ThreatMesh::PathCost ThreatMesh::path_cost(std::span<const NodeId> nodes) const {
  PathCost c;
  for (std::size_t i = 1; i < nodes.size(); ++i) {
    const int d = direction(nodes[i - 1], nodes[i]);
    assert(d >= 0);
    const Edge& e = edges_[edge_index(nodes[i - 1], d)];
    c.length_km += e.length_km;
    c.threat += e.threat;
    c.cost += e.cost;
  }
  return c;
}

double turn_angle_rad(PointKm prev, PointKm cur, PointKm next) {
  const double ax = cur.x - prev.x, ay = cur.y - prev.y;
  const double bx = next.x - cur.x, by = next.y - cur.y;
  return std::abs(std::atan2(ax * by - ay * bx, ax * bx + ay * by));
}

bool turn_allowed(PointKm prev, PointKm cur, PointKm next, double max_turn_rad) {
  return turn_angle_rad(prev, cur, next) <= max_turn_rad + kTurnTolerance;
}

// --------------------------------------------------------------------- ACO

void PointPheromone::add(std::span<const double> tau_p) {
  if (sum.empty()) {
    sum.assign(tau_p.size(), 0.0);
  }
  assert(sum.size() == tau_p.size());
  for (std::size_t i = 0; i < sum.size(); ++i) {
    sum[i] += tau_p[i];
  }
  ++uav_count;
}

double combined_pheromone(double tau_edge, double others_point_sum, uint32_t others_count) {
  if (others_count == 0) {
    return tau_edge;
  }
  return tau_edge * static_cast<double>(others_count) / std::max(others_point_sum, kMinEdgeCost);  // Duan 2009 eq. (10)
}

double heuristic(double edge_cost, double distance_to_target_km) {
  return 1.0 / (std::max(edge_cost, kMinEdgeCost) * distance_to_target_km);  // Duan 2009 eq. (9)
}

std::vector<double> transition_probabilities(std::span<const double> tau, std::span<const double> eta,
                                             double alpha, double beta) {
  assert(tau.size() == eta.size());
  std::vector<double> p(tau.size());
  double sum = 0.0;
  for (std::size_t i = 0; i < tau.size(); ++i) {
    p[i] = std::pow(tau[i], alpha) * std::pow(eta[i], beta);  // Duan 2009 eq. (11) numerator
    sum += p[i];
  }
  for (double& v : p) {
    v = sum > 0.0 ? v / sum : 0.0;
  }
  return p;
}

double updated_pheromone(double tau, double delta, double rho, double tau_min, double tau_max) {
  return std::clamp((1.0 - rho) * tau + delta, tau_min, tau_max);  // Duan 2009 eq. (12)/(13), (18)
}

DuanColony::DuanColony(const ThreatMesh& mesh, const DuanAcoParams& params, Rng rng)
    : mesh_(&mesh), params_(params), rng_(rng) {
  // Turn table for consecutive mesh edges: the geometry is the same at every node.
  const PointKm o{0.0, 0.0};
  for (std::size_t a = 0; a < ThreatMesh::kDirections; ++a) {
    const PointKm prev{-kDx[a] * mesh.step_x_km(), -kDy[a] * mesh.step_y_km()};
    for (std::size_t b = 0; b < ThreatMesh::kDirections; ++b) {
      const PointKm next{kDx[b] * mesh.step_x_km(), kDy[b] * mesh.step_y_km()};
      turn_ok_[a][b] = turn_allowed(prev, o, next, params_.max_turn_rad);
    }
  }
}

void DuanColony::begin(NodeId start, NodeId goal, std::optional<NodeId> previous) {
  const ThreatMesh& mesh = *mesh_;
  start_ = start;
  goal_ = goal;
  previous_ = previous;
  result_ = PathResult{};
  shortcuts_.clear();
  const std::size_t nodes = mesh.node_count();
  tau_edge_.assign(nodes * ThreatMesh::kDirections, params_.tau_initial);
  tau_point_.assign(nodes, params_.tau_point_initial);
  visited_.assign(nodes, 0);
  stamp_ = 0;
  if (start >= nodes || goal >= nodes) {
    eta_beta_.clear();
    return;
  }
  // η^β of Duan 2009 eq. (9) per edge for this goal (recomputed here so pop-up threats count).
  eta_beta_.assign(nodes * ThreatMesh::kDirections, 0.0);
  const PointKm target = mesh.position(goal);
  for (NodeId n = 0; n < nodes; ++n) {
    for (int d = 0; d < ThreatMesh::kDirections; ++d) {
      const NodeId u = mesh.neighbour(n, d);
      if (u == kNoNode || u == goal) {
        continue;  // the goal is taken whenever allowed (η -> ∞)
      }
      eta_beta_[ThreatMesh::edge_index(n, d)] =
          std::pow(heuristic(mesh.edge_cost(n, d), distance_km(mesh.position(u), target)), params_.beta);
    }
  }
}

bool DuanColony::walk(const PointPheromone& others, std::vector<NodeId>& path) {
  const ThreatMesh& mesh = *mesh_;
  if (++stamp_ == 0) {  // wrapped: clear the stamps
    std::fill(visited_.begin(), visited_.end(), 0U);
    stamp_ = 1;
  }
  path.clear();
  path.push_back(start_);
  visited_[start_] = stamp_;
  if (start_ == goal_) {
    return true;
  }
  const bool with_others = others.uav_count > 0 && others.sum.size() == mesh.node_count();
  int incoming = -1;  // direction of the last edge
  std::array<double, ThreatMesh::kDirections> weight{};
  NodeId s = start_;
  while (true) {
    double total = 0.0;
    int goal_dir = -1;
    for (int d = 0; d < ThreatMesh::kDirections; ++d) {
      const auto di = static_cast<std::size_t>(d);
      weight[di] = 0.0;
      const NodeId u = mesh.neighbour(s, d);
      if (u == kNoNode || visited_[u] == stamp_) {
        continue;
      }
      if (incoming >= 0) {
        if (!turn_ok_[static_cast<std::size_t>(incoming)][di]) {
          continue;
        }
      } else if (previous_ && *previous_ != s &&
                 !turn_allowed(mesh.position(*previous_), mesh.position(s), mesh.position(u),
                               params_.max_turn_rad)) {
        continue;
      }
      if (u == goal_) {
        goal_dir = d;
        break;
      }
      const std::size_t e = ThreatMesh::edge_index(s, d);
      const double tau = with_others ? combined_pheromone(tau_edge_[e], others.sum[u], others.uav_count)
                                     : tau_edge_[e];
      weight[di] = std::pow(tau, params_.alpha) * eta_beta_[e];  // Duan 2009 eq. (11)
      total += weight[di];
    }
    NodeId next = kNoNode;
    int dir = -1;
    if (goal_dir >= 0) {
      next = goal_;
      dir = goal_dir;
    } else {
      if (!(total > 0.0)) {
        return false;  // stuck
      }
      double r = rng_.uniform01() * total;
      for (int d = 0; d < ThreatMesh::kDirections; ++d) {
        const double w = weight[static_cast<std::size_t>(d)];
        if (w <= 0.0) {
          continue;
        }
        dir = d;
        if (r < w) {
          break;
        }
        r -= w;
      }
      next = mesh.neighbour(s, dir);
    }
    path.push_back(next);
    visited_[next] = stamp_;
    if (next == goal_) {
      return true;
    }
    incoming = dir;
    s = next;
  }
}

void DuanColony::offer_candidate(const std::vector<NodeId>& path, double cost) {
  auto& cands = result_.candidates;
  const std::size_t k = params_.candidate_count;
  if (k == 0 || (cands.size() >= k && cost >= cands.back().cost)) {
    return;
  }
  if (std::any_of(cands.begin(), cands.end(), [&](const Trajectory& t) { return t.nodes == path; })) {
    return;
  }
  const ThreatMesh::PathCost c = polyline_cost(*mesh_, path);
  Trajectory t{path, c.length_km, c.threat, cost};
  const auto pos = std::upper_bound(cands.begin(), cands.end(), cost,
                                    [](double v, const Trajectory& x) { return v < x.cost; });
  cands.insert(pos, std::move(t));
  if (cands.size() > k) {
    cands.pop_back();
  }
}

const std::vector<NodeId>& DuanColony::shortcut_of(const std::vector<NodeId>& walk) {
  auto it = shortcuts_.find(walk);
  if (it == shortcuts_.end()) {
    it = shortcuts_
             .emplace(walk, params_.planner == DuanPlanner::SafeLineOfSight
                                ? safe_line_of_sight_shortcut(*mesh_, walk, previous_, params_.max_turn_rad)
                                : line_of_sight_shortcut(*mesh_, walk, previous_, params_.max_turn_rad))
             .first;
  }
  return it->second;
}

void DuanColony::iterate(const PointPheromone& others) {
  const ThreatMesh& mesh = *mesh_;
  const double best_so_far = result_.found ? result_.best.cost : std::numeric_limits<double>::infinity();
  if (eta_beta_.empty()) {  // invalid start or goal
    result_.best_cost_history.push_back(best_so_far);
    return;
  }
  std::vector<std::vector<NodeId>> paths(params_.ants);
  std::vector<double> costs(params_.ants, std::numeric_limits<double>::infinity());
  double sum = 0.0, iteration_min = std::numeric_limits<double>::infinity();
  uint32_t arrived = 0;
  for (std::size_t k = 0; k < params_.ants; ++k) {
    if (!walk(others, paths[k])) {
      continue;
    }
    costs[k] = mesh.path_cost(paths[k]).cost;  // J_i,k
    sum += costs[k];
    iteration_min = std::min(iteration_min, costs[k]);
    ++arrived;
  }
  // Duan 2009 eq. (12), Duan 2009 eq. (13): evaporation; Duan 2009 eq. (14), Duan 2009 eq. (15), Duan 2009 eq. (16), Duan 2009 eq. (17): deposits; Duan 2009 eq. (18): clamp.
  for (double& t : tau_edge_) {
    t *= 1.0 - params_.rho;
  }
  for (double& t : tau_point_) {
    t *= 1.0 - params_.rho;
  }
  if (arrived > 0) {
    const double average = sum / arrived;  // J_i,ave(t)
    // Relative slack: when all ants walk the same path, sum / arrived may round
    // below their common cost, and then nobody would deposit.
    const double threshold = (params_.deposit == DepositRule::BelowAverage ? average : iteration_min) *
                             (1.0 + kCostTolerance);
    for (std::size_t k = 0; k < params_.ants; ++k) {
      if (!(costs[k] <= threshold)) {
        continue;
      }
      const double delta = params_.q / std::max(costs[k], kMinEdgeCost);
      const std::vector<NodeId>& p = paths[k];
      for (std::size_t i = 0; i < p.size(); ++i) {
        tau_point_[p[i]] += delta;
        if (i + 1 < p.size()) {
          tau_edge_[ThreatMesh::edge_index(p[i], mesh.direction(p[i], p[i + 1]))] += delta;
        }
      }
    }
  }
  for (double& t : tau_edge_) {
    t = std::clamp(t, params_.tau_min, params_.tau_max);
  }
  for (double& t : tau_point_) {
    t = std::clamp(t, params_.tau_min, params_.tau_max);
  }
  for (std::size_t k = 0; k < params_.ants; ++k) {
    if (!(costs[k] < std::numeric_limits<double>::infinity())) {
      continue;
    }
    if (params_.planner != DuanPlanner::Paper) {
      const std::vector<NodeId>& cut = shortcut_of(paths[k]);
      offer_candidate(cut, polyline_cost(mesh, cut).cost);
    } else {
      offer_candidate(paths[k], costs[k]);
    }
  }
  if (!result_.candidates.empty()) {
    result_.found = true;
    result_.best = result_.candidates.front();
  }
  result_.best_cost_history.push_back(result_.found ? result_.best.cost : best_so_far);
}

PathResult DuanColony::plan(NodeId start, NodeId goal, const PointPheromone& others, std::optional<NodeId> previous) {
  begin(start, goal, previous);
  for (uint32_t t = 0; t < params_.iterations; ++t) {
    iterate(others);
  }
  return result_;
}

std::vector<PathResult> plan_team(std::span<DuanColony> colonies, std::span<const UavTask> tasks,
                                  const std::function<void(uint32_t iteration)>& after_iteration) {
  assert(colonies.size() == tasks.size());
  const std::size_t n = std::min(colonies.size(), tasks.size());
  uint32_t iterations = 0;
  for (std::size_t i = 0; i < n; ++i) {
    colonies[i].begin(tasks[i].start, tasks[i].goal, tasks[i].previous);
    iterations = std::max(iterations, colonies[i].params().iterations);
  }
  std::vector<std::vector<double>> snapshot(n);
  for (uint32_t t = 0; t < iterations; ++t) {
    for (std::size_t i = 0; i < n; ++i) {
      snapshot[i] = colonies[i].point_pheromone();
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (t >= colonies[i].params().iterations) {
        continue;
      }
      PointPheromone others;
      for (std::size_t j = 0; j < n; ++j) {
        if (j != i) {
          others.add(snapshot[j]);
        }
      }
      colonies[i].iterate(others);
    }
    if (after_iteration) after_iteration(t);
  }
  std::vector<PathResult> out;
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    out.push_back(colonies[i].result());
  }
  return out;
}

// --------------------------------------------------------------------- ETA

TimeInterval arrival_interval(double length_km, const SpeedLimits& speeds) {
  const double length_m = 1000.0 * length_km;
  return {length_m / speeds.max_mps, length_m / speeds.min_mps};  // Duan 2009 eq. (4)
}

namespace {

// Sorted union of intervals (Duan 2009 eq. (5)).
std::vector<TimeInterval> merged(std::vector<TimeInterval> v) {
  std::sort(v.begin(), v.end(), [](const TimeInterval& a, const TimeInterval& b) { return a.earliest_s < b.earliest_s; });
  std::vector<TimeInterval> out;
  for (const TimeInterval& i : v) {
    if (!out.empty() && i.earliest_s <= out.back().latest_s) {
      out.back().latest_s = std::max(out.back().latest_s, i.latest_s);
    } else {
      out.push_back(i);
    }
  }
  return out;
}

// Intersection of two sorted unions (Duan 2009 eq. (6)).
std::vector<TimeInterval> intersected(const std::vector<TimeInterval>& a, const std::vector<TimeInterval>& b) {
  std::vector<TimeInterval> out;
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    const double lo = std::max(a[i].earliest_s, b[j].earliest_s);
    const double hi = std::min(a[i].latest_s, b[j].latest_s);
    if (lo <= hi) {
      out.push_back({lo, hi});
    }
    if (a[i].latest_s < b[j].latest_s) {
      ++i;
    } else {
      ++j;
    }
  }
  return out;
}

bool contains(const TimeInterval& i, double t) {
  const double tol = kTimeTolerance * std::max(1.0, std::abs(t));
  return t >= i.earliest_s - tol && t <= i.latest_s + tol;
}

// Cheapest candidate of one UAV that can arrive at t (ties: lower index).
std::optional<std::size_t> cheapest_at(const std::vector<EtaCandidate>& cands, double t, const SpeedLimits& speeds) {
  std::optional<std::size_t> best;
  for (std::size_t j = 0; j < cands.size(); ++j) {
    if (contains(arrival_interval(cands[j].length_km, speeds), t) && (!best || cands[j].cost < cands[*best].cost)) {
      best = j;
    }
  }
  return best;
}

}  // namespace

Result<EtaPlan> coordinate_eta(const std::vector<std::vector<EtaCandidate>>& candidates, const SpeedLimits& speeds,
                               const EtaOptions& options) {
  if (!(speeds.min_mps > 0.0) || !(speeds.max_mps >= speeds.min_mps)) {
    return Error{"duan eta: need 0 < min_mps <= max_mps"};
  }
  if (candidates.empty()) {
    return Error{"duan eta: no UAV"};
  }
  std::vector<TimeInterval> window;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (candidates[i].empty()) {
      return Error{"duan eta: UAV " + std::to_string(i) + " has no candidate trajectory"};
    }
    std::vector<TimeInterval> s_i;
    for (const EtaCandidate& c : candidates[i]) {
      if (!(c.length_km > 0.0)) {
        return Error{"duan eta: UAV " + std::to_string(i) + " has a trajectory of length <= 0"};
      }
      s_i.push_back(arrival_interval(c.length_km, speeds));
    }
    s_i = merged(std::move(s_i));                          // Duan 2009 eq. (5)
    window = i == 0 ? s_i : intersected(window, s_i);      // Duan 2009 eq. (6)
  }
  if (window.empty()) {
    return Error{"duan eta: no common arrival time (S is empty)"};
  }

  // Candidate values of T_a: min S (Duan 2009 Fig. 6) and, for the cost rule, every
  // interval lower bound inside S (Duan 2009 eq. (8) rises with T between them).
  std::vector<double> times{window.front().earliest_s};
  if (options.rule == EtaRule::MinCoordinationCost) {
    for (const auto& cands : candidates) {
      for (const EtaCandidate& c : cands) {
        const double t = arrival_interval(c.length_km, speeds).earliest_s;
        if (std::any_of(window.begin(), window.end(), [&](const TimeInterval& w) { return contains(w, t); })) {
          times.push_back(t);
        }
      }
    }
    std::sort(times.begin(), times.end());
  }

  EtaPlan best;
  double best_cost = std::numeric_limits<double>::infinity();
  for (const double t : times) {
    EtaPlan plan{t, window, {}, {}};
    double total = 0.0;  // Duan 2009 eq. (8)
    bool feasible = true;
    for (const auto& cands : candidates) {
      const auto j = cheapest_at(cands, t, speeds);
      if (!j) {
        feasible = false;
        break;
      }
      plan.chosen.push_back(*j);
      // V = L / T_a, kept inside the limits against rounding at the interval ends.
      plan.speed_mps.push_back(std::clamp(1000.0 * cands[*j].length_km / t, speeds.min_mps, speeds.max_mps));
      total += options.f1 * cands[*j].cost + options.f2 * t;  // Duan 2009 eq. (7)
    }
    if (feasible && total < best_cost) {
      best_cost = total;
      best = std::move(plan);
    }
  }
  if (best.chosen.empty()) {
    return Error{"duan eta: no common arrival time (S is empty)"};
  }
  return best;
}

Result<EtaPlan> coordinate_eta(std::span<const double> lengths_km, const SpeedLimits& speeds) {
  std::vector<std::vector<EtaCandidate>> cands;
  cands.reserve(lengths_km.size());
  for (const double l : lengths_km) {
    cands.push_back({EtaCandidate{l, 0.0}});
  }
  return coordinate_eta(cands, speeds);
}

// ---------------------------------------------------------------- scenario

Duan2009Scenario duan2009_scenario() {
  Duan2009Scenario s;
  s.mesh = MeshSpec{};  // 60 x 70 km, 2 km spacing, f = 0.75
  s.threats = {
      // Duan 2009 Table 1: location [km], threat radius [km], threat grade.
      {{52.0, 32.0}, 10.0, 2.0},
      {{36.0, 26.0}, 6.0, 1.2},
      {{22.0, 48.0}, 8.0, 1.6},
      {{26.0, 56.0}, 12.0, 1.4},
      {{30.0, 30.0}, 9.0, 2.0},
  };
  s.uavs = {
      // Duan 2009 Table 2: starting point -> target [km].
      {{6.0, 20.0}, {10.0, 68.0}},
      {{24.0, 20.0}, {40.0, 60.0}},
      {{40.0, 20.0}, {50.0, 68.0}},
  };
  s.popups = {
      // Duan 2009 Table 4.
      {{12.0, 40.0}, 6.0, 2.5},
      {{40.0, 40.0}, 6.0, 2.0},
  };
  s.speeds = SpeedLimits{200.0, 300.0};
  s.aco = DuanAcoParams{};  // α=3, β=2, ρ=0.7, Q=10, Nc_max=20, m=20, τ ∈ [0.1, 10]
  return s;
}

}  // namespace pheromesh::core
