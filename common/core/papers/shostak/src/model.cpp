// Shostak & Petrenko: GPS-denied stigmergy (see pheromesh/shostak/model.hpp).
#include "pheromesh/shostak/model.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>

#include "pheromesh/core/angles.hpp"

namespace pheromesh::core {

namespace {

// Standard normal by Box-Muller (Rng has no distributions, by design).
double standard_normal(Rng& rng) {
  const double u1 = 1.0 - rng.uniform01();  // (0, 1]
  const double u2 = rng.uniform01();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(kTwoPi * u2);
}

int32_t floor_to_cell(double v) {
  constexpr double lo = static_cast<double>(std::numeric_limits<int32_t>::min());
  constexpr double hi = static_cast<double>(std::numeric_limits<int32_t>::max());
  if (!std::isfinite(v)) {
    return v > 0.0 ? std::numeric_limits<int32_t>::max() : std::numeric_limits<int32_t>::min();
  }
  return static_cast<int32_t>(std::clamp(std::floor(v), lo, hi));
}

}  // namespace

const char* shostak_layer_name(ShostakLayer l) {
  switch (l) {
    case ShostakLayer::Explored:
      return "explored";
    case ShostakLayer::Hazard:
      return "hazard";
    case ShostakLayer::Target:
      return "target";
  }
  return "?";
}

double shostak_evaporation_factor(double rho, double dt_s) {
  if (dt_s <= 0.0) {
    return 1.0;
  }
  return std::pow(1.0 - rho, dt_s);  // Shostak 2024 eq. (2), per-second factor raised to dt
}

double shostak_half_life_s(double rho) { return std::log(0.5) / std::log(1.0 - rho); }

uint32_t shostak_deposits_due(double t0_s, double t1_s, double period_s) {
  if (!(t1_s > t0_s) || !(period_s > 0.0)) {
    return 0;
  }
  // Instants k·period; the small slack keeps 0.6 / 0.2 = 2.9999999999999996 at k = 3.
  constexpr double kSlack = 1e-9;
  const double k0 = std::floor(t0_s / period_s + kSlack);
  const double k1 = std::floor(t1_s / period_s + kSlack);
  const double n = std::max(0.0, k1 - k0);
  return n >= 4294967295.0 ? std::numeric_limits<uint32_t>::max() : static_cast<uint32_t>(n);
}

// --- ShostakLayers ---------------------------------------------------------

ShostakLayers::ShostakLayers(const Rect& rect, const ShostakLayerParams& params) : rect_(rect), p_(params) {
  assert(rect.w >= 0 && rect.h >= 0);
  for (auto& l : layers_) {
    l.assign(static_cast<std::size_t>(rect.area()), 0.0F);
  }
}

std::span<const float> ShostakLayers::layer(ShostakLayer l) const { return layers_[static_cast<int>(l)]; }
std::span<float> ShostakLayers::mutable_layer(ShostakLayer l) { return layers_[static_cast<int>(l)]; }

double ShostakLayers::max_of(ShostakLayer l) const {
  switch (l) {
    case ShostakLayer::Explored:
      return p_.explored_max;
    case ShostakLayer::Hazard:
      return p_.hazard_max;
    case ShostakLayer::Target:
      return p_.target_max;
  }
  return 0.0;
}

std::optional<std::size_t> ShostakLayers::index_of(Cell c) const {
  if (!rect_.contains(c)) {
    return std::nullopt;
  }
  return static_cast<std::size_t>(c.y - rect_.y0) * static_cast<std::size_t>(rect_.w) +
         static_cast<std::size_t>(c.x - rect_.x0);
}

std::optional<ShostakCellValues> ShostakLayers::values(Cell c) const {
  const auto i = index_of(c);
  if (!i) {
    return std::nullopt;
  }
  return ShostakCellValues{layers_[0][*i], layers_[1][*i], layers_[2][*i]};
}

float ShostakLayers::value(ShostakLayer l, Cell c) const {
  const auto i = index_of(c);
  assert(i.has_value());
  return layers_[static_cast<int>(l)][*i];
}

bool ShostakLayers::deposit(ShostakLayer l, Cell c, double amount) {
  const auto i = index_of(c);
  if (!i || !std::isfinite(amount) || amount < 0.0) {
    return false;
  }
  float& v = layers_[static_cast<int>(l)][*i];
  v = static_cast<float>(std::min(static_cast<double>(v) + amount, max_of(l)));  // Shostak 2024 eq. (1)
  return true;
}

void ShostakLayers::evaporate(double dt_s) {
  if (!(dt_s > 0.0)) {
    return;
  }
  const auto f = static_cast<float>(shostak_evaporation_factor(p_.evaporation_rate, dt_s));
  for (auto& layer : layers_) {
    for (float& v : layer) {
      v *= f;  // Shostak 2024 eq. (2)
    }
  }
}

// --- attractiveness, candidates, choice ------------------------------------

ShostakAttractiveness shostak_attractiveness(const ShostakCellValues& v, const ShostakAttractivenessParams& p) {
  ShostakAttractiveness a;
  a.b_e = 1.0 - std::min(std::max(v.explored, 0.0) / p.explored_scale, p.explored_max_penalty);
  a.b_h = 1.0 - std::min(std::max(v.hazard, 0.0) / p.hazard_scale, p.hazard_max_penalty);
  a.b_t = std::max(v.target, 0.0) * p.target_gain;
  a.phi = a.b_e * a.b_h + a.b_t;  // Shostak 2024 eq. (3)
  return a;
}

std::vector<ShostakCandidate> shostak_candidates(const Eigen::Vector3d& p, const ShostakAcoParams& params, Rng& rng) {
  std::vector<ShostakCandidate> out;
  out.reserve(params.candidate_count);
  for (uint32_t k = 0; k < params.candidate_count; ++k) {
    ShostakCandidate c;
    c.azimuth_rad = kTwoPi * rng.uniform01();
    c.pitch_rad = -params.pitch_max_rad + 2.0 * params.pitch_max_rad * rng.uniform01();
    const double cp = std::cos(c.pitch_rad);
    // Shostak 2024 eq. (4)
    c.position = p + params.step_m * Eigen::Vector3d(cp * std::cos(c.azimuth_rad), cp * std::sin(c.azimuth_rad),
                                                     std::sin(c.pitch_rad));
    out.push_back(c);
  }
  return out;
}

double shostak_eta(double candidate_azimuth_rad, std::optional<double> preferred_azimuth_rad,
                   const ShostakAcoParams& p) {
  if (!preferred_azimuth_rad) {
    return 1.0;
  }
  const double align = 0.5 * (1.0 + std::cos(candidate_azimuth_rad - *preferred_azimuth_rad));
  return p.eta_floor + (1.0 - p.eta_floor) * align;
}

double shostak_score(double phi, double eta, const ShostakAcoParams& p) {
  if (!(phi > 0.0) || !(eta > 0.0)) {
    return 0.0;
  }
  return std::pow(phi, p.alpha) * std::pow(eta, p.beta);  // Shostak 2024 eq. (5)
}

std::optional<std::size_t> shostak_roulette(std::span<const double> scores, Rng& rng) {
  auto usable = [](double s) { return std::isfinite(s) && s > 0.0; };
  double total = 0.0;
  for (double s : scores) {
    if (usable(s)) {
      total += s;
    }
  }
  if (!(total > 0.0) || !std::isfinite(total)) {
    return std::nullopt;
  }
  // Shostak 2024 eq. (6): P(c_k) = s_k / Σ s_j
  const double r = rng.uniform01() * total;
  double acc = 0.0;
  std::optional<std::size_t> last;
  for (std::size_t k = 0; k < scores.size(); ++k) {
    if (!usable(scores[k])) {
      continue;
    }
    acc += scores[k];
    last = k;
    if (r < acc) {
      return k;
    }
  }
  return last;  // rounding left r at the very top of the sum
}

Cell shostak_cell_of(const Eigen::Vector3d& p_world, double cell_size_m) {
  return {floor_to_cell(p_world.x() / cell_size_m), floor_to_cell(p_world.y() / cell_size_m)};
}

std::optional<ShostakChoice> shostak_choose(const Eigen::Vector3d& p_world, std::optional<double> preferred_azimuth_rad,
                                            const ShostakLookup& lookup, double cell_size_m,
                                            const ShostakAcoParams& aco, const ShostakAttractivenessParams& attr,
                                            Rng& rng) {
  const auto candidates = shostak_candidates(p_world, aco, rng);
  std::vector<double> scores(candidates.size(), 0.0);
  double total = 0.0;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const auto v = lookup(shostak_cell_of(candidates[k].position, cell_size_m));
    if (!v) {
      continue;
    }
    const double phi = shostak_attractiveness(*v, attr).phi;
    scores[k] = shostak_score(phi, shostak_eta(candidates[k].azimuth_rad, preferred_azimuth_rad, aco), aco);
    if (std::isfinite(scores[k])) {
      total += scores[k];
    }
  }
  const auto k = shostak_roulette(scores, rng);
  if (!k) {
    return std::nullopt;
  }
  return ShostakChoice{candidates[*k], *k, scores[*k] / total};
}

double shostak_dispersal_heading(uint32_t index, uint32_t count) {
  if (count == 0) {
    return 0.0;
  }
  return kTwoPi * static_cast<double>(index % count) / static_cast<double>(count);  // Shostak 2024 Sec. 5
}

Eigen::Vector3d shostak_dispersal_waypoint(const Eigen::Vector3d& start, uint32_t index, uint32_t count,
                                           double distance_m) {
  const double h = shostak_dispersal_heading(index, count);
  return start + distance_m * Eigen::Vector3d(std::cos(h), std::sin(h), 0.0);
}

// --- local frame and drift -------------------------------------------------

Eigen::Vector3d shostak_local_to_world(const ShostakLocalFrame& f, const Eigen::Vector3d& p_local) {
  const double c = std::cos(f.yaw_rad);
  const double s = std::sin(f.yaw_rad);
  return f.origin_world + Eigen::Vector3d(c * p_local.x() - s * p_local.y(), s * p_local.x() + c * p_local.y(),
                                          p_local.z());
}

Eigen::Vector3d shostak_world_to_local(const ShostakLocalFrame& f, const Eigen::Vector3d& p_world) {
  const Eigen::Vector3d d = p_world - f.origin_world;
  const double c = std::cos(f.yaw_rad);
  const double s = std::sin(f.yaw_rad);
  return {c * d.x() + s * d.y(), -s * d.x() + c * d.y(), d.z()};
}

double shostak_heading_local_to_world(const ShostakLocalFrame& f, double heading_local_rad) {
  return wrap_two_pi(heading_local_rad + f.yaw_rad);
}

double shostak_heading_world_to_local(const ShostakLocalFrame& f, double heading_world_rad) {
  return wrap_two_pi(heading_world_rad - f.yaw_rad);
}

ShostakPoseEstimate shostak_drift_step(const ShostakPoseEstimate& est, const Eigen::Vector3d& true_delta_local,
                                       const ShostakDriftParams& p, Rng& rng) {
  const double s = true_delta_local.norm();
  const double c = std::cos(est.yaw_error_rad);
  const double sn = std::sin(est.yaw_error_rad);
  ShostakPoseEstimate out = est;
  out.position_local += Eigen::Vector3d(c * true_delta_local.x() - sn * true_delta_local.y(),
                                        sn * true_delta_local.x() + c * true_delta_local.y(), true_delta_local.z());
  if (p.position_noise_m2_per_m > 0.0 && s > 0.0) {
    const double sigma = std::sqrt(p.position_noise_m2_per_m * s);
    for (int i = 0; i < 3; ++i) {
      out.position_local[i] += sigma * standard_normal(rng);
    }
  }
  if (p.yaw_noise_rad2_per_m > 0.0 && s > 0.0) {
    out.yaw_error_rad += std::sqrt(p.yaw_noise_rad2_per_m * s) * standard_normal(rng);
  }
  return out;
}

}  // namespace pheromesh::core
