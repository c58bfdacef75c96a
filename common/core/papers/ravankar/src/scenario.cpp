// scenario.policy.ravankar (Ravankar 2016; docs/policies/ravankar.md).
// The room's entry of the policy table is at the end.
#include <utility>

#include "pheromesh/ravankar/policy.hpp"
#include "scenario/scenario_internal.hpp"

namespace pheromesh::core::scenario_detail {

namespace {

constexpr double kMaxDtS = 60.0;         // [s]
constexpr double kMaxCellSizeM = 100.0;  // [m]
constexpr double kMaxSpeedMps = 10.0;    // [m/s]

// A count that must fit uint32_t and lie in [lo, hi].
bool read_count(Validator& v, const Node& n, const char* field, bool has, int64_t value, int64_t lo, int64_t hi,
                uint32_t& out) {
  if (!has) return true;
  if (!v.int_between(n, field, value, lo, hi)) return false;
  out = static_cast<uint32_t>(value);
  return true;
}

// dt, the cell size, the leaders and their route; whether cell_size_m is valid.
bool read_ravankar_leaders(const pb::RavankarPolicy& msg, const Node& n, Validator& v, const ScenarioConfig& cfg,
                           const std::optional<MapSize>& map, RavankarConfig& c) {
  if (msg.has_dt_s()) c.dt_s = msg.dt_s();
  v.real_in(n, "dt_s", c.dt_s, 0.0, true, kMaxDtS, false);
  if (msg.has_cell_size_m()) c.cell_size_m = msg.cell_size_m();
  const bool cell_ok = v.real_in(n, "cell_size_m", c.cell_size_m, 0.0, true, kMaxCellSizeM, false);
  c.deposit.cell_size_m = c.cell_size_m;

  read_count(v, n, "leaders", msg.has_leaders(), msg.leaders(), 1, cfg.uavs, c.leaders);

  if (msg.route_size() == 0) {
    v.required(n, "route");
  }
  c.route.clear();
  for (int i = 0; i < msg.route_size(); ++i) {
    if (auto cell = check_cell(v, n.child("route", i), msg.route(i), map)) c.route.push_back(*cell);
  }
  if (msg.has_leader_speed_mps()) c.leader_speed_mps = msg.leader_speed_mps();
  v.real_in(n, "leader_speed_mps", c.leader_speed_mps, 0.0, true, kMaxSpeedMps, false);
  return cell_ok;
}

// Whether max_deposit is valid.
bool read_ravankar_deposit(const pb::RavankarPolicy& msg, const Node& n, Validator& v, bool cell_ok,
                           RavankarConfig& c) {
  // Deposit, Ravankar 2016 eq. (12), Ravankar 2016 eq. (13), Ravankar 2016 eq. (14).
  RavankarDepositParams& d = c.deposit;
  if (msg.has_tau()) d.tau = msg.tau();
  v.real_in(n, "tau", d.tau, 0.0, true, kInf, false);
  if (msg.has_max_deposit()) d.max_deposit = msg.max_deposit();
  const bool cap_ok = v.real_in(n, "max_deposit", d.max_deposit, 0.0, true, kInf, false);
  if (msg.has_sensor_range_m()) d.sensor_range_m = msg.sensor_range_m();
  if (cell_ok) v.real_in(n, "sensor_range_m", d.sensor_range_m, 0.0, true, kMaxSensorRadius * c.cell_size_m, false);
  if (msg.has_axes()) {
    if (msg.axes() == "eigenvalue") {
      d.axes = RavankarAxes::Eigenvalue;
    } else if (msg.axes() == "stddev") {
      d.axes = RavankarAxes::StdDev;
    } else {
      v.fail(n, "axes", "must be \"eigenvalue\" or \"stddev\" (got \"" + msg.axes() + "\")");
    }
  }
  if (msg.has_spread()) {
    if (msg.spread() == "peak") {
      d.spread = RavankarSpread::Peak;
    } else if (msg.spread() == "total") {
      d.spread = RavankarSpread::Total;
    } else {
      v.fail(n, "spread", "must be \"peak\" or \"total\" (got \"" + msg.spread() + "\")");
    }
  }
  return cap_ok;
}

void read_ravankar_evaporation_and_followers(const pb::RavankarPolicy& msg, const Node& n, Validator& v, bool cap_ok,
                                             RavankarConfig& c) {
  const RavankarDepositParams& d = c.deposit;
  // Evaporation, Ravankar 2016 eq. (17), Ravankar 2016 eq. (18), Ravankar 2016 eq. (19), Ravankar 2016 eq. (20), Ravankar 2016 eq. (21), Ravankar 2016 eq. (22).
  if (msg.has_k_per_s()) c.evaporation.k_per_s = msg.k_per_s();
  v.real_in(n, "k_per_s", c.evaporation.k_per_s, 0.0, false, kInf, false);
  if (msg.has_ambient()) c.evaporation.ambient = msg.ambient();
  v.real_in(n, "ambient", c.evaporation.ambient, 0.0, false, kInf, false);

  // Followers, Ravankar 2016 eq. (24) and Ravankar 2016 Table 2.
  c.follower.reference_deposit = msg.has_reference_deposit() ? msg.reference_deposit() : d.max_deposit;
  if (msg.has_reference_deposit() || cap_ok) {
    v.real_in(n, msg.has_reference_deposit() ? "reference_deposit" : "max_deposit", c.follower.reference_deposit, 0.0,
              true, kInf, false);
  }
  if (msg.has_delta()) c.follower.delta = msg.delta();
  v.real_in(n, "delta", c.follower.delta, 0.0, true, 1.0, false);
}

void read_ravankar_motion(const pb::RavankarPolicy& msg, const Node& n, Validator& v, const std::optional<MapSize>& map,
                          RavankarConfig& c) {
  // Motion, Ravankar 2016 eq. (27), Ravankar 2016 eq. (28), Ravankar 2016 eq. (29), Ravankar 2016 eq. (30), Ravankar 2016 eq. (31), Ravankar 2016 eq. (32), Ravankar 2016 eq. (33), and fixes.
  if (msg.has_wheel_separation_m()) c.motion.wheel_separation_m = msg.wheel_separation_m();
  v.real_in(n, "wheel_separation_m", c.motion.wheel_separation_m, 0.0, true, kInf, false);
  if (msg.has_wheel_noise_m2_per_m()) c.motion.wheel_noise_m2_per_m = msg.wheel_noise_m2_per_m();
  v.real_in(n, "wheel_noise_m2_per_m", c.motion.wheel_noise_m2_per_m, 0.0, false, kInf, false);
  read_count(v, n, "fix_every_ticks", msg.has_fix_every_ticks(), msg.fix_every_ticks(), 0, kMaxU32, c.fix_every_ticks);
  if (msg.has_fix_sigma_m()) c.fix_sigma_m = msg.fix_sigma_m();
  v.real_in(n, "fix_sigma_m", c.fix_sigma_m, 0.0, true, kInf, false);
  c.fix_area.reset();
  if (msg.has_fix_area()) {
    c.fix_area = check_rect(v, n.child("fix_area"), msg.fix_area(), map);
  }
}

// How often the trail is laid, by whom, and what a follower does once it rejects it.
void read_ravankar_trail(const pb::RavankarPolicy& msg, const Node& n, Validator& v, RavankarConfig& c) {
  read_count(v, n, "deposit_every_ticks", msg.has_deposit_every_ticks(), msg.deposit_every_ticks(), 1, kMaxU32,
             c.deposit_every_ticks);
  if (msg.has_followers_deposit()) c.followers_deposit = msg.followers_deposit();
  read_count(v, n, "follower_delay_ticks", msg.has_follower_delay_ticks(), msg.follower_delay_ticks(), 0, kMaxU32,
             c.follower_delay_ticks);
  if (msg.has_explore_speed_mps()) c.explore_speed_mps = msg.explore_speed_mps();
  v.real_in(n, "explore_speed_mps", c.explore_speed_mps, 0.0, true, kMaxSpeedMps, false);
  if (msg.has_reject_explore()) {
    if (msg.reject_explore() == "onward") {
      c.reject_explore = RavankarConfig::RejectExplore::Onward;
    } else if (msg.reject_explore() == "retreat") {
      c.reject_explore = RavankarConfig::RejectExplore::Retreat;
    } else {
      v.fail(n, "reject_explore", "must be \"onward\" or \"retreat\" (got \"" + msg.reject_explore() + "\")");
    }
  }
}

void build_ravankar(const pb::RavankarPolicy& msg, const Node& n, Validator& v, ScenarioConfig& cfg) {
  RavankarConfig c;
  const std::optional<MapSize> map =
      cfg.width > 0 && cfg.height > 0 ? std::optional<MapSize>(MapSize{cfg.width, cfg.height}) : std::nullopt;
  const bool cell_ok = read_ravankar_leaders(msg, n, v, cfg, map, c);
  const bool cap_ok = read_ravankar_deposit(msg, n, v, cell_ok, c);
  read_ravankar_evaporation_and_followers(msg, n, v, cap_ok, c);
  read_ravankar_motion(msg, n, v, map, c);
  read_ravankar_trail(msg, n, v, c);
  cfg.set_policy_config(std::move(c));
}

}  // namespace

}  // namespace pheromesh::core::scenario_detail

namespace pheromesh::core {

constinit const PolicyEntry kRavankarPolicy{
    .name = RavankarConfig::kPolicy,
    .parse = &scenario_detail::parse_as<scenario_detail::pb::RavankarPolicy, &scenario_detail::build_ravankar>,
    .parse_scenario_fields = nullptr,
    .traits = &ravankar_traits,
    .broadcasts = false,
    .make_uav = &make_ravankar_uav,
    .make_place = &make_ravankar_place,
    .field_summary = &ravankar_field_summary,
};

}  // namespace pheromesh::core
