// scenario.policy.duan (Duan 2009 Sec. 4, Duan 2009 Table 1, Duan 2009 Table 2, Duan 2009 Table 3, Duan 2009 Table 4;
// docs/policies/duan.md). The room's entry of the policy table is at the end.
#include <numbers>

#include <utility>

#include "pheromesh/duan/policy.hpp"
#include "scenario/scenario_internal.hpp"

namespace pheromesh::core::scenario_detail {

namespace {

constexpr double kMaxTau = 1e5;             // deposits carry τ as a float amount <= 1e6
constexpr int64_t kMaxIterations = 1000;
constexpr int64_t kMaxAnts = 10000;
constexpr int64_t kMaxEtaWaitTicks = 1000;
// The ETA broadcast holds the phase number and one (T_min, T_max) pair per
// candidate: 1 + 2 · 31 <= 64 values (kMaxBroadcastValues).
constexpr int64_t kMaxCandidates = 31;

// A threat of `threats` (popup = false) or `popups` (popup = true).
std::optional<DuanPopup> build_threat(const pb::DuanPolicy::Threat& t, const Node& n, Validator& v, bool popup,
                                      uint32_t ticks) {
  bool ok = true;
  DuanPopup out;
  if (!t.has_x_km()) {
    v.required(n, "x_km");
    ok = false;
  } else {
    ok = v.real_in(n, "x_km", t.x_km(), -kInf, false, kInf, false) && ok;
  }
  if (!t.has_y_km()) {
    v.required(n, "y_km");
    ok = false;
  } else {
    ok = v.real_in(n, "y_km", t.y_km(), -kInf, false, kInf, false) && ok;
  }
  if (!t.has_radius_km()) {
    v.required(n, "radius_km");
    ok = false;
  } else {
    ok = v.real_in(n, "radius_km", t.radius_km(), 0.0, true, kInf, false) && ok;
  }
  if (t.has_grade()) ok = v.real_in(n, "grade", t.grade(), 0.0, false, kInf, false) && ok;
  if (popup) {
    if (!t.has_appear_tick()) {
      v.required(n, "appear_tick");
      ok = false;
    } else {
      ok = v.int_between(n, "appear_tick", t.appear_tick(), 0, ticks, "a pop-up appears within the run") && ok;
    }
  } else if (t.has_appear_tick()) {
    v.fail(n, "appear_tick", "only pop-up threats (policy.duan.popups) have an appear_tick");
    ok = false;
  }
  if (!ok) return std::nullopt;
  out.threat = Threat{{t.x_km(), t.y_km()}, t.radius_km(), t.has_grade() ? t.grade() : 1.0};
  out.appear_tick = static_cast<uint32_t>(t.appear_tick());
  return out;
}

// The real-valued parameters, and the initial pheromone they imply.
void read_duan_reals(const pb::DuanPolicy& msg, const Node& n, Validator& v, DuanConfig& c) {
  DuanAcoParams& a = c.aco;
  if (msg.has_node_spacing_km()) c.node_spacing_km = msg.node_spacing_km();
  if (msg.has_f()) c.f = msg.f();
  if (msg.has_alpha()) a.alpha = msg.alpha();
  if (msg.has_beta()) a.beta = msg.beta();
  if (msg.has_rho()) a.rho = msg.rho();
  if (msg.has_q()) a.q = msg.q();
  if (msg.has_tau_min()) a.tau_min = msg.tau_min();
  if (msg.has_tau_max()) a.tau_max = msg.tau_max();
  if (msg.has_v_min_mps()) c.speeds.min_mps = msg.v_min_mps();
  if (msg.has_v_max_mps()) c.speeds.max_mps = msg.v_max_mps();
  if (msg.has_dt_s()) c.dt_s = msg.dt_s();
  v.real_in(n, "node_spacing_km", c.node_spacing_km, 0.0, true, kInf, false);
  v.real_in(n, "f", c.f, 0.0, false, 1.0, false);
  v.real_in(n, "alpha", a.alpha, 0.0, false, kInf, false);
  v.real_in(n, "beta", a.beta, 0.0, false, kInf, false);
  v.real_in(n, "rho", a.rho, 0.0, true, 1.0, true);
  v.real_in(n, "q", a.q, 0.0, true, kInf, false);
  if (v.real_in(n, "tau_min", a.tau_min, 0.0, true, kMaxTau, false)) {
    v.real_in(n, "tau_max", a.tau_max, a.tau_min, false, kMaxTau, false);
  }
  // Initial pheromone (not given in the paper): τ_max on the edges (MMAS),
  // τ_min on the nodes (pheromesh/duan/aco.hpp), also when the bounds are changed.
  a.tau_initial = a.tau_max;
  a.tau_point_initial = a.tau_min;
  if (v.real_in(n, "v_min_mps", c.speeds.min_mps, 0.0, true, kInf, false)) {
    v.real_in(n, "v_max_mps", c.speeds.max_mps, c.speeds.min_mps, false, kInf, false);
  }
  v.real_in(n, "dt_s", c.dt_s, 0.0, true, kInf, false);
}

// Iterations, ants, candidates and the ETA wait.
void read_duan_counts(const pb::DuanPolicy& msg, const Node& n, Validator& v, DuanConfig& c) {
  DuanAcoParams& a = c.aco;
  if (msg.has_iterations() && v.int_between(n, "iterations", msg.iterations(), 1, kMaxIterations)) {
    a.iterations = static_cast<uint32_t>(msg.iterations());
  }
  if (msg.has_ants() && v.int_between(n, "ants", msg.ants(), 1, kMaxAnts)) a.ants = static_cast<uint32_t>(msg.ants());
  if (msg.has_candidates() &&
      v.int_between(n, "candidates", msg.candidates(), 1, kMaxCandidates, "the ETA broadcast holds 64 values")) {
    a.candidate_count = static_cast<uint32_t>(msg.candidates());
  }
  if (msg.has_eta_wait_ticks() && v.int_between(n, "eta_wait_ticks", msg.eta_wait_ticks(), 0, kMaxEtaWaitTicks)) {
    c.eta_wait_ticks = static_cast<uint32_t>(msg.eta_wait_ticks());
  }
}

// The turn limit, the deposit rule and the planner.
void read_duan_rules(const pb::DuanPolicy& msg, const Node& n, Validator& v, DuanAcoParams& a) {
  if (msg.has_max_turn_deg()) {
    // Below 45° no diagonal turn is left on the 8-neighbour mesh.
    if (v.real_in(n, "max_turn_deg", msg.max_turn_deg(), 45.0, false, 180.0, false)) {
      a.max_turn_rad = msg.max_turn_deg() * std::numbers::pi / 180.0;
    }
  }
  if (msg.has_deposit_rule()) {
    if (msg.deposit_rule() == "below_average") {
      a.deposit = DepositRule::BelowAverage;
    } else if (msg.deposit_rule() == "iteration_best") {
      a.deposit = DepositRule::IterationBest;
    } else {
      v.fail(n, "deposit_rule", "must be \"below_average\" or \"iteration_best\" (got \"" + msg.deposit_rule() + "\")");
    }
  }

  if (msg.has_planner()) {
    if (msg.planner() == "paper") {
      a.planner = DuanPlanner::Paper;
    } else if (msg.planner() == "line_of_sight") {
      a.planner = DuanPlanner::LineOfSight;
    } else if (msg.planner() == "safe_line_of_sight") {
      a.planner = DuanPlanner::SafeLineOfSight;
    } else {
      v.fail(n, "planner",
             "must be \"paper\", \"line_of_sight\" or \"safe_line_of_sight\" (got \"" + msg.planner() + "\")");
    }
  }
}

// One start and target per UAV.
void read_duan_uavs(const pb::DuanPolicy& msg, const Node& n, Validator& v, const ScenarioConfig& cfg, DuanConfig& c) {
  const std::optional<MapSize> map =
      cfg.width > 0 && cfg.height > 0 ? std::optional<MapSize>(MapSize{cfg.width, cfg.height}) : std::nullopt;
  if (msg.uavs_size() != static_cast<int>(cfg.uavs)) {
    v.fail(n, "uavs", "needs exactly one entry per UAV: swarm.uavs = " + std::to_string(cfg.uavs) + ", got " +
                          std::to_string(msg.uavs_size()));
  }
  for (int i = 0; i < msg.uavs_size(); ++i) {
    const Node un = n.child("uavs", i);
    const pb::DuanPolicy::Uav& u = msg.uavs(i);
    std::optional<Cell> start, target;
    if (!u.has_start()) {
      v.required(un, "start");
    } else {
      start = check_cell(v, un.child("start"), u.start(), map);
    }
    if (!u.has_target()) {
      v.required(un, "target");
    } else {
      target = check_cell(v, un.child("target"), u.target(), map);
    }
    if (start && target) {
      if (*start == *target) v.fail(un, "target", "must differ from start");
      c.uavs.push_back({*start, *target});
    }
  }
}

void build_duan(const pb::DuanPolicy& msg, const Node& n, Validator& v, ScenarioConfig& cfg) {
  DuanConfig c;
  read_duan_reals(msg, n, v, c);
  read_duan_counts(msg, n, v, c);
  read_duan_rules(msg, n, v, c.aco);
  for (int i = 0; i < msg.threats_size(); ++i) {
    if (auto t = build_threat(msg.threats(i), n.child("threats", i), v, false, cfg.ticks))
      c.threats.push_back(t->threat);
  }
  for (int i = 0; i < msg.popups_size(); ++i) {
    if (auto t = build_threat(msg.popups(i), n.child("popups", i), v, true, cfg.ticks)) c.popups.push_back(*t);
  }
  read_duan_uavs(msg, n, v, cfg, c);
  cfg.set_policy_config(std::move(c));
}

}  // namespace

}  // namespace pheromesh::core::scenario_detail

namespace pheromesh::core {

// Its UAVs broadcast their ETA intervals (Duan 2009 eq. (4)).
constinit const PolicyEntry kDuanPolicy{
    .name = DuanConfig::kPolicy,
    .parse = &scenario_detail::parse_as<scenario_detail::pb::DuanPolicy, &scenario_detail::build_duan>,
    .parse_scenario_fields = nullptr,
    .traits = &duan_traits,
    .broadcasts = true,
    .make_uav = &make_duan_uav,
    .make_place = &make_duan_place,
    .field_summary = &duan_field_summary,
};

}  // namespace pheromesh::core
