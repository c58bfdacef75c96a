// scenario.policy.shao_search (Shao 2020 Sec. 4, its baseline and our variant) and
// scenario.policy.shao_navigation (Shao 2020 Sec. 5, Shao 2020 Table 2).
#include <utility>

#include "pheromesh/shao/policy.hpp"
#include "scenario_internal.hpp"

namespace pheromesh::core::scenario_detail {

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

void build_shao_navigation(const pb::ShaoNavigationPolicy& msg, const Node& n, Validator& v, ScenarioConfig& cfg) {
  ShaoNavigationConfig c;
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
  // Readings of Shao 2020 Sec. 5.1.1 the paper leaves open (navigation.hpp).
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
  if (msg.has_hold_ticks() && v.int_between(n, "hold_ticks", msg.hold_ticks(), 0, kMaxU32)) {
    c.hold_ticks = static_cast<uint32_t>(msg.hold_ticks());
  }
  ShaoNavParams& p = c.params;
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
  cfg.set_policy_config(std::move(c));
}

}  // namespace pheromesh::core::scenario_detail
