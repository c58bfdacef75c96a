// The Duan 2009 policy: Max-Min adaptive ACO coordinated trajectory
// (re)planning, distributed (docs/policies/duan.md).
//
//  * UAV side: each UAV process owns a copy of the threat mesh (the map cells
//    are the mesh nodes) and its own DuanColony. A planning phase is Nc_max
//    ticks, one ACO iteration per tick (plan_team's lockstep, Duan 2009 Fig. 12): before
//    iteration t it reads Σ_j τ^p_j (after iteration t-1 of every UAV) from
//    the place agents' "point_sum" layer, subtracts its own share to get
//    Σ_{j≠i} τ^p_j of Duan 2009 eq. (10), iterates, and sends its new point pheromone to
//    the place agents (PointClear to the regions it set last time, then
//    PointSet per node above τ_min). After the last iteration it broadcasts
//    its candidates' arrival intervals (Duan 2009 eq. (4)); at the next tick every UAV
//    runs coordinate_eta on the same broadcasts (Duan 2009 eq. (5), Duan 2009 eq. (6), T_a = min S,
//    Duan 2009 Fig. 6) and flies its cheapest feasible candidate at V = L / T_a.
//  * Pop-up threats (Duan 2009 Table 4) are announced to every UAV at their tick (Duan 2009 Sec. 4:
//    "detected by marching multi-UAVs ... shared immediately"); every UAV
//    still on its way replans (Duan 2009 Sec. 2.5 cause (2)) from the next node of its
//    trajectory (Step 3), flying on to it meanwhile, and the ETA is agreed again.
//  * Place side: "point_sum" (Σ over the swarm, absent = τ_min), "threat"
//    (display) and four report layers the UAVs write at their target node
//    (first agreed T_a and length, arrival time, distance flown). No diffusion.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <string>

#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/rng.hpp"
#include "pheromesh/duan/policy.hpp"

namespace pheromesh::core {

namespace duan_detail {

const char* layer_name(int layer) {
  switch (layer) {
    case kPointSum: return "point_sum";
    case kThreat: return "threat";
    case kEtaS: return "eta_s";
    case kPlannedKm: return "planned_km";
    case kArrivalS: return "arrival_s";
    case kFlownKm: return "flown_km";
    default: return "?";
  }
}

double others_point_sum(float published_sum, double own_tau, double tau_min) {
  const double own = own_tau == tau_min ? tau_min : static_cast<double>(static_cast<float>(own_tau));
  return std::max(0.0, static_cast<double>(published_sum) - own);
}

std::vector<double> eta_broadcast(uint32_t phase, const std::vector<double>& lengths_km, const SpeedLimits& speeds) {
  std::vector<double> v{static_cast<double>(phase)};
  for (const double l : lengths_km) {
    const TimeInterval t = arrival_interval(l, speeds);  // Duan 2009 eq. (4)
    v.push_back(t.earliest_s);
    v.push_back(t.latest_s);
  }
  return v;
}

std::optional<EtaDecision> decide_eta(const std::map<uint32_t, std::vector<double>>& intervals, uint32_t self,
                                      const std::vector<double>& own_lengths_km, const SpeedLimits& speeds) {
  if (own_lengths_km.empty()) return std::nullopt;
  // The candidates as every UAV sees them: lengths from the broadcast T_min
  // (own included), so every UAV computes T_a from the same numbers.
  std::vector<std::vector<EtaCandidate>> cands;
  std::optional<std::size_t> self_index;
  double fallback = 0.0;  // max_i min_j T_min,ij
  for (const auto& [uav, v] : intervals) {
    if (v.size() < 2) continue;
    if (uav == self) self_index = cands.size();
    std::vector<EtaCandidate> c;
    double earliest = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k + 1 < v.size(); k += 2) {
      c.push_back({v[k] * speeds.max_mps / 1000.0, 0.0});  // all costs 0: the lowest feasible index = the cheapest
      earliest = std::min(earliest, v[k]);
    }
    fallback = std::max(fallback, earliest);
    cands.push_back(std::move(c));
  }
  EtaDecision d;
  const auto plan = cands.empty() ? Result<EtaPlan>(Error{"no intervals"}) : coordinate_eta(cands, speeds);
  if (plan.ok() && self_index) {
    d.agreed = true;
    d.eta_s = plan->eta_s;
    d.chosen = plan->chosen[*self_index];
  } else {
    // S is empty (or this UAV's own broadcast is missing): the earliest time
    // every UAV can make; each flies its cheapest candidate that fits, else its best.
    d.eta_s = self_index ? fallback : arrival_interval(own_lengths_km.front(), speeds).earliest_s;
    d.chosen = 0;
    for (std::size_t j = 0; j < own_lengths_km.size(); ++j) {
      const TimeInterval t = arrival_interval(own_lengths_km[j], speeds);
      if (d.eta_s >= t.earliest_s * (1.0 - 1e-9) && d.eta_s <= t.latest_s * (1.0 + 1e-9)) {
        d.chosen = j;
        break;
      }
    }
  }
  if (d.chosen >= own_lengths_km.size()) d.chosen = 0;
  d.speed_mps = std::clamp(1000.0 * own_lengths_km[d.chosen] / d.eta_s, speeds.min_mps, speeds.max_mps);
  return d;
}

double node_threat(std::span<const Threat> threats, int32_t x, int32_t y, int32_t columns, int32_t rows,
                   double spacing_km) {
  double sum = 0.0;
  int count = 0;
  const PointKm p{x * spacing_km, y * spacing_km};
  for (int32_t dy = -1; dy <= 1; ++dy) {
    for (int32_t dx = -1; dx <= 1; ++dx) {
      if ((dx == 0 && dy == 0) || x + dx < 0 || y + dy < 0 || x + dx >= columns || y + dy >= rows) continue;
      sum += edge_threat_cost(threats, p, PointKm{(x + dx) * spacing_km, (y + dy) * spacing_km});  // Duan 2009 eq. (2)
      ++count;
    }
  }
  return count > 0 ? sum / count : 0.0;
}

}  // namespace duan_detail

namespace {

using namespace duan_detail;

MeshSpec mesh_spec(const ScenarioConfig& s) {
  MeshSpec m;
  m.origin = {0.0, 0.0};
  m.sections_x = s.width - 1;
  m.sections_y = s.height - 1;
  const DuanConfig& c = s.config_of<DuanConfig>();
  m.width_km = m.sections_x * c.node_spacing_km;
  m.height_km = m.sections_y * c.node_spacing_km;
  m.f = c.f;
  return m;
}

struct Point {
  double x = 0.0, y = 0.0;  // [cell]
};

class DuanUav final : public UavPolicy {
 public:
  DuanUav(const ScenarioConfig& s, const MapGeometry& geo, uint32_t id)
      : cfg_(&s.config_of<DuanConfig>()),
        geo_(&geo),
        id_(id),
        n_(s.uavs),
        mesh_(std::make_unique<ThreatMesh>(mesh_spec(s), s.config_of<DuanConfig>().threats)),
        colony_(std::make_unique<DuanColony>(*mesh_, s.config_of<DuanConfig>().aco, Rng(stream_seed(s.seed, "duan-uav", id)))) {
    const DuanMission m = id < cfg_->uavs.size() ? cfg_->uavs[id] : DuanMission{};
    start_ = node_of(m.start);
    goal_ = node_of(m.target);
    pos_ = {static_cast<double>(m.start.x), static_cast<double>(m.start.y)};
    last_node_ = start_;
    // Tick 0 runs the first iteration of the first planning phase.
    if (start_ == goal_) {
      mode_ = Mode::Arrived;
    } else {
      begin_phase(0, start_, std::nullopt);
    }
  }

  void step(const UavView& view, UavActions& out) override {
    for (const BroadcastMsg& b : view.broadcasts) {
      if (b.kind != static_cast<uint8_t>(BroadcastKind::EtaIntervals) || b.values.empty()) continue;
      if (b.values[0] != static_cast<double>(phase_) || b.uav >= n_) continue;
      eta_inbox_[b.uav].assign(b.values.begin() + 1, b.values.end());
    }
    Point moved{0.0, 0.0};
    if (view.tick > 0) moved = fly(out);
    announce_popups(view.tick, out);
    if (mode_ == Mode::AwaitEta &&
        (eta_inbox_.size() >= n_ || view.tick >= phase_tick_ + cfg_->aco.iterations + cfg_->eta_wait_ticks)) {
      coordinate(out);
    }
    if (mode_ == Mode::Planning) {
      plan_iteration(view, out);
    } else if (bystander_broadcast_tick_ && *bystander_broadcast_tick_ == view.tick) {
      // Not replanning: tell the others there is nothing to wait for.
      BroadcastMsg b;
      b.kind = static_cast<uint8_t>(BroadcastKind::EtaIntervals);
      b.values = {static_cast<double>(phase_)};
      out.broadcast = std::move(b);
      bystander_broadcast_tick_.reset();
    }
    out.state.x = pos_.x;
    out.state.y = pos_.y;
    out.state.vx = moved.x;
    out.state.vy = moved.y;
    heading_ = heading_of_velocity(moved.x, moved.y, heading_);
    out.state.heading = heading_;
    out.state.role = static_cast<uint8_t>(Role::Searcher);
  }

  [[nodiscard]] Cell cell() const override {
    return {std::clamp(static_cast<int32_t>(std::lround(pos_.x)), 0, geo_->width() - 1),
            std::clamp(static_cast<int32_t>(std::lround(pos_.y)), 0, geo_->height() - 1)};
  }

 private:
  enum class Mode : uint8_t { Planning, AwaitEta, Flying, Arrived, Stuck };

  [[nodiscard]] NodeId node_of(Cell c) const { return mesh_->node(c.x, c.y); }
  [[nodiscard]] Cell cell_of(NodeId n) const { return {mesh_->ix(n), mesh_->iy(n)}; }
  [[nodiscard]] Point point_of(NodeId n) const {
    return {static_cast<double>(mesh_->ix(n)), static_cast<double>(mesh_->iy(n))};
  }

  // Starts planning phase `phase_ + 1` from `from` (previous node `prev` for
  // the turn limit). Iteration 0 runs in this tick.
  void begin_phase(uint32_t tick, NodeId from, std::optional<NodeId> prev) {
    ++phase_;
    phase_tick_ = tick;
    eta_inbox_.clear();
    plan_from_ = from;
    colony_->begin(from, goal_, prev);
    iteration_ = 0;
    mode_ = Mode::Planning;
  }

  // Moves dt_s along the waypoints at the current speed; returns the step [cell].
  Point fly(UavActions& out) {
    if (waypoints_.empty()) {
      if (took_off_ && mode_ != Mode::Arrived) clock_s_ += cfg_->dt_s;  // holding at the replanning node
      return {0.0, 0.0};
    }
    const Point before = pos_;
    const double cells_per_s = speed_mps_ / (1000.0 * cfg_->node_spacing_km);
    double budget_s = cfg_->dt_s;
    while (budget_s > 0.0 && !waypoints_.empty()) {
      const Point w = point_of(waypoints_.front());
      const double dist = std::hypot(w.x - pos_.x, w.y - pos_.y);  // [cell]
      const double need_s = dist / cells_per_s;
      if (need_s <= budget_s) {
        pos_ = w;
        budget_s -= need_s;
        clock_s_ += need_s;
        flown_km_ += dist * cfg_->node_spacing_km;
        last_node_ = waypoints_.front();
        waypoints_.erase(waypoints_.begin());
        if (last_node_ == goal_ && waypoints_.empty()) {
          arrive(out);
          return {pos_.x - before.x, pos_.y - before.y};
        }
      } else {
        const double frac = budget_s * cells_per_s / dist;
        pos_ = {pos_.x + frac * (w.x - pos_.x), pos_.y + frac * (w.y - pos_.y)};
        flown_km_ += budget_s * cells_per_s * cfg_->node_spacing_km;
        clock_s_ += budget_s;
        budget_s = 0.0;
      }
    }
    if (budget_s > 0.0 && took_off_) clock_s_ += budget_s;  // reached the replanning node: hold
    return {pos_.x - before.x, pos_.y - before.y};
  }

  void arrive(UavActions& out) {
    mode_ = Mode::Arrived;
    report(kArrivalS, clock_s_, out);
    report(kFlownKm, flown_km_, out);
  }

  // A report to the place agent at the target node (LayerAdd; the place keeps the maximum).
  void report(int layer, double value, UavActions& out) const {
    out.deposits.push_back(layer_add(*geo_, layer, cell_of(goal_), value));
  }

  // Duan 2009 Table 4 pop-ups of this tick: every UAV learns them (Duan 2009 Sec. 4) and the team replans (Duan 2009 Sec. 2.5).
  void announce_popups(uint32_t tick, UavActions& out) {
    std::vector<Threat> now;
    for (const DuanPopup& p : cfg_->popups) {
      if (p.appear_tick == tick) now.push_back(p.threat);
    }
    if (now.empty()) return;
    mesh_->add_threats(now);  // Step 2: edge costs under the pop-ups
    clear_point_pheromone(out);
    bystander_broadcast_tick_.reset();
    switch (mode_) {
      case Mode::Planning:
      case Mode::AwaitEta:
      case Mode::Stuck:
        // Not flying yet (or no plan): plan again from the same node.
        begin_phase(tick, plan_from_, prev_for_plan_);
        return;
      case Mode::Flying:
        if (!waypoints_.empty() && mesh_->direction(last_node_, waypoints_.front()) < 0 &&
            last_node_ != waypoints_.front()) {
          // A line-of-sight segment (planners "line_of_sight", "safe_line_of_sight"): the neighbouring
          // node of Step 3 is the mesh node nearest to the point one node
          // spacing ahead on the segment (not past its end), as in duan_table3.
          const Point w = point_of(waypoints_.front());
          const double left = std::hypot(w.x - pos_.x, w.y - pos_.y);  // [cell]
          const double ahead = std::min(1.0, left) / std::max(left, 1e-12);
          const Cell c{static_cast<int32_t>(std::lround(pos_.x + ahead * (w.x - pos_.x))),
                       static_cast<int32_t>(std::lround(pos_.y + ahead * (w.y - pos_.y)))};
          const NodeId r = node_of({std::clamp(c.x, 0, geo_->width() - 1), std::clamp(c.y, 0, geo_->height() - 1)});
          if (r != goal_) waypoints_.insert(waypoints_.begin(), r);
        }
        if (!waypoints_.empty() && waypoints_.front() != goal_) {
          // Step 3: fly on to the next node of the trajectory and replan from there.
          const NodeId next = waypoints_.front();
          const NodeId prev = last_node_ != next ? last_node_ : kNoNode;
          waypoints_.assign(1, next);
          prev_for_plan_ = prev == kNoNode ? std::nullopt : std::optional<NodeId>(prev);
          begin_phase(tick, next, prev_for_plan_);
          return;
        }
        break;
      case Mode::Arrived:
        break;
    }
    // Arrived, or the next node is the target: keep going, take no part.
    ++phase_;
    phase_tick_ = tick;
    eta_inbox_.clear();
    bystander_broadcast_tick_ = tick + cfg_->aco.iterations - 1;
  }

  void clear_point_pheromone(UavActions& out) {
    for (const RegionId r : point_regions_) {
      DepositMsg d;
      d.region = r;
      d.kind = static_cast<uint8_t>(DepositKind::PointClear);
      const Rect rr = geo_->region_rect(r);
      d.cell = {rr.x0, rr.y0};
      out.deposits.push_back(d);
    }
    point_regions_.clear();
  }

  // Σ_{j≠i} τ^p_j of Duan 2009 eq. (10) for the coming iteration.
  void read_others(const UavView& view) {
    const double tau_min = cfg_->aco.tau_min;
    others_.uav_count = n_ > 0 ? n_ - 1 : 0;
    if (others_.uav_count == 0) {
      others_.sum.clear();
      return;
    }
    const std::size_t nodes = mesh_->node_count();
    // Iteration 0: every colony has just been initialised to τ_p = τ_min
    // (plan_team's first snapshot), whatever the tiles still hold.
    const double fresh = static_cast<double>(others_.uav_count) * cfg_->aco.tau_point_initial;
    others_.sum.assign(nodes, fresh);
    if (iteration_ == 0) return;
    const std::vector<double>& own = colony_->point_pheromone();
    for (NodeId u = 0; u < nodes; ++u) {
      const auto v = view.tiles->value(kPointSum, cell_of(u));
      if (v) others_.sum[u] = others_point_sum(*v, own[u], tau_min);
    }
  }

  void plan_iteration(const UavView& view, UavActions& out) {
    read_others(view);
    colony_->iterate(others_);  // Duan 2009 eq. (9), Duan 2009 eq. (10), Duan 2009 eq. (11), Duan 2009 eq. (12), Duan 2009 eq. (13), Duan 2009 eq. (14), Duan 2009 eq. (15), Duan 2009 eq. (16), Duan 2009 eq. (17), Duan 2009 eq. (18)
    ++iteration_;
    // Send the new point pheromone (Duan 2009 Fig. 11: "transmitted to other UAVs").
    clear_point_pheromone(out);
    const std::vector<double>& tau = colony_->point_pheromone();
    std::set<RegionId> regions;
    for (NodeId u = 0; u < tau.size(); ++u) {
      if (tau[u] == cfg_->aco.tau_min) continue;  // the place counts absent values as τ_min
      const Cell c = cell_of(u);
      DepositMsg d;
      d.region = geo_->region_of(c);
      d.kind = static_cast<uint8_t>(DepositKind::PointSet);
      d.cell = c;
      d.amount = static_cast<float>(tau[u]);
      out.deposits.push_back(d);
      regions.insert(d.region);
    }
    point_regions_.assign(regions.begin(), regions.end());
    if (iteration_ < cfg_->aco.iterations) return;
    // Planning ends (Step 7): broadcast the candidates' intervals (Duan 2009 eq. (4)),
    // lengths counted from where the UAV will be when the ETA is agreed.
    const PathResult& r = colony_->result();
    offset_km_ = 0.0;
    if (!waypoints_.empty()) {
      const Point w = point_of(waypoints_.front());
      const double left_km = std::hypot(w.x - pos_.x, w.y - pos_.y) * cfg_->node_spacing_km;
      offset_km_ = std::max(0.0, left_km - speed_mps_ * cfg_->dt_s / 1000.0);
    }
    lengths_km_.clear();
    if (r.found) {
      for (const Trajectory& t : r.candidates) lengths_km_.push_back(offset_km_ + t.length_km);
    }
    BroadcastMsg b;
    b.kind = static_cast<uint8_t>(BroadcastKind::EtaIntervals);
    b.values = eta_broadcast(phase_, lengths_km_, cfg_->speeds);
    out.broadcast = std::move(b);
    mode_ = Mode::AwaitEta;
  }

  // Duan 2009 eq. (5), Duan 2009 eq. (6), Duan 2009 eq. (7), Duan 2009 eq. (8): agree on T_a with the swarm, pick the trajectory and V.
  void coordinate(UavActions& out) {
    const auto d = decide_eta(eta_inbox_, id_, lengths_km_, cfg_->speeds);
    if (!d) {
      mode_ = waypoints_.empty() ? Mode::Stuck : Mode::Flying;  // no trajectory found: stay put
      return;
    }
    const Trajectory& t = colony_->result().candidates[d->chosen];
    // Holding short of the replanning node: it stays the first waypoint.
    std::vector<NodeId> route;
    if (!waypoints_.empty()) route.push_back(waypoints_.front());
    route.insert(route.end(), t.nodes.begin() + 1, t.nodes.end());
    waypoints_ = std::move(route);
    speed_mps_ = d->speed_mps;
    prev_for_plan_.reset();
    if (!took_off_) {
      // Duan 2009 Table 3 quantities of the first agreed plan.
      took_off_ = true;
      report(kEtaS, d->eta_s, out);
      report(kPlannedKm, lengths_km_[d->chosen], out);
    }
    mode_ = Mode::Flying;
  }

  const DuanConfig* cfg_;
  const MapGeometry* geo_;
  uint32_t id_;
  uint32_t n_;
  std::unique_ptr<ThreatMesh> mesh_;  // this UAV's copy; the colony points into it
  std::unique_ptr<DuanColony> colony_;
  NodeId start_ = kNoNode, goal_ = kNoNode;
  Mode mode_ = Mode::Planning;
  uint32_t phase_ = 0;       // planning phases begun (the ETA broadcasts carry it)
  uint32_t phase_tick_ = 0;  // tick of the phase's first iteration
  uint32_t iteration_ = 0;
  NodeId plan_from_ = kNoNode;
  std::optional<NodeId> prev_for_plan_;
  PointPheromone others_;
  std::vector<RegionId> point_regions_;  // regions holding this UAV's PointSet values
  std::map<uint32_t, std::vector<double>> eta_inbox_;  // uav -> intervals of this phase
  std::optional<uint32_t> bystander_broadcast_tick_;
  std::vector<double> lengths_km_;  // candidate lengths incl. the offset [km]
  double offset_km_ = 0.0;
  // Flight.
  Point pos_{};                      // [cell]
  std::vector<NodeId> waypoints_;    // nodes still to reach
  NodeId last_node_ = kNoNode;       // last node reached
  double speed_mps_ = 0.0;
  bool took_off_ = false;
  double clock_s_ = 0.0;   // [s] since take-off (the first agreed ETA)
  double flown_km_ = 0.0;  // [km]
  uint8_t heading_ = 0;

};

class DuanPlace final : public PlaceModel {
 public:
  DuanPlace(const ScenarioConfig& s, const MapGeometry& geo, RegionId region)
      : s_(&s), geo_(&geo), region_(region), rect_(geo.region_rect(region)) {
    const auto cells = static_cast<std::size_t>(rect_.area());
    sum_.assign(cells, 0.0);
    for (auto& l : reports_) l.assign(cells, 0.0F);
    threat_.assign(cells, 0.0F);
    update_threats(std::nullopt);
    recompute_sum();
  }

  std::optional<std::string> apply(const DepositMsg& d, uint32_t /*tick*/,
                                   std::vector<TargetEventMsg>& /*events*/) override {
    switch (static_cast<DepositKind>(d.kind)) {
      case DepositKind::PointClear:
        if (d.uav >= s_->uavs) return "point pheromone from unknown UAV " + std::to_string(d.uav);
        points_.erase(d.uav);
        return std::nullopt;
      case DepositKind::PointSet:
        if (d.uav >= s_->uavs) return "point pheromone from unknown UAV " + std::to_string(d.uav);
        points_[d.uav][index(d.cell)] = d.amount;
        return std::nullopt;
      case DepositKind::LayerAdd: {
        if (d.layer < kEtaS || d.layer >= kDuanLayerCount || !rect_.contains(d.cell)) {
          return "layer " + std::to_string(d.layer) + " takes no reports";
        }
        float& v = reports_[static_cast<std::size_t>(d.layer - kEtaS)][index(d.cell)];
        v = std::max(v, d.amount);
        return std::nullopt;
      }
      default:
        return "deposit kind " + std::to_string(d.kind) + " is not used by the Duan policy";
    }
  }

  HaloRing begin_step(uint32_t tick, std::vector<TargetEventMsg>& /*events*/) override {
    const bool appears = std::any_of(s_->config_of<DuanConfig>().popups.begin(), s_->config_of<DuanConfig>().popups.end(),
                                     [tick](const DuanPopup& p) { return p.appear_tick == tick; });
    if (appears) update_threats(tick);
    return HaloRing{region_, {}, {}};  // no diffusion
  }
  void accept_halo(const Rect& /*neighbour_rect*/, const HaloRing& /*ring*/) override {}
  void finish_step() override { recompute_sum(); }

  [[nodiscard]] float value(int layer, Cell c) const override {
    if (!rect_.contains(c)) return 0.0F;
    const std::size_t i = index(c);
    switch (layer) {
      case kPointSum: return static_cast<float>(sum_[i]);
      case kThreat: return threat_[i];
      case kEtaS:
      case kPlannedKm:
      case kArrivalS:
      case kFlownKm: return reports_[static_cast<std::size_t>(layer - kEtaS)][i];
      default: return 0.0F;
    }
  }

 private:
  [[nodiscard]] std::size_t index(Cell c) const {
    return static_cast<std::size_t>((c.y - rect_.y0) * rect_.w + (c.x - rect_.x0));
  }

  // Σ over the swarm in UAV id order; a UAV without a value counts τ_min.
  void recompute_sum() {
    const double tau_min = s_->config_of<DuanConfig>().aco.tau_min;
    const double base = static_cast<double>(s_->uavs) * tau_min;
    std::fill(sum_.begin(), sum_.end(), base);
    for (const auto& [uav, cells] : points_) {
      for (const auto& [i, v] : cells) sum_[i] += static_cast<double>(v) - tau_min;
    }
  }

  // The threats present at `tick` (all pop-ups up to it; none before tick 0).
  void update_threats(std::optional<uint32_t> tick) {
    std::vector<Threat> threats = s_->config_of<DuanConfig>().threats;
    if (tick) {
      for (const DuanPopup& p : s_->config_of<DuanConfig>().popups) {
        if (p.appear_tick <= *tick) threats.push_back(p.threat);
      }
    }
    for (int32_t y = rect_.y0; y < rect_.y0 + rect_.h; ++y) {
      for (int32_t x = rect_.x0; x < rect_.x0 + rect_.w; ++x) {
        threat_[index({x, y})] = static_cast<float>(
            node_threat(threats, x, y, geo_->width(), geo_->height(), s_->config_of<DuanConfig>().node_spacing_km));
      }
    }
  }

  const ScenarioConfig* s_;
  const MapGeometry* geo_;
  RegionId region_;
  Rect rect_;
  std::map<uint32_t, std::map<std::size_t, float>> points_;  // uav -> cell index -> τ^p
  std::vector<double> sum_;
  std::vector<float> threat_;
  std::array<std::vector<float>, 4> reports_;
};

}  // namespace

PolicyTraits duan_traits(const ScenarioConfig& s) {
  PolicyTraits t;
  for (int l = 0; l < duan_detail::kDuanLayerCount; ++l) t.layers.emplace_back(duan_detail::layer_name(l));
  t.sensor_radius = 1.0;  // [cell] one node: the coverage metric is not a Duan quantity
  // An ant may walk anywhere on the mesh (only the tabu list and the turn
  // limit bound it), and Duan 2009 eq. (10) needs the others' point pheromone wherever
  // it goes: every UAV reads the whole map.
  t.view_radius = static_cast<double>(std::max(s.width, s.height));
  // The others' point pheromone and broadcasts, never their poses: without
  // this every view would carry every UAV of the swarm.
  t.reads_neighbours = false;
  // V_max for one tick on the mesh, twice for margin [node/tick]; UAVs start
  // at their missions' start nodes (Duan 2009 Table 2).
  const DuanConfig& c = s.config_of<DuanConfig>();
  t.max_step = 2.0 * c.speeds.max_mps * c.dt_s / (c.node_spacing_km * 1000.0);
  for (uint32_t i = 0; i < s.uavs; ++i) t.starts.push_back(i < c.uavs.size() ? c.uavs[i].start : Cell{});
  return t;
}

std::unique_ptr<UavPolicy> make_duan_uav(const ScenarioConfig& s, const MapGeometry& geo, const World& /*world*/,
                                         uint32_t id) {
  return std::make_unique<DuanUav>(s, geo, id);
}

std::unique_ptr<PlaceModel> make_duan_place(const ScenarioConfig& s, const MapGeometry& geo, RegionId region) {
  return std::make_unique<DuanPlace>(s, geo, region);
}

std::map<std::string, double> duan_field_summary(const ScenarioConfig& s, const FieldLookup& value) {
  std::map<std::string, double> out;
  double point_max = 0.0;
  for (int32_t y = 0; y < s.height; ++y) {
    for (int32_t x = 0; x < s.width; ++x) point_max = std::max(point_max, static_cast<double>(value(duan_detail::kPointSum, {x, y})));
  }
  out["point_sum_max"] = point_max;
  double first = std::numeric_limits<double>::infinity(), last = 0.0;
  uint32_t arrived = 0;
  for (std::size_t i = 0; i < s.config_of<DuanConfig>().uavs.size(); ++i) {
    const Cell t = s.config_of<DuanConfig>().uavs[i].target;
    const std::string p = "uav" + std::to_string(i + 1) + "_";
    const double eta = value(duan_detail::kEtaS, t);
    const double planned = value(duan_detail::kPlannedKm, t);
    const double arrival = value(duan_detail::kArrivalS, t);
    out[p + "eta_s"] = eta;
    out[p + "planned_km"] = planned;
    out[p + "speed_mps"] = eta > 0.0 ? 1000.0 * planned / eta : 0.0;
    out[p + "arrival_s"] = arrival;
    out[p + "flown_km"] = value(duan_detail::kFlownKm, t);
    if (arrival > 0.0) {
      ++arrived;
      first = std::min(first, arrival);
      last = std::max(last, arrival);
    }
  }
  out["arrived"] = arrived;
  out["arrival_spread_s"] = arrived > 0 ? last - first : 0.0;
  return out;
}

}  // namespace pheromesh::core
