// Shao 2020 ACO direction choice, Shao 2020 Sec. 4.2, Shao 2020 eq. (9), Shao 2020 eq. (10), Shao 2020 eq. (11) and Shao 2020 Algorithm 1
// lines 10-11.
//
// Interpretations (the paper leaves these open):
//  * Sectors. A cell c != pos within the sensor radius (Euclidean, <= SD)
//    belongs to the sector of the heading whose angle is within ±22.5° of the
//    bearing from pos to c. A bearing exactly on a boundary goes to the sector
//    counter-clockwise of it (sector = floor((bearing + 22.5°) / 45°) mod 8).
//    No integer offset lies exactly on a boundary (tan 22.5° is irrational),
//    so the rule only fixes the definition. Cells in the three rear sectors
//    are not used. Only cells whose pheromones the UAV knows count; a sector
//    without a known cell has means 0.
//  * Attractiveness floor. λTh < 0, so λTa·τ + λTh·ε + λTr·σ can be <= 0 and
//    its α-th power undefined. The base is clamped to kAttractivenessFloor:
//    P stays defined and a sector dominated by obstacle pheromone ranks last.
//  * Accessibility. J_ik holds the candidates whose next cell is not
//    view.blocked(); LocalView::blocked reports cells outside the map too.
//    A view without a `blocked` (or `pheromones`) function blocks (knows) nothing.
//  * Shao 2020 eq. (9) is evaluated in log space (a softmax of α·ln a + β·ln η), which
//    equals the quotient of powers but cannot underflow for large α or β.
#include "pheromesh/shao/aco.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <deque>
#include <numbers>
#include <vector>

namespace pheromesh::core {

namespace {

constexpr double kAttractivenessFloor = 1e-6;
constexpr double kTieTolerance = 1e-12;
constexpr int kMaxTurn = 2;  // ±90°, Shao 2020 eq. (10)

// Sector (heading index 0..7) of the bearing of offset (dx, dy) != (0, 0).
int sector_of(int32_t dx, int32_t dy) {
  constexpr double kEighth = std::numbers::pi / 4.0;
  const double bearing = std::atan2(static_cast<double>(dy), static_cast<double>(dx));  // (-π, π]
  const auto s = static_cast<int>(std::floor((bearing + kEighth / 2.0) / kEighth));
  return ((s % kHeadingCount) + kHeadingCount) % kHeadingCount;
}

struct SectorSums {
  double tau = 0.0, eps = 0.0, sigma = 0.0;
  int count = 0;
};

// Sums of known pheromone values per sector over the sensor disk around pos.
std::array<SectorSums, kHeadingCount> sector_sums(Cell pos, const LocalView& view, double radius) {
  std::array<SectorSums, kHeadingCount> sums{};
  if (!view.pheromones || !(radius >= 1.0)) {
    return sums;
  }
  // A sensor radius beyond any sane map is capped so the loop stays bounded.
  const auto r = static_cast<int32_t>(std::floor(std::min(radius, 4096.0)));
  const double r2 = radius * radius;
  for (int32_t dy = -r; dy <= r; ++dy) {
    for (int32_t dx = -r; dx <= r; ++dx) {
      if ((dx == 0 && dy == 0) || static_cast<double>(dx * dx + dy * dy) > r2) {
        continue;
      }
      const auto v = view.pheromones(Cell{pos.x + dx, pos.y + dy});
      if (!v) {
        continue;
      }
      SectorSums& s = sums[static_cast<std::size_t>(sector_of(dx, dy))];
      s.tau += static_cast<double>((*v)[0]);
      s.eps += static_cast<double>((*v)[1]);
      s.sigma += static_cast<double>((*v)[2]);
      ++s.count;
    }
  }
  return sums;
}

// Normalises weights given as logarithms over the accessible candidates:
// out[i] = exp(w[i]) / Σ exp(w[j]); 0 for inaccessible candidates.
void softmax_accessible(const std::array<double, 5>& log_w, std::array<Candidate, 5>& cands,
                        double Candidate::*out) {
  double max_w = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < cands.size(); ++i) {
    if (cands[i].accessible) {
      max_w = std::max(max_w, log_w[i]);
    }
  }
  if (!std::isfinite(max_w)) {
    return;  // nothing accessible (or degenerate weights): all stay 0
  }
  double sum = 0.0;
  std::array<double, 5> w{};
  for (std::size_t i = 0; i < cands.size(); ++i) {
    if (cands[i].accessible) {
      w[i] = std::exp(log_w[i] - max_w);
      sum += w[i];
    }
  }
  for (std::size_t i = 0; i < cands.size(); ++i) {
    cands[i].*out = w[i] / sum;
  }
}

}  // namespace

// Shao 2020 eq. (11): η_ij = 1.4 for D_ij = 1, 1 for D_ij = √2, 0 otherwise.
double eta_distance(int32_t d2) {
  switch (d2) {
    case 1:
      return 1.4;
    case 2:
      return 1.0;
    default:
      return 0.0;
  }
}

// Shao 2020 eq. (10): η_ijk = (1/4, 5/24, 1/6)·η_ij for θ = 0°, 45°, 90°.
double eta_turn(int abs_turn_eighths) {
  switch (abs_turn_eighths) {
    case 0:
      return 1.0 / 4.0;
    case 1:
      return 5.0 / 24.0;
    case 2:
      return 1.0 / 6.0;
    default:
      return 0.0;
  }
}

std::array<Candidate, 5> evaluate_candidates(Cell pos, Heading heading, const LocalView& view,
                                             const ShaoAcoParams& p) {
  const auto sums = sector_sums(pos, view, p.sensor_radius);

  std::array<Candidate, 5> cands{};
  std::array<double, 5> log_info{};
  std::array<double, 5> log_random{};
  for (int turn = -kMaxTurn; turn <= kMaxTurn; ++turn) {
    const auto i = static_cast<std::size_t>(turn + kMaxTurn);
    Candidate& c = cands[i];
    c.turn_eighths = turn;
    c.heading = rotate(heading, turn);
    const Cell step = step_of(c.heading);
    c.next = Cell{pos.x + step.x, pos.y + step.y};
    c.accessible = !(view.blocked && view.blocked(c.next));
    c.eta = eta_turn(std::abs(turn)) * eta_distance(step.x * step.x + step.y * step.y);  // Shao 2020 eq. (10), Shao 2020 eq. (11)

    const SectorSums& s = sums[static_cast<std::size_t>(c.heading)];
    if (s.count > 0) {
      c.tau = s.tau / s.count;
      c.eps = s.eps / s.count;
      c.sigma = s.sigma / s.count;
    }
    const double base = p.lambda_target * c.tau + p.lambda_obstacle * c.eps + p.lambda_path * c.sigma;
    c.attractiveness = std::isnan(base) ? kAttractivenessFloor : std::max(base, kAttractivenessFloor);

    // Shao 2020 eq. (9) numerator, and the physical-costs-only weight of the random
    // sub-group, both as logarithms (η > 0 for every turn of -2..2).
    log_info[i] = p.alpha * std::log(c.attractiveness) + p.beta * std::log(c.eta);
    log_random[i] = p.beta * std::log(c.eta);
  }
  softmax_accessible(log_info, cands, &Candidate::probability);
  softmax_accessible(log_random, cands, &Candidate::random_probability);
  return cands;
}

// Random-stream consumption, in this order, for every call:
//  1. rng.uniform01() decides the sub-group (always drawn);
//  2. if at least one candidate is accessible, exactly one more call:
//     information group: rng.uniform_below(number of tied maxima), made even
//     when there is a single maximum; random group: rng.uniform01() for the
//     roulette wheel.
// Nothing more is drawn when no candidate is accessible.
Decision decide(Cell pos, Heading heading, const LocalView& view, const ShaoAcoParams& p, Rng& rng) {
  const auto cands = evaluate_candidates(pos, heading, view, p);
  Decision d;
  d.random_group = rng.uniform01() < p.random_fraction;

  std::vector<std::size_t> accessible;
  for (std::size_t i = 0; i < cands.size(); ++i) {
    if (cands[i].accessible) {
      accessible.push_back(i);
    }
  }
  if (accessible.empty()) {
    return d;  // the caller decides what to do (e.g. turn back)
  }

  if (!d.random_group) {
    // Shao 2020 Algorithm 1 line 11: the information sub-group selects the maximum.
    double best = -1.0;
    for (const std::size_t i : accessible) {
      best = std::max(best, cands[i].probability);
    }
    std::vector<std::size_t> ties;
    for (const std::size_t i : accessible) {
      if (cands[i].probability >= best - kTieTolerance) {
        ties.push_back(i);
      }
    }
    const uint32_t k = rng.uniform_below(static_cast<uint32_t>(ties.size()));
    d.chosen = cands[ties[k]];
    return d;
  }

  // Random sub-group: roulette wheel over physical costs only.
  const double u = rng.uniform01();
  double cumulative = 0.0;
  for (const std::size_t i : accessible) {
    cumulative += cands[i].random_probability;
    if (u < cumulative) {
      d.chosen = cands[i];
      return d;
    }
  }
  d.chosen = cands[accessible.back()];  // rounding left u just above the total
  return d;
}

namespace {

constexpr int32_t kUnreached = -1;

// 8-connected breadth-first distances from `from` over unblocked cells of a
// width x height map; stops as soon as `done(cell)` holds for a settled cell
// (returned) or every reachable cell is settled (nullopt).
std::optional<Cell> breadth_first(Cell from, int32_t width, int32_t height, const std::function<bool(Cell)>& blocked,
                                  std::vector<int32_t>& dist, const std::function<bool(Cell)>& done) {
  const auto idx = [width](Cell c) {
    return static_cast<std::size_t>(c.y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(c.x);
  };
  dist.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), kUnreached);
  std::deque<Cell> queue{from};
  dist[idx(from)] = 0;
  while (!queue.empty()) {
    const Cell c = queue.front();
    queue.pop_front();
    if (done(c)) return c;
    for (int h = 0; h < kHeadingCount; ++h) {
      const Cell st = step_of(static_cast<Heading>(h));
      const Cell n{c.x + st.x, c.y + st.y};
      if (n.x < 0 || n.y < 0 || n.x >= width || n.y >= height || dist[idx(n)] != kUnreached || blocked(n)) continue;
      dist[idx(n)] = dist[idx(c)] + 1;
      queue.push_back(n);
    }
  }
  return std::nullopt;
}

}  // namespace

int32_t coverage_gain(Cell next, const VisitedMap& m, double sd) {
  if (!(sd >= 0.0)) return 0;
  const auto r = static_cast<int32_t>(std::floor(std::min(sd, 4096.0)));
  int32_t gain = 0;
  for (int32_t dy = -r; dy <= r; ++dy) {
    for (int32_t dx = -r; dx <= r; ++dx) {
      const Cell c{next.x + dx, next.y + dy};
      if (static_cast<double>(dx * dx + dy * dy) <= sd * sd && m.in_map(c) && !m.is_visited(c)) ++gain;
    }
  }
  return gain;
}

std::optional<std::size_t> coverage_candidate(Cell pos, Heading heading, const VisitedMap& m, double sd,
                                              const std::function<bool(Cell)>& blocked) {
  std::optional<std::size_t> best;
  int32_t best_gain = 0;
  // Candidates in order of |turn| (0, -1, 1, -2, 2): the first strict maximum wins ties.
  for (const int turn : {0, -1, 1, -2, 2}) {
    const Cell st = step_of(rotate(heading, turn));
    const Cell next{pos.x + st.x, pos.y + st.y};
    if (!m.in_map(next) || blocked(next)) continue;
    const int32_t g = coverage_gain(next, m, sd);
    if (g > best_gain) {
      best = static_cast<std::size_t>(turn + kMaxTurn);
      best_gain = g;
    }
  }
  return best;
}

std::optional<Cell> nearest_unvisited(Cell pos, const VisitedMap& m, const std::function<bool(Cell)>& blocked) {
  if (!m.in_map(pos) || m.visited.size() != static_cast<std::size_t>(m.width) * static_cast<std::size_t>(m.height)) {
    return std::nullopt;
  }
  std::vector<int32_t> dist;
  return breadth_first(pos, m.width, m.height, blocked, dist, [&m](Cell c) { return !m.is_visited(c); });
}

std::optional<std::size_t> frontier_candidate(Cell pos, Heading heading, Cell goal, int32_t width, int32_t height,
                                              const std::function<bool(Cell)>& blocked) {
  if (goal.x < 0 || goal.y < 0 || goal.x >= width || goal.y >= height) return std::nullopt;
  std::array<Cell, 5> next{};
  for (int turn = -kMaxTurn; turn <= kMaxTurn; ++turn) {
    const Cell st = step_of(rotate(heading, turn));
    next[static_cast<std::size_t>(turn + kMaxTurn)] = Cell{pos.x + st.x, pos.y + st.y};
  }
  const auto usable = [&](Cell c) { return c.x >= 0 && c.y >= 0 && c.x < width && c.y < height && !blocked(c); };
  // Distances from the goal, searched until every usable candidate is settled.
  std::vector<int32_t> dist;
  const auto idx = [width](Cell c) {
    return static_cast<std::size_t>(c.y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(c.x);
  };
  std::size_t wanted = 0;
  for (const Cell& c : next) wanted += usable(c) ? 1U : 0U;
  std::size_t settled = 0;
  breadth_first(goal, width, height, blocked, dist, [&](Cell c) {
    for (const Cell& n : next) {
      if (n.x == c.x && n.y == c.y && usable(n)) ++settled;
    }
    return settled >= wanted;
  });
  std::optional<std::size_t> best;
  int32_t best_dist = 0;
  // Candidates in order of |turn| (0, -1, 1, -2, 2): the first strict minimum wins ties.
  for (const std::size_t i : {std::size_t{2}, std::size_t{1}, std::size_t{3}, std::size_t{0}, std::size_t{4}}) {
    if (!usable(next[i])) continue;
    const int32_t d = dist[idx(next[i])];
    if (d == kUnreached) continue;
    if (!best || d < best_dist) {
      best = i;
      best_dist = d;
    }
  }
  return best;
}

}  // namespace pheromesh::core
