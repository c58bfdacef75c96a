// Liu 2022 (ESUSTPM): TPM, environmental uncertainty, local rules and
// baselines. How we read the PDF-extracted equations:
//
//  Liu 2022 eq. (1) bivariate normal density. The extracted text has
//    {(x-μ1)²/σ1² - 2ρ(x-μ1)(y-μ2)/(σ1σ2) - (y-μ2)²/σ2²};
//  the last minus makes the "density" non-integrable, so it is a typo for +
//  (the textbook form). ρ is called "the covariance", but sqrt(1 - ρ²) in the
//  normaliser makes it the correlation coefficient.
//  Liu 2022 eq. (2) f = Σ α_i f_i; P_mn = ∬ over the cell of f (the sentence after
//  Liu 2022 eq. (2)). "independent in x and y, thus σ1 = σ2 = σ0": independence means
//  ρ = 0; we keep σx, σy, ρ general, callers can pass σx = σy, ρ = 0.
//  Liu 2022 eq. (3) unsearched cell unchanged; Liu 2022 eq. (4) detection posterior
//    P' = Pd P / ((Pd - Pf) P + Pf)  (= Pd P / (Pd P + Pf (1 - P)));
//  Liu 2022 eq. (5) miss, printed P' = (1 - Pd) P / (1 - Pf) (see MissUpdate).
//  Liu 2022 eq. (6) mvel = 1/4 Σ_{i=1..4} F_i/|F_i| β_i; Liu 2022 eq. (7), Liu 2022 eq. (8), Liu 2022 eq. (9)
//    g(d) = t (1 - exp(-(d - c)²/δ'²)),  a(d) = k (d - c) exp(-(d - c)²/δ²),
//    β = a g.
//  Liu 2022 eq. (10), Liu 2022 eq. (11) P(t+1) = P(t) + mvel Δt. Liu 2022 eq. (12) dir = rnd(2,1)/|rnd(2,1)|,
//  rnd uniform in [-1, 1]; Liu 2022 eq. (13) P += dir S Δt; Liu 2022 eq. (14) P += b l Δt.
#include "pheromesh/liu/tpm.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace pheromesh::core {

namespace {

constexpr double kTiny = 1e-9;           // velocities below this [m/s] have no direction
constexpr double kTieTolerance = 1e-12;  // equal probabilities / alignments
constexpr int kSimpsonPanels = 64;       // x-integration of a correlated component over one cell (even)

double norm(Vec2 v) { return std::hypot(v.x, v.y); }
Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
Vec2 operator*(Vec2 a, double s) { return {a.x * s, a.y * s}; }

// v / |v|, or 0 if v has no direction.
Vec2 unit_or_zero(Vec2 v) {
  const double n = norm(v);
  return n < kTiny ? Vec2{} : v * (1.0 / n);
}

Vec2 clip_speed(Vec2 v, double max_speed) {
  const double n = norm(v);
  return n > max_speed ? v * (max_speed / n) : v;
}

// Standard normal CDF.
double phi_cdf(double z) { return 0.5 * std::erfc(-z / std::numbers::sqrt2); }

// ∬ over [x0, x1] x [y0, y1] of one component's density (Liu 2022 eq. (1)), without α.
double cell_mass(const GaussianComponent& g, double x0, double x1, double y0, double y1) {
  if (g.rho == 0.0) {
    // Separable: product of the marginal masses, exact.
    const double mx = phi_cdf((x1 - g.mu_x) / g.sigma_x) - phi_cdf((x0 - g.mu_x) / g.sigma_x);
    const double my = phi_cdf((y1 - g.mu_y) / g.sigma_y) - phi_cdf((y0 - g.mu_y) / g.sigma_y);
    return mx * my;
  }
  // f(x, y) = f_x(x) f(y | x) with y | x ~ N(μ2 + ρ σ2 (x - μ1)/σ1, σ2² (1 - ρ²)):
  // the y-integral is exact, the x-integral composite Simpson.
  const double s = g.sigma_y * std::sqrt(1.0 - g.rho * g.rho);
  auto integrand = [&](double x) {
    const double zx = (x - g.mu_x) / g.sigma_x;
    const double fx = std::exp(-0.5 * zx * zx) / (g.sigma_x * std::sqrt(2.0 * std::numbers::pi));
    const double m = g.mu_y + g.rho * g.sigma_y * zx;
    return fx * (phi_cdf((y1 - m) / s) - phi_cdf((y0 - m) / s));
  };
  const double hstep = (x1 - x0) / kSimpsonPanels;
  double sum = integrand(x0) + integrand(x1);
  for (int i = 1; i < kSimpsonPanels; ++i) {
    sum += (i % 2 == 1 ? 4.0 : 2.0) * integrand(x0 + hstep * i);
  }
  return sum * hstep / 3.0;
}

bool in_grid(Cell c, const LiuParams& p) { return c.x >= 0 && c.y >= 0 && c.x < p.grid_width && c.y < p.grid_height; }

double neg_p_log2_p(double p) { return p > 0.0 ? -p * std::log2(p) : 0.0; }

}  // namespace

// ---------------------------------------------------------------------------
// Prior
// ---------------------------------------------------------------------------

std::optional<Error> check_component(const GaussianComponent& g) {
  if (!std::isfinite(g.mu_x) || !std::isfinite(g.mu_y) || !std::isfinite(g.sigma_x) || !std::isfinite(g.sigma_y) ||
      !std::isfinite(g.rho) || !std::isfinite(g.weight)) {
    return Error{"gaussian component: values must be finite"};
  }
  if (!(g.sigma_x > 0.0) || !(g.sigma_y > 0.0)) {
    return Error{"gaussian component: sigma_x and sigma_y must be > 0"};
  }
  if (!(std::abs(g.rho) < 1.0)) {
    return Error{"gaussian component: |rho| must be < 1"};
  }
  if (g.weight < 0.0) {
    return Error{"gaussian component: weight must be >= 0"};
  }
  return std::nullopt;
}

std::vector<double> gaussian_mixture_prior(int32_t w, int32_t h, std::span<const GaussianComponent> components) {
  if (w <= 0 || h <= 0) {
    return {};
  }
  std::vector<double> map(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0.0);
  for (const GaussianComponent& g : components) {
    if (check_component(g)) {
      continue;
    }
    for (int32_t y = 0; y < h; ++y) {
      for (int32_t x = 0; x < w; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
        map[i] += g.weight * cell_mass(g, x, x + 1.0, y, y + 1.0);  // Liu 2022 eq. (2)
      }
    }
  }
  for (double& v : map) {
    v = std::clamp(v, 0.0, 1.0);
  }
  return map;
}

// ---------------------------------------------------------------------------
// TPM update
// ---------------------------------------------------------------------------

double tpm_after_detection(double p, double p_detection, double p_false_alarm) {
  const double den = (p_detection - p_false_alarm) * p + p_false_alarm;  // Liu 2022 eq. (4)
  return den > 0.0 ? p_detection * p / den : p;
}

double tpm_after_miss(double p, double p_detection, double p_false_alarm, MissUpdate rule) {
  if (rule == MissUpdate::kAsPrinted) {
    return (1.0 - p_detection) * p / (1.0 - p_false_alarm);  // Liu 2022 eq. (5) as printed
  }
  const double den = (p_false_alarm - p_detection) * p + 1.0 - p_false_alarm;  // (1-Pd)P + (1-Pf)(1-P)
  return den > 0.0 ? (1.0 - p_detection) * p / den : p;
}

double tpm_update(double p, bool detected, const LiuParams& params) {
  return detected ? tpm_after_detection(p, params.p_detection, params.p_false_alarm)
                  : tpm_after_miss(p, params.p_detection, params.p_false_alarm, params.miss_update);
}

TargetProbabilityMap::TargetProbabilityMap(Rect region, const LiuParams& params)
    : TargetProbabilityMap(region,
                           std::vector<double>(static_cast<std::size_t>(std::max<int64_t>(region.area(), 0)),
                                               params.initial_probability),
                           params) {}

TargetProbabilityMap::TargetProbabilityMap(Rect region, std::vector<double> values, const LiuParams& params)
    : region_(region),
      p_(std::move(values)),
      p_detection_(params.p_detection),
      p_false_alarm_(params.p_false_alarm),
      threshold_(params.confirm_threshold),
      miss_update_(params.miss_update) {}

Result<TargetProbabilityMap> TargetProbabilityMap::from_map(Rect region, std::span<const double> map, int32_t map_width,
                                                            int32_t map_height, const LiuParams& params) {
  if (map_width <= 0 || map_height <= 0 ||
      map.size() != static_cast<std::size_t>(map_width) * static_cast<std::size_t>(map_height)) {
    return Error{"target probability map: map size does not match " + std::to_string(map_width) + " x " +
                 std::to_string(map_height)};
  }
  if (region.w <= 0 || region.h <= 0 || region.x0 < 0 || region.y0 < 0 || region.x0 + region.w > map_width ||
      region.y0 + region.h > map_height) {
    return Error{"target probability map: region is not inside the map"};
  }
  std::vector<double> values;
  values.reserve(static_cast<std::size_t>(region.area()));
  for (int32_t y = region.y0; y < region.y0 + region.h; ++y) {
    for (int32_t x = region.x0; x < region.x0 + region.w; ++x) {
      const double v = map[static_cast<std::size_t>(y) * static_cast<std::size_t>(map_width) + static_cast<std::size_t>(x)];
      if (!std::isfinite(v) || v < 0.0 || v > 1.0) {
        return Error{"target probability map: value at (" + std::to_string(x) + ", " + std::to_string(y) +
                     ") is not a probability"};
      }
      values.push_back(v);
    }
  }
  return TargetProbabilityMap(region, std::move(values), params);
}

std::size_t TargetProbabilityMap::index(Cell c) const {
  return static_cast<std::size_t>(c.y - region_.y0) * static_cast<std::size_t>(region_.w) +
         static_cast<std::size_t>(c.x - region_.x0);
}

double TargetProbabilityMap::probability(Cell c) const {
  assert(contains(c));
  return p_[index(c)];
}

std::optional<double> TargetProbabilityMap::find(Cell c) const {
  if (!contains(c)) {
    return std::nullopt;
  }
  return p_[index(c)];
}

bool TargetProbabilityMap::observe(Cell c, bool detected) {
  if (!contains(c)) {
    return false;
  }
  double& p = p_[index(c)];
  p = detected ? tpm_after_detection(p, p_detection_, p_false_alarm_)
               : tpm_after_miss(p, p_detection_, p_false_alarm_, miss_update_);
  return true;
}

bool TargetProbabilityMap::confirmed(Cell c) const { return contains(c) && p_[index(c)] > threshold_; }

std::vector<Cell> TargetProbabilityMap::confirmed_cells() const {
  std::vector<Cell> out;
  for (int32_t y = region_.y0; y < region_.y0 + region_.h; ++y) {
    for (int32_t x = region_.x0; x < region_.x0 + region_.w; ++x) {
      if (confirmed(Cell{x, y})) {
        out.push_back(Cell{x, y});
      }
    }
  }
  return out;
}

// ---------------------------------------------------------------------------
// Environmental uncertainty
// ---------------------------------------------------------------------------

double environmental_uncertainty(std::span<const double> probabilities) {
  double sum = 0.0;
  for (const double p : probabilities) {
    sum += neg_p_log2_p(p);
  }
  return sum;
}

double binary_entropy_bits(std::span<const double> probabilities) {
  double sum = 0.0;
  for (const double p : probabilities) {
    sum += neg_p_log2_p(p) + neg_p_log2_p(1.0 - p);
  }
  return sum;
}

// ---------------------------------------------------------------------------
// Grid helpers
// ---------------------------------------------------------------------------

Vec2 cell_centre(Cell c, double cell_size_m) { return {(c.x + 0.5) * cell_size_m, (c.y + 0.5) * cell_size_m}; }

Cell cell_of(Vec2 position, const LiuParams& p) {
  const auto axis = [&](double v, int32_t n) {
    const double f = std::floor(v / p.cell_size_m);
    return static_cast<int32_t>(std::clamp(f, 0.0, static_cast<double>(n - 1)));
  };
  return {axis(position.x, p.grid_width), axis(position.y, p.grid_height)};
}

std::optional<Heading> heading_of(Vec2 v) {
  if (norm(v) < kTiny) {
    return std::nullopt;
  }
  constexpr double kEighth = std::numbers::pi / 4.0;
  const auto s = static_cast<int>(std::floor((std::atan2(v.y, v.x) + kEighth / 2.0) / kEighth));
  return static_cast<Heading>(((s % 8) + 8) % 8);
}

std::vector<std::size_t> nearest_neighbours(Vec2 self, std::span<const LiuUav> others, const LiuParams& params) {
  std::vector<std::pair<double, std::size_t>> by_distance;
  for (std::size_t i = 0; i < others.size(); ++i) {
    const double d = norm(others[i].position - self);
    if (d <= params.comm_range_m) {
      by_distance.emplace_back(d, i);
    }
  }
  std::sort(by_distance.begin(), by_distance.end());  // distance, then index
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < by_distance.size() && i < params.neighbour_count; ++i) {
    out.push_back(by_distance[i].second);
  }
  return out;
}

std::optional<Cell> most_probable_neighbour(Cell at, Vec2 velocity, const TpmLookup& tpm) {
  if (!tpm) {
    return std::nullopt;
  }
  const Vec2 dir = unit_or_zero(velocity);
  std::optional<Cell> best;
  double best_p = 0.0;
  double best_align = 0.0;
  for (int h = 0; h < 8; ++h) {
    const Cell step = step_of(static_cast<Heading>(h));
    const Cell c{at.x + step.x, at.y + step.y};
    const std::optional<double> p = tpm(c);
    if (!p) {
      continue;
    }
    const double align = (dir.x * step.x + dir.y * step.y) / std::hypot(step.x, step.y);  // cos to velocity
    if (!best || *p > best_p + kTieTolerance ||
        (std::abs(*p - best_p) <= kTieTolerance && align > best_align + kTieTolerance)) {
      best = c;
      best_p = *p;
      best_align = align;
    }
  }
  return best;
}

double liu_gain(std::size_t rule, double distance_m, const LiuParams& params) {
  const double e = distance_m - params.c[rule];
  const double g = params.t[rule] * (1.0 - std::exp(-e * e / (params.delta_prime[rule] * params.delta_prime[rule])));  // Liu 2022 eq. (7)
  const double a = params.k[rule] * e * std::exp(-e * e / (params.delta[rule] * params.delta[rule]));  // Liu 2022 eq. (8)
  return a * g;  // Liu 2022 eq. (9)
}

LiuMove grid_move(Vec2 position, Vec2 velocity, const LiuParams& params) {
  const Cell at = cell_of(position, params);
  LiuMove m{velocity, heading_of(velocity), at};
  if (!m.heading) {
    return m;
  }
  Cell step = step_of(*m.heading);
  if (at.x + step.x < 0 || at.x + step.x >= params.grid_width) {  // Liu 2022 Sec. 2.2: velocity reversed at the boundary
    step.x = -step.x;
    m.velocity.x = -m.velocity.x;
  }
  if (at.y + step.y < 0 || at.y + step.y >= params.grid_height) {
    step.y = -step.y;
    m.velocity.y = -m.velocity.y;
  }
  const Cell next{at.x + step.x, at.y + step.y};
  if (!in_grid(next, params)) {
    m.heading = std::nullopt;  // one-cell-wide map: nowhere to go
    return m;
  }
  m.heading = heading_of(Vec2{static_cast<double>(step.x), static_cast<double>(step.y)});
  m.next = next;
  return m;
}

LiuUav advance_uav(const LiuUav& uav, Vec2 velocity, double dt_s, const LiuParams& params) {
  LiuUav out{uav.position + velocity * dt_s, velocity};  // Liu 2022 eq. (10), Liu 2022 eq. (11)
  const auto reflect = [](double& x, double& v, double extent) {
    if (x < 0.0) {
      x = -x;
      v = -v;
    } else if (x > extent) {
      x = 2.0 * extent - x;
      v = -v;
    }
    x = std::clamp(x, 0.0, extent);  // a step longer than the map
  };
  reflect(out.position.x, out.velocity.x, params.grid_width * params.cell_size_m);
  reflect(out.position.y, out.velocity.y, params.grid_height * params.cell_size_m);
  return out;
}

double liu_lowest_eu(int32_t looked_cells, int32_t cells, int32_t looks, const LiuParams& params) {
  if (looked_cells < 0 || looks < 0 || looked_cells > cells) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  if (looked_cells > looks) {
    return std::numeric_limits<double>::infinity();
  }
  const double q = (1.0 - params.p_detection) / (1.0 - params.p_false_alarm);  // Liu 2022 eq. (5) as printed
  const auto h = [](double x) { return x <= 0.0 ? 0.0 : -x * std::log2(x); };
  const auto n_looks = static_cast<std::size_t>(looks);
  std::vector<double> cell_eu(n_looks + 1);  // EU of one cell after n misses
  for (std::size_t n = 0; n <= n_looks; ++n) {
    cell_eu[n] = h(params.initial_probability * std::pow(q, static_cast<double>(n)));
  }
  const double inf = std::numeric_limits<double>::infinity();
  // best[u]: lowest EU of the cells placed so far using exactly u looks.
  std::vector<double> best(n_looks + 1, inf);
  best[0] = 0.0;
  for (int32_t c = 0; c < looked_cells; ++c) {
    std::vector<double> next(n_looks + 1, inf);
    for (std::size_t used = 0; used <= n_looks; ++used) {
      if (best[used] == inf) continue;
      for (std::size_t n = 1; used + n <= n_looks; ++n) {
        next[used + n] = std::min(next[used + n], best[used] + cell_eu[n]);
      }
    }
    best = std::move(next);
  }
  return *std::min_element(best.begin(), best.end()) + (cells - looked_cells) * h(params.initial_probability);
}

// ---------------------------------------------------------------------------
// ESUSTPM
// ---------------------------------------------------------------------------

namespace {

// Liu 2022 eq. (6) with rules 1-3 as given, or (repel_only) with their
// attracting half dropped (ESUSTPM-disperse).
Vec2 objective_velocity(const LiuUav& self, std::span<const LiuUav> others, const TpmLookup& tpm,
                        const LiuParams& params, bool repel_only) {
  Vec2 sum{};
  const std::vector<std::size_t> nn = nearest_neighbours(self.position, others, params);
  for (std::size_t rule = 0; rule < nn.size() && rule < 3; ++rule) {
    const Vec2 f = self.position - others[nn[rule]].position;  // F_i: from the neighbour to the UAV
    const double d = norm(f);
    if (d > 0.0) {
      const double beta = liu_gain(rule, d, params);
      sum = sum + f * ((repel_only ? std::max(beta, 0.0) : beta) / d);
    }
  }
  const std::optional<Cell> guide =
      most_probable_neighbour(cell_of(self.position, params), self.velocity, tpm);
  if (guide) {
    const Vec2 f = cell_centre(*guide, params.cell_size_m) - self.position;  // F_4: towards the cell
    const double d = norm(f);
    if (d > 0.0) {
      sum = sum + f * (std::abs(liu_gain(3, d, params)) / d);
    }
  }
  return sum * 0.25;  // Liu 2022 eq. (6)
}

LiuMove step_towards(const LiuUav& self, Vec2 v, const LiuParams& params) {
  if (norm(v) < kTiny) {
    v = self.velocity;
  }
  return grid_move(self.position, clip_speed(v, params.max_speed_mps), params);
}

}  // namespace

Vec2 esustpm_objective_velocity(const LiuUav& self, std::span<const LiuUav> others, const TpmLookup& tpm,
                                const LiuParams& params) {
  return objective_velocity(self, others, tpm, params, false);
}

LiuMove esustpm_step(const LiuUav& self, std::span<const LiuUav> others, const TpmLookup& tpm,
                     const LiuParams& params) {
  return step_towards(self, esustpm_objective_velocity(self, others, tpm, params), params);
}

Vec2 esustpm_disperse_objective_velocity(const LiuUav& self, std::span<const LiuUav> others, const TpmLookup& tpm,
                                         const LiuParams& params) {
  return objective_velocity(self, others, tpm, params, true);
}

LiuMove esustpm_disperse_step(const LiuUav& self, std::span<const LiuUav> others, const TpmLookup& tpm,
                              const LiuParams& params) {
  return step_towards(self, esustpm_disperse_objective_velocity(self, others, tpm, params), params);
}

// ---------------------------------------------------------------------------
// Baselines
// ---------------------------------------------------------------------------

Vec2 random_direction(Rng& rng) {
  for (;;) {
    const Vec2 r{2.0 * rng.uniform01() - 1.0, 2.0 * rng.uniform01() - 1.0};  // rnd(2, 1)
    const double n = norm(r);
    if (n > kTiny) {
      return r * (1.0 / n);  // Liu 2022 eq. (12)
    }
  }
}

LiuMove random_search_step(const LiuUav& self, Rng& rng, const LiuParams& params) {
  return grid_move(self.position, random_direction(rng) * params.random_step_mps, params);  // Liu 2022 eq. (13)
}

Rect lawnmower_lane(uint32_t uav, uint32_t uavs, int32_t w, int32_t h) {
  assert(uavs > 0 && uav < uavs && static_cast<int64_t>(uavs) <= h);
  const int64_t rows = h;
  const auto row0 = static_cast<int32_t>(rows * uav / uavs);
  const auto row1 = static_cast<int32_t>(rows * (uav + 1) / uavs);
  return {0, row0, w, row1 - row0};
}

LawnmowerState lawnmower_start(Rect lane) { return {Cell{lane.x0, lane.y0}, 1, 1}; }

LawnmowerState lawnmower_step(const LawnmowerState& s, Rect lane) {
  if (!lane.contains(s.cell)) {
    return s;
  }
  LawnmowerState n = s;
  const Cell along{s.cell.x + s.dx, s.cell.y};
  if (lane.contains(along)) {  // Liu 2022 eq. (14): P += b l Δt
    n.cell = along;
    return n;
  }
  n.dx = -s.dx;  // b reversed at the boundary
  for (int attempt = 0; attempt < 2; ++attempt) {
    const Cell up{s.cell.x, s.cell.y + n.dy};
    if (lane.contains(up)) {
      n.cell = up;
      return n;
    }
    n.dy = -n.dy;  // top (or bottom) row of the lane: sweep back the other way
  }
  const Cell back{s.cell.x + n.dx, s.cell.y};  // one-row lane: straight back along the row
  if (lane.contains(back)) {
    n.cell = back;
  }
  return n;
}

namespace {

LiuMove boids_common(const LiuUav& self, std::span<const LiuUav> others, const TpmLookup* tpm,
                     const LiuParams& params) {
  const std::vector<std::size_t> nn = nearest_neighbours(self.position, others, params);
  Vec2 separation{}, mean_velocity{}, centroid{};
  for (const std::size_t i : nn) {
    const Vec2 away = self.position - others[i].position;
    const double d = norm(away);
    if (d > 0.0 && d < params.boids_safe_distance_m) {
      separation = separation + away * (1.0 / d);
    }
    mean_velocity = mean_velocity + others[i].velocity;
    centroid = centroid + others[i].position;
  }
  Vec2 desired{};
  if (!nn.empty()) {
    const double inv = 1.0 / static_cast<double>(nn.size());
    desired = unit_or_zero(separation) * params.boids_separation_weight +
              unit_or_zero(mean_velocity * inv) * params.boids_alignment_weight +
              unit_or_zero(centroid * inv - self.position) * params.boids_cohesion_weight;
  }
  if (tpm != nullptr) {
    const std::optional<Cell> guide =
        most_probable_neighbour(cell_of(self.position, params), self.velocity, *tpm);
    if (guide) {
      desired = desired + unit_or_zero(cell_centre(*guide, params.cell_size_m) - self.position) *
                              params.boids_guidance_weight;
    }
  }
  const Vec2 v = norm(desired) < kTiny ? clip_speed(self.velocity, params.max_speed_mps)
                                       : unit_or_zero(desired) * params.max_speed_mps;
  return grid_move(self.position, v, params);
}

}  // namespace

LiuMove boids_step(const LiuUav& self, std::span<const LiuUav> others, const LiuParams& params) {
  return boids_common(self, others, nullptr, params);
}

LiuMove boids_guided_step(const LiuUav& self, std::span<const LiuUav> others, const TpmLookup& tpm,
                          const LiuParams& params) {
  return boids_common(self, others, &tpm, params);
}

// ---------------------------------------------------------------------------
// Metrics
// ---------------------------------------------------------------------------

VisitedCells::VisitedCells(int32_t w, int32_t h)
    : w_(std::max(w, 0)), h_(std::max(h, 0)), seen_(static_cast<std::size_t>(w_) * static_cast<std::size_t>(h_), 0) {}

bool VisitedCells::visit(Cell c) {
  if (c.x < 0 || c.y < 0 || c.x >= w_ || c.y >= h_) {
    return false;
  }
  uint8_t& s = seen_[static_cast<std::size_t>(c.y) * static_cast<std::size_t>(w_) + static_cast<std::size_t>(c.x)];
  if (s != 0) {
    return false;
  }
  s = 1;
  ++count_;
  return true;
}

bool VisitedCells::visited(Cell c) const {
  return c.x >= 0 && c.y >= 0 && c.x < w_ && c.y < h_ &&
         seen_[static_cast<std::size_t>(c.y) * static_cast<std::size_t>(w_) + static_cast<std::size_t>(c.x)] != 0;
}

}  // namespace pheromesh::core
