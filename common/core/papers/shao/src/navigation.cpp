// Shao 2020 Sec. 5, navigation via flocking and stigmergy (Shao 2020 eq. (12), Shao 2020 eq. (13), Shao 2020 eq. (14), Shao 2020 eq. (15), Shao 2020 eq. (16), Shao 2020 eq. (17), Shao 2020 eq. (18), Shao 2020 eq. (19), Shao 2020 eq. (20), Shao 2020 eq. (21), Shao 2020 eq. (22), Shao 2020 eq. (23), Shao 2020 eq. (24),
// Shao 2020 Algorithm 2 and Shao 2020 Algorithm 3). The text of the paper is mangled around the equations;
// this is our reading of each, and every choice the paper leaves open.
//
// Leader (Shao 2020 Sec. 5.1.1):
//  * Shao 2020 eq. (12): τ_ij = (τ(i) - τ(j))/‖q_i^L - q_j‖ · (q_i^L - q_j)/‖q_i^L - q_j‖,
//    i.e. (τ(i) - τ(j))·(q_i^L - q_j)/‖q_i^L - q_j‖². Its norm is
//    |τ(i) - τ(j)|/‖q_i^L - q_j‖, as the paper says. Sign: (τ(i) - τ(j))(q_i - q_j)
//    = (τ(j) - τ(i))(q_j - q_i), so τ_ij points TOWARDS j when j holds more
//    pheromone: the printed formula already points up the gradient, which is
//    what Shao 2020 eq. (14) needs (λTa > 0 attracts to targets, λTh < 0 repels from
//    obstacles, λTr > 0 attracts to cells with more path pheromone, i.e. less
//    recently visited). We use it as printed, for all three layers (ε_d and
//    σ_d "are defined similar").
//  * q_i^L is the leader's continuous position; i, "the ith point", is the
//    lattice point nearest to it (std::lround), whose pheromones are τ(i).
//    J(d), Shao 2020 eq. (13): lattice points j with 0 < ‖q^L - q_j‖ <= sensorLD whose
//    bearing from q^L falls in sector d, and whose pheromones the leader
//    knows (unknown or non-finite cells are skipped). If τ(i) is unknown the
//    leader has no reference and does not move.
//  * Sectors (Shao 2020 Fig. 8 is not readable): eight 45° sectors centred on the
//    compass headings E, NE, ..., SE (Heading order), as the ACO of Shao 2020 Sec. 4 uses.
//  * "s_t = max_d s_d^t": the maximum of vectors, read by default as the s_d
//    of largest Euclidean norm (the strongest weighted gradient, whichever way
//    it points); VectorSectorChoice::Projection reads it as the s_d of largest
//    component along its own sector's bisector (shao-fig10 flies both:
//    docs/policies/shao-navigation.md). Ties (within 1e-12 relative) go to the
//    lowest Heading index.
//    All s_d = 0 (flat or unknown field): no direction, the leader stays
//    (v = 0); Shao 2020 Algorithm 2 lists v_t^L as an input but Shao 2020 eq. (15) never uses it.
//    Consequence of "max over sectors": on a smooth field s_d ≈ Σ_j (∇τ·u_j)u_j
//    over the sector's unit bearings u_j, which lies near the sector's axis,
//    so v points within a few degrees of one of the eight headings, not
//    along the gradient itself.
//  * Shao 2020 eq. (15): v_{t+1} = ρ s/‖s‖, q_{t+1} = q_t + v_{t+1}; the speed is
//    always ρ = 2 [cell/tick] and the position is continuous.
//  * Scalar leader (Shao 2020 Fig. 10b, not specified in the paper; our baseline): per
//    sector the mean over J(d) of λTa τ_j + λTh ε_j + λTr σ_j (the same
//    fusion as Shao 2020 eq. (9) of Shao 2020 Sec. 4), the sector of the largest mean wins (ties to
//    the lowest index; sectors without a known cell take no part), and the
//    leader moves ρ along that sector's bisector. ScalarSectorScore (sum,
//    max) and ScalarLeaderStep (one lattice step per iteration, as the UAVs
//    of Shao 2020 Sec. 4 move) are the other readings shao-fig10 flies.
//    On a flat field (every sector's score equal) the scalar leader moves
//    along the lowest index (E) where the vector leader stays: a float
//    target pheromone below ~1e-16 of the path term λTr σ0 is flat to it.
//  * Shao 2020 Algorithm 2 lines 1-4: once the centre is within sensorLD (inclusive)
//    the leader "goes there" at speed at most ρ (Shao 2020 eq. (15)'s speed), and becomes
//    a follower on the tick it arrives. The paper does not say how fast "go
//    there" is.
//
// Followers (Shao 2020 Sec. 5.1.2):
//  * Shao 2020 eq. (17): N_k = {j != k follower : ‖q_k - q_j‖ < r} (strict), the
//    leader not included; the follower always knows the leader's state.
//  * Shao 2020 eq. (18): ‖z‖_σ, evaluated as ‖z‖²/(1 + √(1 + ε‖z‖²)), the same value
//    without the cancellation of √(1 + ε‖z‖²) - 1 for small z.
//  * Shao 2020 eq. (21): n_kj = (q_j - q_k)/√(1 + ε‖q_j - q_k‖²) with the Euclidean norm
//    under the root, as in Olfati-Saber (2006) (it is ∇‖·‖_σ); the mangled
//    text may carry a σ subscript there. Direction: see NeighbourGradient.
//    A neighbour at distance 0 has no direction and φα(0) = ∞: it adds
//    nothing to the gradient term (it still counts in the consensus term).
//  * Shao 2020 eq. (22): a_kj = ρh(‖q_j - q_k‖_σ / r_σ) with r_σ = ‖r‖_σ by default
//    (Olfati-Saber), or / r as printed; see AdjacencyScale.
//  * Shao 2020 eq. (23): ρh(z) = 1 on [0, h), ½(1 + cos(π(z - h)/(1 - h))) on [h, 1),
//    0 otherwise (the cosine is 0 at z = 1, so [h, 1] is the same function).
//  * Shao 2020 eq. (19) is a velocity, not an acceleration: the paper names its left
//    side "the velocity vector after updating" and Shao 2020 eq. (24) adds it to the
//    position, q_{t+1} = q_t + v_{t+1}, although it calls c1 and c2 weights of
//    "the follower's acceleration". v_{t+1} is the right-hand side itself
//    (not v_t plus it), and is not clamped (the paper gives no speed limit).
//    With the leader alone and v_L constant this settles with v_k = v_L,
//    trailing the leader by v_L/c1 (3.3 cells at ρ = 2).
#include "pheromesh/shao/navigation.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>

namespace pheromesh::core {

namespace {

// A sensor radius beyond any sane map is capped so the cell loops stay bounded.
constexpr double kMaxRadius = 4096.0;
// Positions beyond this [cell] are rejected rather than cast to int32_t.
constexpr double kMaxCoordinate = 1e9;
constexpr double kTieTolerance = 1e-12;

bool usable_position(const Eigen::Vector2d& q) { return q.allFinite() && q.cwiseAbs().maxCoeff() < kMaxCoordinate; }

Eigen::Vector2d point_of(Cell c) { return {static_cast<double>(c.x), static_cast<double>(c.y)}; }

Cell nearest_cell(const Eigen::Vector2d& q) {
  return Cell{static_cast<int32_t>(std::lround(q.x())), static_cast<int32_t>(std::lround(q.y()))};
}

// Known, finite pheromones of c as doubles.
std::optional<Eigen::Vector3d> known(const PheromoneLookup& pheromones, Cell c) {
  const auto v = pheromones(c);
  if (!v) {
    return std::nullopt;
  }
  const Eigen::Vector3d d{static_cast<double>((*v)[0]), static_cast<double>((*v)[1]), static_cast<double>((*v)[2])};
  if (!d.allFinite()) {
    return std::nullopt;
  }
  return d;
}

Eigen::Vector3d lambdas(const ShaoNavParams& p) { return {p.lambda_target, p.lambda_obstacle, p.lambda_path}; }

// Calls f(cell, offset q_j - q) for every lattice point j with
// 0 < ‖q_j - q‖ <= radius.
template <typename F>
void for_each_cell_in_disk(const Eigen::Vector2d& q, double radius, F&& f) {
  if (!(radius > 0.0)) {
    return;
  }
  const double r = std::min(radius, kMaxRadius);
  const double r2 = r * r;
  const auto x0 = static_cast<int32_t>(std::ceil(q.x() - r));
  const auto x1 = static_cast<int32_t>(std::floor(q.x() + r));
  const auto y0 = static_cast<int32_t>(std::ceil(q.y() - r));
  const auto y1 = static_cast<int32_t>(std::floor(q.y() + r));
  for (int32_t y = y0; y <= y1; ++y) {
    for (int32_t x = x0; x <= x1; ++x) {
      const Cell c{x, y};
      const Eigen::Vector2d offset = point_of(c) - q;
      const double d2 = offset.squaredNorm();
      if (d2 > 0.0 && d2 <= r2) {
        f(c, offset);
      }
    }
  }
}

// Index of the largest score among eligible sectors, ties to the lowest index.
std::optional<std::size_t> best_sector(const std::array<double, kNavSectorCount>& score,
                                       const std::array<bool, kNavSectorCount>& eligible) {
  std::optional<double> best;
  for (std::size_t d = 0; d < score.size(); ++d) {
    if (eligible[d] && (!best || score[d] > *best)) {
      best = score[d];
    }
  }
  if (!best) {
    return std::nullopt;
  }
  const double tol = kTieTolerance * std::max(1.0, std::abs(*best));
  for (std::size_t d = 0; d < score.size(); ++d) {
    if (eligible[d] && score[d] >= *best - tol) {
      return d;
    }
  }
  return std::nullopt;  // unreachable: the maximum itself qualifies
}

}  // namespace

Heading nav_sector_of(const Eigen::Vector2d& offset) {
  constexpr double kEighth = std::numbers::pi / 4.0;
  const double bearing = std::atan2(offset.y(), offset.x());  // (-π, π]
  const auto s = static_cast<int>(std::floor((bearing + kEighth / 2.0) / kEighth));
  return static_cast<Heading>(((s % kNavSectorCount) + kNavSectorCount) % kNavSectorCount);
}

double sigma_norm(const Eigen::Vector2d& z, double epsilon) {
  const double n2 = z.squaredNorm();
  return n2 / (1.0 + std::sqrt(1.0 + epsilon * n2));  // = (√(1 + ε‖z‖²) - 1)/ε
}

double bump(double z, double h) {
  if (z >= 0.0 && z < h) {
    return 1.0;
  }
  if (z >= h && z < 1.0) {
    return 0.5 * (1.0 + std::cos(std::numbers::pi * (z - h) / (1.0 - h)));
  }
  return 0.0;
}

double phi_alpha(double z) { return 1.0 / z; }

namespace {

// Σ_{j∈J(d)} of Shao 2020 eq. (12) per sector and layer (Shao 2020 eq. (13)), weighted into
// s_d by Shao 2020 eq. (14). False if τ(i) is unknown (no reference value).
bool sector_vectors(const Eigen::Vector2d& q, const PheromoneLookup& pheromones, const ShaoNavParams& p,
                    LeaderStep& s) {
  const auto own = known(pheromones, nearest_cell(q));
  if (!own) {
    return false;
  }
  std::array<std::array<Eigen::Vector2d, 3>, kNavSectorCount> layer_sums;
  for (auto& sector : layer_sums) {
    sector.fill(Eigen::Vector2d::Zero());
  }
  for_each_cell_in_disk(q, p.leader_sensor_radius, [&](Cell c, const Eigen::Vector2d& to_j) {
    const auto val = known(pheromones, c);
    if (!val) {
      return;
    }
    const auto d = static_cast<std::size_t>(nav_sector_of(to_j));
    const Eigen::Vector2d from_j = -to_j;  // q_i^L - q_j
    const double d2 = from_j.squaredNorm();
    for (Eigen::Index l = 0; l < 3; ++l) {
      layer_sums[d][static_cast<std::size_t>(l)] += ((*own)(l) - (*val)(l)) / d2 * from_j;  // Shao 2020 eq. (12)
    }
    ++s.sector_cells[d];
  });
  const Eigen::Vector3d lam = lambdas(p);
  for (std::size_t d = 0; d < kNavSectorCount; ++d) {
    s.sector_sums[d] = lam(0) * layer_sums[d][0] + lam(1) * layer_sums[d][1] + lam(2) * layer_sums[d][2];  // Shao 2020 eq. (14)
  }
  return true;
}

Eigen::Vector2d bisector(std::size_t d) {
  const double angle = heading_angle(static_cast<Heading>(d));
  return {std::cos(angle), std::sin(angle)};
}

}  // namespace

LeaderStep leader_vector_step(const Eigen::Vector2d& q, const PheromoneLookup& pheromones, const ShaoNavParams& p) {
  LeaderStep s;
  s.q = q;
  if (!usable_position(q) || !pheromones || !sector_vectors(q, pheromones, p, s)) {
    return s;
  }
  std::array<bool, kNavSectorCount> eligible{};
  for (std::size_t d = 0; d < kNavSectorCount; ++d) {
    const double norm = s.sector_sums[d].norm();
    s.sector_scores[d] = p.vector_choice == VectorSectorChoice::Norm ? norm : s.sector_sums[d].dot(bisector(d));
    // A zero s_d has no direction for Shao 2020 eq. (15); under Projection a sector whose
    // s_d points back out of it (score <= 0) is no candidate either.
    eligible[d] = norm > 0.0 && s.sector_scores[d] > 0.0 && std::isfinite(s.sector_scores[d]);
  }
  const auto best = best_sector(s.sector_scores, eligible);
  if (!best) {
    return s;
  }
  s.sector = static_cast<Heading>(*best);
  s.v = p.rho * s.sector_sums[*best] / s.sector_sums[*best].norm();  // Shao 2020 eq. (15)
  s.q = q + s.v;
  return s;
}

LeaderStep leader_gradient_step(const Eigen::Vector2d& q, const PheromoneLookup& pheromones, const ShaoNavParams& p) {
  LeaderStep s;
  s.q = q;
  if (!usable_position(q) || !pheromones || !sector_vectors(q, pheromones, p, s)) {
    return s;
  }
  Eigen::Vector2d total = Eigen::Vector2d::Zero();
  for (std::size_t d = 0; d < kNavSectorCount; ++d) {
    s.sector_scores[d] = s.sector_sums[d].norm();
    total += s.sector_sums[d];
  }
  const double norm = total.norm();
  if (!(norm > 0.0) || !std::isfinite(norm)) {
    return s;  // flat or unknown field: stay, as the vector leader does
  }
  s.v = p.rho * total / norm;  // the speed of Shao 2020 eq. (15)
  s.q = q + s.v;
  return s;
}

LeaderStep leader_pull_step(const Eigen::Vector2d& q, const PheromoneLookup& pheromones, const ShaoNavParams& p) {
  LeaderStep s;
  s.q = q;
  if (!usable_position(q) || !pheromones || !sector_vectors(q, pheromones, p, s)) {
    return s;
  }
  Eigen::Vector2d total = Eigen::Vector2d::Zero();
  for (std::size_t d = 0; d < kNavSectorCount; ++d) {
    s.sector_scores[d] = s.sector_sums[d].dot(bisector(d));
    if (s.sector_scores[d] > 0.0 && std::isfinite(s.sector_scores[d])) {
      total += s.sector_sums[d];
    }
  }
  const double norm = total.norm();
  if (!(norm > 0.0) || !std::isfinite(norm)) {
    return s;  // nothing pulls: stay
  }
  s.v = p.rho * total / norm;  // the speed of Shao 2020 eq. (15)
  s.q = q + s.v;
  return s;
}

LeaderStep leader_scalar_step(const Eigen::Vector2d& q, const PheromoneLookup& pheromones,
                              const ShaoNavParams& p) {
  LeaderStep s;
  s.q = q;
  if (!usable_position(q) || !pheromones) {
    return s;
  }
  const Eigen::Vector3d lam = lambdas(p);
  std::array<double, kNavSectorCount> sums{};
  std::array<double, kNavSectorCount> maxima{};
  for_each_cell_in_disk(q, p.leader_sensor_radius, [&](Cell c, const Eigen::Vector2d& to_j) {
    const auto val = known(pheromones, c);
    if (!val) {
      return;
    }
    const auto d = static_cast<std::size_t>(nav_sector_of(to_j));
    const double w = lam.dot(*val);  // the fusion of Shao 2020 eq. (9)
    sums[d] += w;
    maxima[d] = s.sector_cells[d] == 0 ? w : std::max(maxima[d], w);
    ++s.sector_cells[d];
  });
  std::array<bool, kNavSectorCount> eligible{};
  for (std::size_t d = 0; d < kNavSectorCount; ++d) {
    eligible[d] = s.sector_cells[d] > 0;
    if (!eligible[d]) {
      continue;
    }
    switch (p.scalar_score) {
      case ScalarSectorScore::Mean:
        s.sector_scores[d] = sums[d] / s.sector_cells[d];
        break;
      case ScalarSectorScore::Sum:
        s.sector_scores[d] = sums[d];
        break;
      case ScalarSectorScore::Max:
        s.sector_scores[d] = maxima[d];
        break;
    }
  }
  const auto best = best_sector(s.sector_scores, eligible);
  if (!best) {
    return s;
  }
  s.sector = static_cast<Heading>(*best);
  // A lattice step is 1 cell on an axis and √2 on a diagonal (odd Heading index).
  const double speed = p.scalar_step == ScalarLeaderStep::Rho ? p.rho : (*best % 2 == 0 ? 1.0 : std::numbers::sqrt2);
  s.v = speed * bisector(*best);
  s.q = q + s.v;
  return s;
}

bool leader_reaches_centre(const Eigen::Vector2d& q, const Eigen::Vector2d& centre, const ShaoNavParams& p) {
  return (centre - q).norm() <= p.leader_sensor_radius;  // false for non-finite input
}

LeaderStep leader_algorithm2_step(const Eigen::Vector2d& q, const Eigen::Vector2d& centre,
                                  const PheromoneLookup& pheromones, const ShaoNavParams& p,
                                  LeaderPheromones kind) {
  if (!leader_reaches_centre(q, centre, p)) {
    switch (kind) {
      case LeaderPheromones::Scalar:
        return leader_scalar_step(q, pheromones, p);
      case LeaderPheromones::Gradient:
        return leader_gradient_step(q, pheromones, p);
      case LeaderPheromones::Pull:
        return leader_pull_step(q, pheromones, p);
      case LeaderPheromones::Vector:
        break;
    }
    return leader_vector_step(q, pheromones, p);
  }
  // Shao 2020 Algorithm 2 lines 1-4: go there, at most ρ per tick.
  LeaderStep s;
  s.heading_to_centre = true;
  const Eigen::Vector2d to_centre = centre - q;
  const double dist = to_centre.norm();
  if (dist <= p.rho) {
    s.v = to_centre;
    s.q = centre;
    s.at_centre = true;
  } else {
    s.v = p.rho * to_centre / dist;
    s.q = q + s.v;
  }
  return s;
}

FollowerStep follower_step(const FollowerState& self, std::span<const FollowerState> others,
                           const FollowerState& leader, const ShaoNavParams& p) {
  FollowerStep s;
  const double r_scale = p.adjacency_scale == AdjacencyScale::SigmaRange
                             ? sigma_norm(Eigen::Vector2d{p.follower_range, 0.0}, p.epsilon)
                             : p.follower_range;
  const double sign = p.neighbour_gradient == NeighbourGradient::TowardsNeighbour ? 1.0 : -1.0;
  for (const FollowerState& other : others) {
    if (!other.q.allFinite() || !other.v.allFinite()) {
      continue;  // a corrupt neighbour state is ignored, not propagated
    }
    const Eigen::Vector2d d = other.q - self.q;  // q_j - q_k
    const double dist = d.norm();
    if (!(dist < p.follower_range)) {
      continue;  // Shao 2020 eq. (17)
    }
    ++s.neighbour_count;
    const double z = sigma_norm(d, p.epsilon);
    if (dist > 0.0) {
      const Eigen::Vector2d n = d / std::sqrt(1.0 + p.epsilon * dist * dist);  // Shao 2020 eq. (21)
      s.gradient += sign * phi_alpha(z) * n;                                    // Shao 2020 eq. (20)
    }
    const double a = bump(z / r_scale, p.h);  // Shao 2020 eq. (22), Shao 2020 eq. (23)
    s.consensus += a * (other.v - self.v);
  }
  s.leader = -p.c1 * (self.q - leader.q) - p.c2 * (self.v - leader.v);
  s.v = s.gradient + s.consensus + s.leader;  // Shao 2020 eq. (19)
  s.q = self.q + s.v;                         // Shao 2020 eq. (24)
  return s;
}

}  // namespace pheromesh::core
