// scenario.policy.liu (Liu 2022 ESUSTPM, Liu 2022 Sec. 5 and Liu 2022 Table 1; liu/src/policy.cpp).
// The room's entry of the policy table is at the end.
#include <array>
#include <utility>

#include "pheromesh/liu/policy.hpp"
#include "scenario/scenario_internal.hpp"

namespace pheromesh::core::scenario_detail {

namespace {

// Reads a string enumeration: `choices` pairs the accepted names with values.
template <typename E, std::size_t N>
void read_choice(Validator& v, const Node& n, const char* field, bool has, const std::string& got,
                 const std::array<std::pair<const char*, E>, N>& choices, E& out) {
  if (!has) return;
  std::string names;
  for (const auto& [name, value] : choices) {
    if (got == name) {
      out = value;
      return;
    }
    names += names.empty() ? "" : ", ";
    names += std::string("\"") + name + "\"";
  }
  v.fail(n, field, "must be one of " + names + " (got \"" + got + "\")");
}

// The string enumerations: search, prior, sensor, start velocity and point, miss update.
void read_liu_choices(const pb::LiuPolicy& msg, const Node& n, Validator& v, LiuConfig& c) {
  LiuParams& p = c.params;
  read_choice<LiuPolicy, 6>(v, n, "search", msg.has_search(), msg.search(),
                            {{{"esustpm", LiuPolicy::kEsustpm},
                              {"lawnmower", LiuPolicy::kLawnmower},
                              {"random", LiuPolicy::kRandom},
                              {"boids", LiuPolicy::kBoids},
                              {"guided_boids", LiuPolicy::kGuidedBoids},
                              {"esustpm_disperse", LiuPolicy::kEsustpmDisperse}}},
                            c.search);
  read_choice<LiuPrior, 3>(v, n, "prior", msg.has_prior(), msg.prior(),
                           {{{"uniform", LiuPrior::kUniform}, {"accurate", LiuPrior::kAccurate}, {"wrong", LiuPrior::kWrong}}},
                           c.prior);
  read_choice<LiuSensor, 2>(v, n, "sensor", msg.has_sensor(), msg.sensor(),
                            {{{"noisy", LiuSensor::kNoisy}, {"algorithm1", LiuSensor::kAlgorithm1}}}, c.sensor);
  read_choice<LiuStartVelocity, 2>(
      v, n, "start_velocity", msg.has_start_velocity(), msg.start_velocity(),
      {{{"random_heading", LiuStartVelocity::kRandomHeading}, {"rest", LiuStartVelocity::kRest}}}, c.start_velocity);
  read_choice<LiuStartPoint, 2>(v, n, "start_point", msg.has_start_point(), msg.start_point(),
                                {{{"centre", LiuStartPoint::kCentre}, {"corner", LiuStartPoint::kCorner}}}, c.start_point);
  read_choice<MissUpdate, 2>(v, n, "miss_update", msg.has_miss_update(), msg.miss_update(),
                             {{{"as_printed", MissUpdate::kAsPrinted}, {"bayes", MissUpdate::kBayes}}}, p.miss_update);
  if (msg.has_release_confirmed_cells()) c.release_confirmed_cells = msg.release_confirmed_cells();
}

// Prior.
void read_liu_prior(const pb::LiuPolicy& msg, const Node& n, Validator& v, const ScenarioConfig& cfg, LiuConfig& c) {
  const std::optional<MapSize> map =
      cfg.width > 0 && cfg.height > 0 ? std::optional<MapSize>(MapSize{cfg.width, cfg.height}) : std::nullopt;
  for (int i = 0; i < msg.wrong_prior_cells_size(); ++i) {
    if (auto cell = check_cell(v, n.child("wrong_prior_cells", i), msg.wrong_prior_cells(i), map)) {
      c.wrong_prior_cells.push_back(*cell);
    }
  }
  if (c.prior == LiuPrior::kWrong && msg.wrong_prior_cells_size() == 0) {
    v.fail(n, "wrong_prior_cells", "the \"wrong\" prior needs at least one cell");
  }
  if (msg.has_prior_sigma()) c.prior_sigma_cells = msg.prior_sigma();
  if (msg.has_prior_weight()) c.prior_weight = msg.prior_weight();
  v.real_in(n, "prior_sigma", c.prior_sigma_cells, 0.0, true, kInf, false);
  v.real_in(n, "prior_weight", c.prior_weight, 0.0, false, kInf, false);
}

// Sensor and TPM.
void read_liu_sensor(const pb::LiuPolicy& msg, const Node& n, Validator& v, LiuParams& p) {
  if (msg.has_p_detection()) p.p_detection = msg.p_detection();
  if (msg.has_p_false_alarm()) p.p_false_alarm = msg.p_false_alarm();
  if (msg.has_confirm_threshold()) p.confirm_threshold = msg.confirm_threshold();
  if (msg.has_initial_probability()) p.initial_probability = msg.initial_probability();
  v.real_in(n, "p_detection", p.p_detection, 0.0, false, 1.0, false);
  v.real_in(n, "p_false_alarm", p.p_false_alarm, 0.0, false, 1.0, true);  // Liu 2022 eq. (5) divides by 1 - P_f
  v.real_in(n, "confirm_threshold", p.confirm_threshold, 0.0, true, 1.0, true);
  v.real_in(n, "initial_probability", p.initial_probability, 0.0, false, 1.0, false);
}

// Liu 2022 Table 1: one value for the four rules.
void read_liu_rules(const pb::LiuPolicy& msg, const Node& n, Validator& v, LiuParams& p) {
  const auto all = [](std::array<double, 4>& a, double x) { a.fill(x); };
  if (msg.has_k()) all(p.k, msg.k());
  if (msg.has_t()) all(p.t, msg.t());
  if (msg.has_c()) all(p.c, msg.c());
  if (msg.has_delta()) all(p.delta, msg.delta());
  if (msg.has_delta_prime()) all(p.delta_prime, msg.delta_prime());
  v.real_in(n, "k", p.k[0], -kInf, false, kInf, false);
  v.real_in(n, "t", p.t[0], -kInf, false, kInf, false);
  v.real_in(n, "c", p.c[0], 0.0, false, kInf, false);
  v.real_in(n, "delta", p.delta[0], 0.0, true, kInf, false);
  v.real_in(n, "delta_prime", p.delta_prime[0], 0.0, true, kInf, false);
}

// Space and time.
void read_liu_space_time(const pb::LiuPolicy& msg, const Node& n, Validator& v, LiuParams& p) {
  if (msg.has_cell_size_m()) p.cell_size_m = msg.cell_size_m();
  if (msg.has_max_speed_mps()) p.max_speed_mps = msg.max_speed_mps();
  if (msg.has_dt_s()) p.dt_s = msg.dt_s();
  if (msg.has_cycle_s()) p.cycle_s = msg.cycle_s();
  if (msg.has_random_step_mps()) p.random_step_mps = msg.random_step_mps();
  if (msg.has_mower_step_mps()) p.mower_step_mps = msg.mower_step_mps();
  v.real_in(n, "cell_size_m", p.cell_size_m, 0.0, true, kInf, false);
  v.real_in(n, "max_speed_mps", p.max_speed_mps, 0.0, true, kInf, false);
  // A cycle of at most 100 s keeps it at most 1e6 Δt steps of 0.1 ms.
  if (v.real_in(n, "cycle_s", p.cycle_s, 0.0, true, 100.0, false) && v.real_in(n, "dt_s", p.dt_s, 0.0, true, kInf, false)) {
    if (p.dt_s > p.cycle_s) v.fail(n, "dt_s", "must be <= cycle_s (" + format_number(p.cycle_s) + ")");
    if (p.cycle_s / p.dt_s > 1e6) v.fail(n, "dt_s", "gives more than 1e6 steps per cycle");
  }
  v.real_in(n, "random_step_mps", p.random_step_mps, 0.0, true, kInf, false);
  v.real_in(n, "mower_step_mps", p.mower_step_mps, 0.0, true, kInf, false);
}

// Boids.
void read_liu_boids(const pb::LiuPolicy& msg, const Node& n, Validator& v, LiuParams& p) {
  if (msg.has_boids_safe_distance_m()) p.boids_safe_distance_m = msg.boids_safe_distance_m();
  if (msg.has_boids_separation_weight()) p.boids_separation_weight = msg.boids_separation_weight();
  if (msg.has_boids_alignment_weight()) p.boids_alignment_weight = msg.boids_alignment_weight();
  if (msg.has_boids_cohesion_weight()) p.boids_cohesion_weight = msg.boids_cohesion_weight();
  if (msg.has_boids_guidance_weight()) p.boids_guidance_weight = msg.boids_guidance_weight();
  v.real_in(n, "boids_safe_distance_m", p.boids_safe_distance_m, 0.0, true, kInf, false);
  v.real_in(n, "boids_separation_weight", p.boids_separation_weight, 0.0, false, kInf, false);
  v.real_in(n, "boids_alignment_weight", p.boids_alignment_weight, 0.0, false, kInf, false);
  v.real_in(n, "boids_cohesion_weight", p.boids_cohesion_weight, 0.0, false, kInf, false);
  v.real_in(n, "boids_guidance_weight", p.boids_guidance_weight, 0.0, false, kInf, false);
}

void build_liu(const pb::LiuPolicy& msg, const Node& n, Validator& v, ScenarioConfig& cfg) {
  LiuConfig c;
  read_liu_choices(msg, n, v, c);
  read_liu_prior(msg, n, v, cfg, c);
  read_liu_sensor(msg, n, v, c.params);
  read_liu_rules(msg, n, v, c.params);
  read_liu_space_time(msg, n, v, c.params);
  read_liu_boids(msg, n, v, c.params);
  if (msg.has_view_radius()) {
    c.view_radius_cells = msg.view_radius();
    v.real_in(n, "view_radius", msg.view_radius(), 0.0, true, kMaxSensorRadius, false);
  }

  // The mower sweeps one lane of rows per UAV (lawnmower_lane).
  if (c.search == LiuPolicy::kLawnmower && cfg.height > 0 && static_cast<int64_t>(cfg.uavs) > cfg.height) {
    v.fail(n, "search", "\"lawnmower\" needs at most one UAV per map row (" + std::to_string(cfg.uavs) + " UAVs, " +
                            std::to_string(cfg.height) + " rows)");
  }
  cfg.set_policy_config(std::move(c));
}

}  // namespace

}  // namespace pheromesh::core::scenario_detail

namespace pheromesh::core {

constinit const PolicyEntry kLiuPolicy{
    .name = LiuConfig::kPolicy,
    .parse = &scenario_detail::parse_as<scenario_detail::pb::LiuPolicy, &scenario_detail::build_liu>,
    .parse_scenario_fields = nullptr,
    .traits = &liu_traits,
    .broadcasts = false,
    .make_uav = &make_liu_uav,
    .make_place = &make_liu_place,
    .field_summary = &liu_field_summary,
};

}  // namespace pheromesh::core
