// scenario.shao (the layers and ACO parameters both Shao policies read),
// scenario.policy.shao_search (Shao 2020 Sec. 4, its baseline and our variant) and
// scenario.policy.shao_navigation (Shao 2020 Sec. 5, Shao 2020 Table 2); the Shao
// room's two entries of the policy table.
#include <utility>

#include "pheromesh/shao/policy.hpp"
#include "scenario/scenario_internal.hpp"

namespace pheromesh::core::scenario_detail {
namespace {

// scenario.shao, read in every scenario (PolicyEntry::parse_scenario_fields).
void build_shao_fields(const pb::Scenario& msg, const Node& root, Validator& v, ScenarioConfig& cfg) {
  // --- shao.layers: Shao 2020 eq. (1), Shao 2020 eq. (2), Shao 2020 eq. (3), Shao 2020 eq. (4),
  // Shao 2020 eq. (5), Shao 2020 eq. (6), Shao 2020 eq. (7), Shao 2020 eq. (8)
  const Node shn = root.child("shao");
  const Node ln = shn.child("layers");
  const pb::Layers& l = msg.shao().layers();
  ShaoLayerParams& lp = cfg.layers;
  if (l.has_e_tau()) lp.e_tau = l.e_tau();
  if (l.has_g_tau()) lp.g_tau = l.g_tau();
  if (l.has_d_tau()) lp.d_tau = l.d_tau();
  if (l.has_e_eps()) lp.e_eps = l.e_eps();
  if (l.has_g_eps()) lp.g_eps = l.g_eps();
  if (l.has_d_eps()) lp.d_eps = l.d_eps();
  if (l.has_sigma0()) lp.sigma0 = l.sigma0();
  if (l.has_sigma_min()) lp.sigma_min = l.sigma_min();
  if (l.has_d0()) lp.d0 = l.d0();
  if (l.has_q()) lp.q = l.q();
  v.real_in(ln, "e_tau", lp.e_tau, 0.0, false, 1.0, true);
  v.real_in(ln, "g_tau", lp.g_tau, 0.0, false, 1.0, true);
  v.real_in(ln, "d_tau", lp.d_tau, 0.0, false, kInf, false);
  v.real_in(ln, "e_eps", lp.e_eps, 0.0, false, 1.0, true);
  v.real_in(ln, "g_eps", lp.g_eps, 0.0, false, 1.0, true);
  v.real_in(ln, "d_eps", lp.d_eps, 0.0, false, kInf, false);
  // Shao 2020 eq. (8) clamps path pheromone to [σmin, σ0], so the interval must not be empty.
  const bool sigma_min_ok = v.real_in(ln, "sigma_min", lp.sigma_min, 0.0, true, kInf, false);
  const bool sigma0_ok = v.real_in(ln, "sigma0", lp.sigma0, 0.0, true, kInf, false);
  if (sigma_min_ok && sigma0_ok && lp.sigma0 < lp.sigma_min) {
    v.fail(ln, "sigma0",
           "must be >= sigma_min = " + format_number(lp.sigma_min) + " (got " + format_number(lp.sigma0) + ")");
  }
  v.real_in(ln, "d0", lp.d0, 0.0, true, kInf, false);
  v.real_in(ln, "q", lp.q, 0.0, true, kInf, false);

  // --- shao.aco: Shao 2020 eq. (9), Shao 2020 eq. (10), Shao 2020 eq. (11), Shao 2020 Sec. 4.2
  const Node cn = shn.child("aco");
  const pb::Aco& a = msg.shao().aco();
  ShaoAcoParams& ap = cfg.aco;
  if (a.has_alpha()) ap.alpha = a.alpha();
  if (a.has_beta()) ap.beta = a.beta();
  if (a.has_lambda_target()) ap.lambda_target = a.lambda_target();
  if (a.has_lambda_obstacle()) ap.lambda_obstacle = a.lambda_obstacle();
  if (a.has_lambda_path()) ap.lambda_path = a.lambda_path();
  if (a.has_sensor_radius()) ap.sensor_radius = a.sensor_radius();
  if (a.has_random_fraction()) ap.random_fraction = a.random_fraction();
  v.real_in(cn, "alpha", ap.alpha, 0.0, false, kInf, false);
  v.real_in(cn, "beta", ap.beta, 0.0, false, kInf, false);
  v.real_in(cn, "lambda_target", ap.lambda_target, 0.0, false, 1.0, false);
  v.real_in(cn, "lambda_obstacle", ap.lambda_obstacle, -1.0, false, 0.0, false);
  v.real_in(cn, "lambda_path", ap.lambda_path, 0.0, false, 1.0, false);
  v.real_in(cn, "sensor_radius", ap.sensor_radius, 0.0, true, kMaxSensorRadius, false);
  v.real_in(cn, "random_fraction", ap.random_fraction, 0.0, false, 1.0, false);
  if (a.has_revisit_period() && v.int_between(cn, "revisit_period", a.revisit_period(), 1, kMaxU32)) {
    ap.revisit_period = static_cast<uint32_t>(a.revisit_period());
  }
}

void build_shao_search(const pb::ShaoSearchPolicy& msg, const Node& n, Validator& v, ScenarioConfig& cfg) {
  if (!msg.has_search() && !msg.has_mark()) return;  // the paper's pheromone search (no config)
  ShaoSearchConfig c;
  if (msg.has_mark()) {
    if (msg.mark() == "on_arrival") {
      c.mark_on_arrival = true;
    } else if (msg.mark() != "in_range") {
      v.fail(n, "mark", "must be \"in_range\" or \"on_arrival\" (got \"" + msg.mark() + "\")");
    }
  }
  if (!msg.has_search() || msg.search() == "pheromone") {
    c.route = ShaoRoute::Pheromone;
  } else if (msg.search() == "lawnmower_transit") {
    c.route = ShaoRoute::LawnmowerTransit;
  } else if (msg.search() == "frontier") {
    c.route = ShaoRoute::Frontier;
  } else {
    v.fail(n, "search",
           "must be \"pheromone\", \"lawnmower_transit\" or \"frontier\" (got \"" + msg.search() + "\")");
    return;
  }
  cfg.set_policy_config(std::move(c));
}

// The target region and which pheromones the leader reads.
void read_navigation_leader(const pb::ShaoNavigationPolicy& msg, const Node& n, Validator& v, const ScenarioConfig& cfg,
                            ShaoNavigationConfig& c) {
  if (!msg.has_region_centre()) {
    v.required(n, "region_centre");
  } else {
    const std::optional<MapSize> map =
        cfg.width > 0 && cfg.height > 0 ? std::optional<MapSize>(MapSize{cfg.width, cfg.height}) : std::nullopt;
    if (auto cell = check_cell(v, n.child("region_centre"), msg.region_centre(), map)) c.region_centre = *cell;
  }
  if (msg.has_leader_pheromones()) {
    if (msg.leader_pheromones() == "vector") {
      c.leader = LeaderPheromones::Vector;
    } else if (msg.leader_pheromones() == "scalar") {
      c.leader = LeaderPheromones::Scalar;
    } else if (msg.leader_pheromones() == "gradient") {
      c.leader = LeaderPheromones::Gradient;  // our variant (navigation.hpp)
    } else if (msg.leader_pheromones() == "pull") {
      c.leader = LeaderPheromones::Pull;  // our variant (navigation.hpp)
    } else {
      v.fail(n, "leader_pheromones",
             "must be \"vector\", \"scalar\", \"gradient\" or \"pull\" (got \"" + msg.leader_pheromones() + "\")");
    }
  }
}

// Readings of Shao 2020 Sec. 5.1.1 the paper leaves open (navigation.hpp).
void read_navigation_readings(const pb::ShaoNavigationPolicy& msg, const Node& n, Validator& v,
                              ShaoNavigationConfig& c) {
  if (msg.has_vector_choice()) {
    if (msg.vector_choice() == "norm") {
      c.params.vector_choice = VectorSectorChoice::Norm;
    } else if (msg.vector_choice() == "projection") {
      c.params.vector_choice = VectorSectorChoice::Projection;
    } else {
      v.fail(n, "vector_choice", "must be \"norm\" or \"projection\" (got \"" + msg.vector_choice() + "\")");
    }
  }
  if (msg.has_scalar_score()) {
    if (msg.scalar_score() == "mean") {
      c.params.scalar_score = ScalarSectorScore::Mean;
    } else if (msg.scalar_score() == "sum") {
      c.params.scalar_score = ScalarSectorScore::Sum;
    } else if (msg.scalar_score() == "max") {
      c.params.scalar_score = ScalarSectorScore::Max;
    } else {
      v.fail(n, "scalar_score", "must be \"mean\", \"sum\" or \"max\" (got \"" + msg.scalar_score() + "\")");
    }
  }
  if (msg.has_scalar_step()) {
    if (msg.scalar_step() == "rho") {
      c.params.scalar_step = ScalarLeaderStep::Rho;
    } else if (msg.scalar_step() == "lattice") {
      c.params.scalar_step = ScalarLeaderStep::Lattice;
    } else {
      v.fail(n, "scalar_step", "must be \"rho\" or \"lattice\" (got \"" + msg.scalar_step() + "\")");
    }
  }
  if (msg.has_neighbour_gradient()) {
    if (msg.neighbour_gradient() == "towards") {
      c.params.neighbour_gradient = NeighbourGradient::TowardsNeighbour;
    } else if (msg.neighbour_gradient() == "away") {
      c.params.neighbour_gradient = NeighbourGradient::AwayFromNeighbour;
    } else {
      v.fail(n, "neighbour_gradient", "must be \"towards\" or \"away\" (got \"" + msg.neighbour_gradient() + "\")");
    }
  }
}

void read_navigation_params(const pb::ShaoNavigationPolicy& msg, const Node& n, Validator& v, const ScenarioConfig& cfg,
                            ShaoNavParams& p) {
  // The leader weighs the layers with the search's λ (Shao 2020 Table 2 uses
  // the same 1, -0.3, 0.3 as Shao 2020 Table 1).
  p.lambda_target = cfg.aco.lambda_target;
  p.lambda_obstacle = cfg.aco.lambda_obstacle;
  p.lambda_path = cfg.aco.lambda_path;
  if (msg.has_leader_sensor_radius()) p.leader_sensor_radius = msg.leader_sensor_radius();
  if (msg.has_rho()) p.rho = msg.rho();
  if (msg.has_epsilon()) p.epsilon = msg.epsilon();
  if (msg.has_h()) p.h = msg.h();
  if (msg.has_c1()) p.c1 = msg.c1();
  if (msg.has_c2()) p.c2 = msg.c2();
  if (msg.has_follower_range()) p.follower_range = msg.follower_range();
  v.real_in(n, "leader_sensor_radius", p.leader_sensor_radius, 0.0, true, kMaxSensorRadius, false);
  v.real_in(n, "rho", p.rho, 0.0, true, kInf, false);
  v.real_in(n, "epsilon", p.epsilon, 0.0, true, 1.0, true);
  v.real_in(n, "h", p.h, 0.0, true, 1.0, true);
  v.real_in(n, "c1", p.c1, 0.0, false, kInf, false);
  v.real_in(n, "c2", p.c2, 0.0, false, kInf, false);
  v.real_in(n, "follower_range", p.follower_range, 0.0, true, kMaxSensorRadius, false);
}

void build_shao_navigation(const pb::ShaoNavigationPolicy& msg, const Node& n, Validator& v, ScenarioConfig& cfg) {
  ShaoNavigationConfig c;
  read_navigation_leader(msg, n, v, cfg, c);
  read_navigation_readings(msg, n, v, c);
  if (msg.has_hold_ticks() && v.int_between(n, "hold_ticks", msg.hold_ticks(), 0, kMaxU32)) {
    c.hold_ticks = static_cast<uint32_t>(msg.hold_ticks());
  }
  read_navigation_params(msg, n, v, cfg, c.params);
  cfg.set_policy_config(std::move(c));
}

}  // namespace
}  // namespace pheromesh::core::scenario_detail

namespace pheromesh::core {

namespace {
std::unique_ptr<PlaceModel> make_shao_search_place(const ScenarioConfig& s, const MapGeometry& geo, RegionId region) {
  return make_shao_place(s, geo, region, false);
}
}  // namespace

static_assert(ShaoSearchConfig::kPolicy == kDefaultPolicy, "a scenario without `policy` runs the Shao search");

constinit const PolicyEntry kShaoSearchPolicy{
    .name = ShaoSearchConfig::kPolicy,
    .parse = &scenario_detail::parse_as<scenario_detail::pb::ShaoSearchPolicy, &scenario_detail::build_shao_search>,
    .parse_scenario_fields =
        &scenario_detail::parse_as<scenario_detail::pb::Scenario, &scenario_detail::build_shao_fields>,
    .traits = &shao_search_traits,
    .broadcasts = false,
    .make_uav = &make_shao_search_uav,
    .make_place = &make_shao_search_place,
    .field_summary = nullptr,
};

// The leader's state (Shao 2020 Sec. 5) is a broadcast.
constinit const PolicyEntry kShaoNavigationPolicy{
    .name = ShaoNavigationConfig::kPolicy,
    .parse =
        &scenario_detail::parse_as<scenario_detail::pb::ShaoNavigationPolicy, &scenario_detail::build_shao_navigation>,
    .parse_scenario_fields =
        &scenario_detail::parse_as<scenario_detail::pb::Scenario, &scenario_detail::build_shao_fields>,
    .traits = &shao_navigation_traits,
    .broadcasts = true,
    .make_uav = &make_shao_navigation_uav,
    .make_place = &make_shao_navigation_place,
    .field_summary = &shao_navigation_field_summary,
};

}  // namespace pheromesh::core
