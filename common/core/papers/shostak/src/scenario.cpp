// scenario.policy.shostak (Shostak 2024 Sec. 2, Shostak 2024 Sec. 3, Shostak 2024 Sec. 4, Shostak 2024 Sec. 5;
// shostak/src/policy.cpp). The room's entry of the policy table is at the end.
#include <numbers>

#include <utility>

#include "pheromesh/shostak/policy.hpp"
#include "scenario/scenario_internal.hpp"

namespace pheromesh::core::scenario_detail {

namespace {
constexpr double kDegToRad = std::numbers::pi / 180.0;

// dt and the layers of Shostak 2024 eq. (1) and Shostak 2024 eq. (2); whether cell_size_m is valid.
bool read_shostak_layers(const pb::ShostakPolicy& msg, const Node& n, Validator& v, ShostakConfig& c) {
  ShostakLayerParams& lp = c.layers;
  if (msg.has_dt_s()) c.dt_s = msg.dt_s();
  if (msg.has_cell_size_m()) lp.cell_size_m = msg.cell_size_m();
  if (msg.has_rho()) lp.evaporation_rate = msg.rho();
  if (msg.has_delta_tau()) lp.explored_increment = msg.delta_tau();
  if (msg.has_deposit_period_s()) lp.deposit_period_s = msg.deposit_period_s();
  if (msg.has_hazard_increment()) lp.hazard_increment = msg.hazard_increment();
  if (msg.has_target_increment()) lp.target_increment = msg.target_increment();
  if (msg.has_explored_max()) lp.explored_max = msg.explored_max();
  if (msg.has_hazard_max()) lp.hazard_max = msg.hazard_max();
  if (msg.has_target_max()) lp.target_max = msg.target_max();
  v.real_in(n, "dt_s", c.dt_s, 0.0, true, 1.0, false);
  const bool cell_ok = v.real_in(n, "cell_size_m", lp.cell_size_m, 0.0, true, 1000.0, false);
  v.real_in(n, "rho", lp.evaporation_rate, 0.0, false, 1.0, true);
  v.real_in(n, "delta_tau", lp.explored_increment, 0.0, false, kInf, false);
  v.real_in(n, "deposit_period_s", lp.deposit_period_s, 0.0, true, 60.0, false);
  v.real_in(n, "hazard_increment", lp.hazard_increment, 0.0, false, kInf, false);
  v.real_in(n, "target_increment", lp.target_increment, 0.0, false, kInf, false);
  v.real_in(n, "explored_max", lp.explored_max, 0.0, true, kInf, false);
  v.real_in(n, "hazard_max", lp.hazard_max, 0.0, true, kInf, false);
  v.real_in(n, "target_max", lp.target_max, 0.0, true, kInf, false);
  return cell_ok;
}

// The waypoint roulette (candidates, step, pitch, α, β, η floor).
void read_shostak_aco(const pb::ShostakPolicy& msg, const Node& n, Validator& v, bool cell_ok, ShostakConfig& c) {
  const ShostakLayerParams& lp = c.layers;
  ShostakAcoParams& aco = c.aco;
  if (msg.has_candidates() && v.int_between(n, "candidates", msg.candidates(), 1, 64)) {
    aco.candidate_count = static_cast<uint32_t>(msg.candidates());
  }
  if (msg.has_step_m()) aco.step_m = msg.step_m();
  double pitch_deg = aco.pitch_max_rad / kDegToRad;
  if (msg.has_pitch_max_deg()) pitch_deg = msg.pitch_max_deg();
  if (msg.has_alpha()) aco.alpha = msg.alpha();
  if (msg.has_beta()) aco.beta = msg.beta();
  if (msg.has_eta_floor()) aco.eta_floor = msg.eta_floor();
  // The tiles a UAV reads reach one cell beyond the candidate ring; keep that
  // within the bound of every sensor / view radius.
  if (v.real_in(n, "step_m", aco.step_m, 0.0, true, kInf, false) && cell_ok &&
      aco.step_m / lp.cell_size_m > kMaxSensorRadius - 1.0) {
    v.fail(n, "step_m", "must be at most " + format_number(kMaxSensorRadius - 1.0) + " cells = " +
                            format_number((kMaxSensorRadius - 1.0) * lp.cell_size_m) + " m (got " +
                            format_number(aco.step_m) + " m)");
  }
  if (v.real_in(n, "pitch_max_deg", pitch_deg, 0.0, false, 90.0, true)) aco.pitch_max_rad = pitch_deg * kDegToRad;
  v.real_in(n, "alpha", aco.alpha, 0.0, false, kInf, false);
  v.real_in(n, "beta", aco.beta, 0.0, false, kInf, false);
  v.real_in(n, "eta_floor", aco.eta_floor, 0.0, false, 1.0, false);
}

// Speed, altitudes, dispersal and the sensors' ranges.
void read_shostak_flight(const pb::ShostakPolicy& msg, const Node& n, Validator& v, bool cell_ok, ShostakConfig& c) {
  const ShostakLayerParams& lp = c.layers;
  if (msg.has_speed_mps()) c.speed_mps = msg.speed_mps();
  if (msg.has_altitude_m()) c.altitude_m = msg.altitude_m();
  if (msg.has_min_altitude_m()) c.min_altitude_m = msg.min_altitude_m();
  if (msg.has_max_altitude_m()) c.max_altitude_m = msg.max_altitude_m();
  if (msg.has_dispersal_m()) c.dispersal_m = msg.dispersal_m();
  if (msg.has_detect_radius_m()) c.detect_radius_m = msg.detect_radius_m();
  if (msg.has_lidar_range_m()) c.lidar_range_m = msg.lidar_range_m();
  v.real_in(n, "speed_mps", c.speed_mps, 0.0, true, 1000.0, false);
  const bool min_ok = v.real_in(n, "min_altitude_m", c.min_altitude_m, 0.0, false, kInf, false);
  const bool max_ok = v.real_in(n, "max_altitude_m", c.max_altitude_m, 0.0, false, kInf, false);
  if (min_ok && max_ok && c.max_altitude_m < c.min_altitude_m) {
    v.fail(n, "max_altitude_m", "must be >= min_altitude_m = " + format_number(c.min_altitude_m) + " (got " +
                                    format_number(c.max_altitude_m) + ")");
  } else if (min_ok && max_ok) {
    v.real_in(n, "altitude_m", c.altitude_m, c.min_altitude_m, false, c.max_altitude_m, false);
  }
  v.real_in(n, "dispersal_m", c.dispersal_m, 0.0, false, kInf, false);
  if (v.real_in(n, "detect_radius_m", c.detect_radius_m, 0.0, true, kInf, false) && cell_ok &&
      c.detect_radius_m / lp.cell_size_m > kMaxSensorRadius) {
    v.fail(n, "detect_radius_m", "must be at most " + format_number(kMaxSensorRadius) + " cells = " +
                                     format_number(kMaxSensorRadius * lp.cell_size_m) + " m (got " +
                                     format_number(c.detect_radius_m) + " m)");
  }
  v.real_in(n, "lidar_range_m", c.lidar_range_m, 0.0, false, kInf, false);
}

// One frame yaw per UAV at most.
void read_shostak_frames(const pb::ShostakPolicy& msg, const Node& n, Validator& v, const ScenarioConfig& cfg,
                         ShostakConfig& c) {
  c.frame_yaw_rad.clear();
  for (int i = 0; i < msg.frame_yaw_deg_size(); ++i) {
    const double yaw = msg.frame_yaw_deg(i);
    if (static_cast<int64_t>(i) >= static_cast<int64_t>(cfg.uavs)) {
      v.fail(n, "frame_yaw_deg", "more entries than swarm.uavs = " + std::to_string(cfg.uavs), i);
      break;
    }
    if (!std::isfinite(yaw) || yaw <= -360.0 || yaw >= 360.0) {
      v.fail(n, "frame_yaw_deg", "must be in (-360, 360) (got " + format_number(yaw) + ")", i);
      continue;
    }
    c.frame_yaw_rad.push_back(yaw * kDegToRad);
  }
}

// The drift of the UAVs' pose and the convergence rule.
void read_shostak_drift_and_converge(const pb::ShostakPolicy& msg, const Node& n, Validator& v, ShostakConfig& c) {
  if (msg.has_position_noise_m2_per_m()) c.drift.position_noise_m2_per_m = msg.position_noise_m2_per_m();
  if (msg.has_yaw_noise_rad2_per_m()) c.drift.yaw_noise_rad2_per_m = msg.yaw_noise_rad2_per_m();
  v.real_in(n, "position_noise_m2_per_m", c.drift.position_noise_m2_per_m, 0.0, false, kInf, false);
  v.real_in(n, "yaw_noise_rad2_per_m", c.drift.yaw_noise_rad2_per_m, 0.0, false, kInf, false);
  if (msg.has_converge()) {
    if (msg.converge() == "roulette") {
      c.converge = ShostakConfig::Converge::Roulette;
    } else if (msg.converge() == "beeline") {
      c.converge = ShostakConfig::Converge::Beeline;
    } else {
      v.fail(n, "converge", "must be \"roulette\" or \"beeline\" (got \"" + msg.converge() + "\")");
    }
  }
}

void build_shostak(const pb::ShostakPolicy& msg, const Node& n, Validator& v, ScenarioConfig& cfg) {
  ShostakConfig c;
  const bool cell_ok = read_shostak_layers(msg, n, v, c);
  read_shostak_aco(msg, n, v, cell_ok, c);
  read_shostak_flight(msg, n, v, cell_ok, c);
  read_shostak_frames(msg, n, v, cfg, c);
  read_shostak_drift_and_converge(msg, n, v, c);
  cfg.set_policy_config(std::move(c));
}

}  // namespace

}  // namespace pheromesh::core::scenario_detail

namespace pheromesh::core {

// A UAV that finds a target broadcasts "target found" (Shostak 2024 Sec. 5).
constinit const PolicyEntry kShostakPolicy{
    .name = ShostakConfig::kPolicy,
    .parse = &scenario_detail::parse_as<scenario_detail::pb::ShostakPolicy, &scenario_detail::build_shostak>,
    .parse_scenario_fields = nullptr,
    .traits = &shostak_traits,
    .broadcasts = true,
    .make_uav = &make_shostak_uav,
    .make_place = &make_shostak_place,
    .field_summary = &shostak_field_summary,
};

}  // namespace pheromesh::core
