// Ravankar 2016 uncertainty-aware pheromone deposition (see pheromesh/ravankar/model.hpp).
#include "pheromesh/ravankar/model.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include <Eigen/LU>

#include "pheromesh/core/angles.hpp"

namespace pheromesh::core {

namespace {

// sinc(x) = sin x / x and its derivative, stable near 0 (Taylor terms).
double sinc(double x) { return std::abs(x) < 1e-4 ? 1.0 - x * x / 6.0 : std::sin(x) / x; }
double sinc_derivative(double x) {
  if (std::abs(x) < 1e-3) {
    return -x / 3.0 + x * x * x / 30.0;
  }
  return (x * std::cos(x) - std::sin(x)) / (x * x);
}

// Mean of the differential-drive step and its Jacobians. The arc of
// Ravankar 2016 eq. (29), Ravankar 2016 eq. (30), Ravankar 2016 eq. (31) written as a chord: the robot moves c = d·sinc(β/2) along
// the mid heading φ = θ + β/2 (d = (l + r)/2). This equals the arc for every
// β and Ravankar 2016 eq. (33) at β = 0, without a branch.
struct MotionStep {
  Eigen::Vector3d next;
  Eigen::Matrix3d g;              // ∂(x', y', θ') / ∂(x, y, θ)
  Eigen::Matrix<double, 3, 2> v;  // ∂(x', y', θ') / ∂(l, r)
};

MotionStep motion_step(const Eigen::Vector3d& pose, double l, double r, double w) {
  const double d = 0.5 * (l + r);
  const double beta = (r - l) / w;                 // Ravankar 2016 eq. (27)
  const double phi = pose.z() + 0.5 * beta;
  const double s = sinc(0.5 * beta);
  const double c = d * s;                          // chord length [m]
  const double cp = std::cos(phi);
  const double sp = std::sin(phi);

  MotionStep m;
  m.next = {pose.x() + c * cp, pose.y() + c * sp, wrap_two_pi(pose.z() + beta)};  // Ravankar 2016 eq. (30), Ravankar 2016 eq. (31), Ravankar 2016 eq. (32), Ravankar 2016 eq. (33)

  m.g.setIdentity();
  m.g(0, 2) = -c * sp;
  m.g(1, 2) = c * cp;

  // ∂/∂d and ∂/∂β, then chained to (l, r): ∂d/∂l = ∂d/∂r = 1/2, ∂β/∂l = -1/W, ∂β/∂r = 1/W.
  const double dc_dbeta = 0.5 * d * sinc_derivative(0.5 * beta);
  const Eigen::Vector3d by_d(s * cp, s * sp, 0.0);
  const Eigen::Vector3d by_beta(dc_dbeta * cp - 0.5 * c * sp, dc_dbeta * sp + 0.5 * c * cp, 1.0);
  m.v.col(0) = 0.5 * by_d - by_beta / w;
  m.v.col(1) = 0.5 * by_d + by_beta / w;
  return m;
}

// Exponent q = u²/a1² + v²/a2² of Ravankar 2016 eq. (14); a zero axis admits only 0 along it.
double exponent(double u, double v, double a1, double a2) {
  auto term = [](double x, double a) {
    if (x == 0.0) {
      return 0.0;
    }
    if (a <= 0.0) {
      return std::numeric_limits<double>::infinity();
    }
    return (x * x) / (a * a);
  };
  return term(u, a1) + term(v, a2);
}

std::pair<double, double> axes_of(const RavankarEllipse& e, RavankarAxes axes) {
  if (axes == RavankarAxes::StdDev) {
    return {std::sqrt(e.lambda1), std::sqrt(e.lambda2)};
  }
  return {e.lambda1, e.lambda2};
}

}  // namespace

// --- belief ------------------------------------------------------------------

Eigen::Vector3d ravankar_motion(const Eigen::Vector3d& pose, double left_m, double right_m, double wheel_separation_m) {
  return motion_step(pose, left_m, right_m, wheel_separation_m).next;
}

RavankarBelief ravankar_predict(const RavankarBelief& b, double left_m, double right_m, const RavankarMotionParams& p) {
  const MotionStep m = motion_step(b.mean, left_m, right_m, p.wheel_separation_m);
  Eigen::Matrix2d noise = Eigen::Matrix2d::Zero();
  noise(0, 0) = p.wheel_noise_m2_per_m * std::abs(left_m);
  noise(1, 1) = p.wheel_noise_m2_per_m * std::abs(right_m);
  RavankarBelief out;
  out.mean = m.next;
  out.covariance = m.g * b.covariance * m.g.transpose() + m.v * noise * m.v.transpose();  // Ravankar 2016 eq. (4), EKF prediction
  out.covariance = 0.5 * (out.covariance + out.covariance.transpose());
  return out;
}

RavankarBelief ravankar_correct(const RavankarBelief& b, const Eigen::Vector2d& z, const Eigen::Matrix2d& r) {
  const Eigen::Matrix2d s = b.covariance.topLeftCorner<2, 2>() + r;  // H Σ Hᵀ + R
  const double det = s.determinant();
  if (!(det > 0.0) || !std::isfinite(det)) {
    return b;
  }
  const Eigen::Matrix<double, 3, 2> k = b.covariance.leftCols<2>() * s.inverse();
  RavankarBelief out;
  out.mean = b.mean + k * (z - b.mean.head<2>());
  out.mean.z() = wrap_two_pi(out.mean.z());
  Eigen::Matrix3d ikh = Eigen::Matrix3d::Identity();
  ikh.leftCols<2>() -= k;
  out.covariance = ikh * b.covariance;
  out.covariance = 0.5 * (out.covariance + out.covariance.transpose());
  return out;
}

Eigen::Matrix2d ravankar_position_covariance(const Eigen::Matrix3d& sigma) {
  // Ravankar 2016 eq. (11). (Ravankar 2016 eq. (9) prints σ_x² at (2,1); it is σ_xy.)
  Eigen::Matrix2d s = sigma.topLeftCorner<2, 2>();
  s(0, 1) = s(1, 0) = 0.5 * (sigma(0, 1) + sigma(1, 0));
  return s;
}

RavankarEllipse ravankar_error_ellipse(const Eigen::Matrix2d& sigma_xy) {
  const double a = sigma_xy(0, 0);
  const double c = sigma_xy(1, 1);
  const double b = 0.5 * (sigma_xy(0, 1) + sigma_xy(1, 0));
  const double mean = 0.5 * (a + c);
  const double half_diff = 0.5 * (a - c);
  const double rad = std::sqrt(half_diff * half_diff + b * b);
  RavankarEllipse e;
  e.lambda1 = std::max(mean + rad, 0.0);
  e.lambda2 = std::max(mean - rad, 0.0);
  e.angle_rad = 0.5 * std::atan2(2.0 * b, a - c);
  return e;
}

// --- deposit -------------------------------------------------------------------

double ravankar_deposit_amount(const Eigen::Matrix2d& sigma_xy, const RavankarDepositParams& p) {
  const RavankarEllipse e = ravankar_error_ellipse(sigma_xy);
  const double product = e.lambda1 * e.lambda2;
  if (!(product > 0.0)) {
    return p.max_deposit;
  }
  return std::min(p.tau / product, p.max_deposit);  // Ravankar 2016 eq. (12), capped
}

Cell ravankar_cell_of(const Eigen::Vector2d& position_m, double cell_size_m) {
  auto to_cell = [](double v) {
    constexpr double lo = static_cast<double>(std::numeric_limits<int32_t>::min());
    constexpr double hi = static_cast<double>(std::numeric_limits<int32_t>::max());
    if (std::isnan(v)) {
      return int32_t{0};
    }
    return static_cast<int32_t>(std::clamp(std::floor(v), lo, hi));
  };
  return {to_cell(position_m.x() / cell_size_m), to_cell(position_m.y() / cell_size_m)};
}

RavankarDeposit ravankar_spread(const Eigen::Vector2d& position_m, const Eigen::Matrix2d& sigma_xy, const Rect& rect,
                                const RavankarDepositParams& p) {
  RavankarDeposit out;
  out.rect = rect;
  out.amounts.assign(static_cast<std::size_t>(std::max<int64_t>(rect.area(), 0)), 0.0);
  out.gamma = ravankar_deposit_amount(sigma_xy, p);
  out.centre = ravankar_cell_of(position_m, p.cell_size_m);

  const RavankarEllipse e = ravankar_error_ellipse(sigma_xy);
  const auto [a1, a2] = axes_of(e, p.axes);
  const double ca = std::cos(e.angle_rad);
  const double sa = std::sin(e.angle_rad);
  const double s = p.cell_size_m;
  const double range2 = p.sensor_range_m * p.sensor_range_m;

  // e^(-q) at the centre of the cell (dx, dy) cells away from the centre cell; 0 out of range.
  // a1, a2 captured by copy: clang before 16 cannot capture structured
  // bindings (the fuzz tree, docs/fuzzing.md, is built with clang 14).
  auto weight = [&, a1 = a1, a2 = a2](int64_t dx, int64_t dy) {
    const double ox = static_cast<double>(dx) * s;
    const double oy = static_cast<double>(dy) * s;
    if (ox * ox + oy * oy > range2) {
      return 0.0;
    }
    const double u = ca * ox + sa * oy;   // along v1
    const double v = -sa * ox + ca * oy;  // along v2
    return std::exp(-exponent(u, v, a1, a2));  // Ravankar 2016 eq. (14)
  };

  double scale = out.gamma;
  if (p.spread == RavankarSpread::Total) {
    const auto reach = static_cast<int64_t>(std::ceil(p.sensor_range_m / s));
    double sum = 0.0;
    for (int64_t dy = -reach; dy <= reach; ++dy) {
      for (int64_t dx = -reach; dx <= reach; ++dx) {
        sum += weight(dx, dy);
      }
    }
    scale = sum > 0.0 ? out.gamma / sum : 0.0;  // sum >= 1: the centre weighs e^0
  }

  std::size_t i = 0;
  for (int32_t y = rect.y0; y < rect.y0 + rect.h; ++y) {
    for (int32_t x = rect.x0; x < rect.x0 + rect.w; ++x) {
      out.amounts[i++] = scale * weight(int64_t{x} - out.centre.x, int64_t{y} - out.centre.y);
    }
  }
  return out;
}

Eigen::Vector2d ravankar_gradient(const Eigen::Vector2d& offset_m, double gamma, const RavankarEllipse& e,
                                  const RavankarDepositParams& p) {
  if (offset_m.squaredNorm() > p.sensor_range_m * p.sensor_range_m) {
    return Eigen::Vector2d::Zero();
  }
  const auto [a1, a2] = axes_of(e, p.axes);
  const double ca = std::cos(e.angle_rad);
  const double sa = std::sin(e.angle_rad);
  const double u = ca * offset_m.x() + sa * offset_m.y();
  const double v = -sa * offset_m.x() + ca * offset_m.y();
  const double value = gamma * std::exp(-exponent(u, v, a1, a2));
  // Ravankar 2016 eq. (16) in the ellipse axes: -2γ e^(-q) (u/a1², v/a2²).
  const double gu = (u == 0.0 || a1 <= 0.0) ? 0.0 : -2.0 * value * u / (a1 * a1);
  const double gv = (v == 0.0 || a2 <= 0.0) ? 0.0 : -2.0 * value * v / (a2 * a2);
  return {ca * gu - sa * gv, sa * gu + ca * gv};
}

// --- evaporation -----------------------------------------------------------------

double ravankar_evaporate(double p, double ambient, double k_per_s, double dt_s) {
  return ambient + (p - ambient) * std::exp(-k_per_s * dt_s);  // Ravankar 2016 eq. (22)
}

std::optional<double> ravankar_rate_constant(double p0, double ambient, double t_m_s, double p_tm) {
  const double ratio = (p_tm - ambient) / (p0 - ambient);
  if (!(t_m_s > 0.0) || !(ratio > 0.0) || !(ratio <= 1.0)) {
    return std::nullopt;
  }
  return -std::log(ratio) / t_m_s;  // Ravankar 2016 eq. (23)
}

std::optional<double> ravankar_time_to_level(double p0, double ambient, double k_per_s, double level) {
  const double ratio = (level - ambient) / (p0 - ambient);
  if (!(k_per_s > 0.0) || !(ratio > 0.0) || !(ratio <= 1.0)) {
    return std::nullopt;
  }
  return -std::log(ratio) / k_per_s;  // Ravankar 2016 eq. (24) solved for t
}

std::optional<double> ravankar_time_to_threshold(double p0, double ambient, double delta, double t_m_s, double p_tm) {
  const double num = (delta * p0 - ambient) / (p0 - ambient);
  const double den = (p_tm - ambient) / (p0 - ambient);
  if (!(t_m_s > 0.0) || !(num > 0.0) || !(num <= 1.0) || !(den > 0.0) || !(den < 1.0)) {
    return std::nullopt;
  }
  return t_m_s * std::log(num) / std::log(den);  // Ravankar 2016 eq. (26)
}

// --- field -----------------------------------------------------------------------

RavankarField::RavankarField(const Rect& rect, double cap)
    : rect_(rect), cap_(cap), v_(static_cast<std::size_t>(std::max<int64_t>(rect.area(), 0)), 0.0F) {}

std::optional<double> RavankarField::value(Cell c) const {
  if (!rect_.contains(c)) {
    return std::nullopt;
  }
  return v_[static_cast<std::size_t>(c.y - rect_.y0) * static_cast<std::size_t>(rect_.w) +
            static_cast<std::size_t>(c.x - rect_.x0)];
}

void RavankarField::add(const RavankarDeposit& d) {
  std::size_t i = 0;
  for (int32_t y = d.rect.y0; y < d.rect.y0 + d.rect.h; ++y) {
    for (int32_t x = d.rect.x0; x < d.rect.x0 + d.rect.w; ++x, ++i) {
      const double a = d.amounts[i];
      if (!rect_.contains({x, y}) || !std::isfinite(a) || a <= 0.0) {
        continue;
      }
      float& v = v_[static_cast<std::size_t>(y - rect_.y0) * static_cast<std::size_t>(rect_.w) +
                    static_cast<std::size_t>(x - rect_.x0)];
      v = static_cast<float>(std::min(static_cast<double>(v) + a, cap_));  // total capped, Ravankar 2016 Fig. 26(b)
    }
  }
}

void RavankarField::evaporate(double dt_s, const RavankarEvaporationParams& p) {
  if (!(dt_s > 0.0)) {
    return;
  }
  const double f = std::exp(-p.k_per_s * dt_s);
  for (float& v : v_) {
    if (static_cast<double>(v) > p.ambient) {
      v = static_cast<float>(p.ambient + (static_cast<double>(v) - p.ambient) * f);  // Ravankar 2016 eq. (22)
    }
  }
}

// --- followers ---------------------------------------------------------------------

bool ravankar_follows(double sensed, const RavankarFollowerParams& p) {
  return sensed >= p.delta * p.reference_deposit;  // below δ·P0 the trail is rejected
}

double ravankar_speed(double sensed, const RavankarFollowerParams& p) {
  for (const auto& band : p.speed_bands) {  // Ravankar 2016 Table 2, highest band first
    if (sensed >= band.min_pheromone) {
      return band.speed_mps;
    }
  }
  return p.speed_bands.back().speed_mps;
}

}  // namespace pheromesh::core
