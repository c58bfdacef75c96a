// The Ravankar 2016 policy (docs/policies/ravankar.md): uncertainty-aware
// pheromone deposition by leaders, trail following with rejection below δ·P0
// and Ravankar 2016 Table 2 speeds by followers, evaporation toward the ambient level at
// the place agents. The pure paper code is in ravankar.{hpp,cpp}.
//
// Frames: a UAV's belief and its true pose are in metres, x along the map's
// columns and y along its rows, cell c covering [c·s, (c+1)·s) (s =
// cell_size_m); the UAV state reports cell units with the cell centre at an
// integer (x_cell = x_m / s - 0.5).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <utility>

#include "pheromesh/core/angles.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/rng.hpp"
#include "pheromesh/ravankar/policy.hpp"

namespace pheromesh::core {

namespace {

constexpr double kPi = std::numbers::pi;
// Turn rate of our UAVs [rad/s] (the paper's robots' limits are not given):
// a larger heading change is made on the spot first.
constexpr double kMaxTurnRateRadPerS = kPi / 2.0;
// A waypoint counts as reached when the estimate is this close [cell].
constexpr double kArriveCells = 0.05;
// An exploring follower turns by up to ± this each tick [rad] (correlated random walk, ours).
constexpr double kExploreTurnRad = kPi / 4.0;

double wrap_pi(double a) { return std::remainder(a, 2.0 * kPi); }

// Standard normal from two uniforms (Box-Muller, one of the pair used), so the
// draws depend only on the UAV's own stream.
double gaussian(Rng& rng) {
  const double u1 = 1.0 - rng.uniform01();  // (0, 1]
  const double u2 = rng.uniform01();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}

Eigen::Vector2d centre_m(Cell c, double s) { return {(c.x + 0.5) * s, (c.y + 0.5) * s}; }

const std::vector<Cell> kRing1{{1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}, {-1, -1}, {0, -1}, {1, -1}};
constexpr int32_t kFollowerSearchRings = 2;  // [cell] outermost ring a follower searches

class RavankarUav final : public UavPolicy {
 public:
  RavankarUav(const ScenarioConfig& s, const MapGeometry& geo, uint32_t id)
      : c_(&s.config_of<RavankarConfig>()), geo_(&geo), id_(id), rng_(stream_seed(s.seed, "ravankar-uav", id)) {
    leader_ = id < c_->leaders;
    if (!leader_) {
      start_tick_ = static_cast<uint64_t>(id - c_->leaders + 1) * c_->follower_delay_ticks;
    }
    const double sz = c_->cell_size_m;
    const Eigen::Vector2d p = centre_m(start_cell(s, id), sz);
    double heading = 0.0;
    if (!c_->route.empty()) {
      const Eigen::Vector2d to = centre_m(c_->route.front(), sz) - p;
      if (to.squaredNorm() > 0.0) heading = wrap_two_pi(std::atan2(to.y(), to.x()));
    }
    // Both robots start at a known "anchor": zero uncertainty (paper, Ravankar 2016 Fig. 16).
    truth_ = {p.x(), p.y(), heading};
    belief_.mean = truth_;
    belief_.covariance.setZero();
    explore_heading_ = heading;
    trail_heading_ = heading;
    last_trail_position_ = p;
  }

  void step(const UavView& view, UavActions& out) override {
    const Eigen::Vector2d before = truth_.head<2>();
    if (view.tick > 0) {
      if (leader_) {
        lead();
      } else {
        follow(view);
      }
      fix(view.tick);
    }
    if ((leader_ || c_->followers_deposit) && view.tick % c_->deposit_every_ticks == 0) deposit(out);
    set_state_from_metres(out.state, truth_.x(), truth_.y(), before.x(), before.y(), c_->cell_size_m, heading_);
    out.state.role = static_cast<uint8_t>(leader_ ? Role::Leader : Role::Follower);
  }

  [[nodiscard]] Cell cell() const override { return ravankar_cell_of(truth_.head<2>(), c_->cell_size_m); }

 private:
  // The leaders fly the route on their ESTIMATED position: with a poor
  // estimate they fly (and deposit) somewhere else than they think.
  void lead() {
    const double s = c_->cell_size_m;
    while (next_waypoint_ < c_->route.size() &&
           (centre_m(c_->route[next_waypoint_], s) - belief_.mean.head<2>()).norm() <= kArriveCells * s) {
      ++next_waypoint_;
    }
    if (next_waypoint_ >= c_->route.size()) return;  // at the end of the route: stay
    drive_to(centre_m(c_->route[next_waypoint_], s), c_->leader_speed_mps);
  }

  void follow(const UavView& view) {
    if (view.tick < start_tick_) {
      mode_ = RavankarFollowerMode::Waiting;
      return;
    }
    const double s = c_->cell_size_m;
    const Cell at = ravankar_cell_of(belief_.mean.head<2>(), s);
    visited_.insert({at.x, at.y});
    const auto value = [&view](Cell c) -> std::optional<float> { return view.tiles->value(0, c); };
    const auto visited = [this](Cell c) { return visited_.contains({c.x, c.y}); };
    const double threshold = c_->follower.delta * c_->follower.reference_deposit;

    // Keep going to the cell chosen before while it is still a trail.
    if (mode_ == RavankarFollowerMode::Following && !(target_ == at)) {
      const double v = value(target_).value_or(0.0F);
      if (v >= threshold) {
        sensed_ = v;
        drive_to(centre_m(target_, s), ravankar_speed(sensed_, c_->follower));
        note_trail_heading();
        return;
      }
    }
    const RavankarChoice choice = ravankar_follower_choice(at, value, visited, c_->follower);
    const bool was_on_trail = mode_ == RavankarFollowerMode::Following || mode_ == RavankarFollowerMode::Holding;
    mode_ = choice.mode;
    sensed_ = choice.sensed;
    switch (choice.mode) {
      case RavankarFollowerMode::Following:
        target_ = choice.target;
        drive_to(centre_m(target_, s), ravankar_speed(sensed_, c_->follower));  // Ravankar 2016 Table 2
        note_trail_heading();
        return;
      case RavankarFollowerMode::Holding:
      case RavankarFollowerMode::Waiting:
        return;
      case RavankarFollowerMode::Exploring:
        // The tick the trail is rejected: the retreat variant turns the walk
        // back along the trail; the paper's policy (onward) keeps its heading.
        if (was_on_trail && c_->reject_explore == RavankarConfig::RejectExplore::Retreat) {
          explore_heading_ = ravankar_reject_heading(trail_heading_, c_->reject_explore);
        }
        explore();
        return;
    }
  }

  // The heading of the follower's estimate after a move along the trail
  // (a turn on the spot does not count: it is not yet a direction of travel).
  void note_trail_heading() {
    const Eigen::Vector2d p = belief_.mean.head<2>();
    if ((p - last_trail_position_).norm() > 1e-9) trail_heading_ = belief_.mean.z();
    last_trail_position_ = p;
  }

  // The trail was rejected: a correlated random walk at explore_speed (ours;
  // the paper's follower "carries its own exploration"), turned back toward
  // the map centre when the next step would leave the map (by its estimate).
  void explore() {
    const double s = c_->cell_size_m;
    explore_heading_ = wrap_two_pi(explore_heading_ + (2.0 * rng_.uniform01() - 1.0) * kExploreTurnRad);
    const double stride = c_->explore_speed_mps * c_->dt_s;
    const Eigen::Vector2d here = belief_.mean.head<2>();
    const Eigen::Vector2d dir(std::cos(explore_heading_), std::sin(explore_heading_));
    const Eigen::Vector2d ahead = here + dir * std::max(stride, s);
    const bool inside = ahead.x() >= 0.0 && ahead.y() >= 0.0 && ahead.x() < geo_->width() * s &&
                        ahead.y() < geo_->height() * s;
    if (!inside) {
      const Eigen::Vector2d to_centre = Eigen::Vector2d(geo_->width() * s, geo_->height() * s) / 2.0 - here;
      explore_heading_ = wrap_two_pi(std::atan2(to_centre.y(), to_centre.x()));
    }
    const Eigen::Vector2d goal = here + Eigen::Vector2d(std::cos(explore_heading_), std::sin(explore_heading_)) * stride;
    drive_to(goal, c_->explore_speed_mps);
  }

  // One tick of differential-drive motion toward `goal_m` (estimate frame) at
  // `speed`: turn on the spot while the heading error exceeds what one tick
  // of turning allows, else move min(speed·dt, distance) on an arc that ends
  // facing the goal (β = heading error, Ravankar 2016 eq. (27)).
  void drive_to(const Eigen::Vector2d& goal_m, double speed_mps) {
    const Eigen::Vector2d to = goal_m - belief_.mean.head<2>();
    const double dist = to.norm();
    if (dist <= 0.0) return;
    const double diff = wrap_pi(std::atan2(to.y(), to.x()) - belief_.mean.z());
    const double max_turn = kMaxTurnRateRadPerS * c_->dt_s;
    double beta = diff;
    double travel = std::min(speed_mps * c_->dt_s, dist);
    if (std::abs(diff) > max_turn) {
      beta = std::copysign(max_turn, diff);
      travel = 0.0;
    }
    const double w = c_->motion.wheel_separation_m;
    move_wheels(travel - 0.5 * beta * w, travel + 0.5 * beta * w);  // β = (r - l) / W_r, Ravankar 2016 eq. (27)
  }

  // Commanded wheel travels l, r [m]. The wheels slip: each actually travels
  // its command plus N(0, k·|command|) (the noise the belief assumes), so the
  // true pose drifts from the estimate, which predicts with the commands
  // (Ravankar 2016 eq. (3), Ravankar 2016 eq. (4), Ravankar 2016 eq. (27), Ravankar 2016 eq. (28), Ravankar 2016 eq. (29), Ravankar 2016 eq. (30), Ravankar 2016 eq. (31), Ravankar 2016 eq. (32), Ravankar 2016 eq. (33)).
  void move_wheels(double l, double r) {
    const double k = c_->motion.wheel_noise_m2_per_m;
    const double nl = gaussian(rng_) * std::sqrt(k * std::abs(l));
    const double nr = gaussian(rng_) * std::sqrt(k * std::abs(r));
    truth_ = ravankar_motion(truth_, l + nl, r + nr, c_->motion.wheel_separation_m);
    // The true position stays over the map (its border is a wall).
    const double s = c_->cell_size_m;
    const double eps = 1e-9 * s;
    truth_.x() = std::clamp(truth_.x(), 0.0, geo_->width() * s - eps);
    truth_.y() = std::clamp(truth_.y(), 0.0, geo_->height() * s - eps);
    belief_ = ravankar_predict(belief_, l, r, c_->motion);
  }

  // A position fix every fix_every_ticks while the true position is in
  // fix_area: z = true position + N(0, σ²) per axis, EKF correction.
  void fix(uint32_t tick) {
    if (c_->fix_every_ticks == 0 || tick % c_->fix_every_ticks != 0) return;
    if (c_->fix_area && !c_->fix_area->contains(cell())) return;
    const double sigma = c_->fix_sigma_m;
    const Eigen::Vector2d z(truth_.x() + sigma * gaussian(rng_), truth_.y() + sigma * gaussian(rng_));
    belief_ = ravankar_correct(belief_, z, Eigen::Matrix2d::Identity() * sigma * sigma);
  }

  // Ravankar 2016 eq. (11), Ravankar 2016 eq. (12), Ravankar 2016 eq. (13), Ravankar 2016 eq. (14): the cell under the estimated position and
  // Σ_xy go to every region within z_rng of that cell; each place agent
  // spreads γ over its own cells.
  void deposit(UavActions& out) {
    const double s = c_->cell_size_m;
    const Cell at = ravankar_cell_of(belief_.mean.head<2>(), s);
    if (!geo_->in_map(at)) return;  // the UAV believes it is off the map: nothing to mark
    const Eigen::Matrix2d sxy = ravankar_position_covariance(belief_.covariance);
    DepositMsg d;
    d.kind = static_cast<uint8_t>(DepositKind::Ellipse);
    d.layer = 0;
    d.cell = at;
    d.spread = {static_cast<float>(sxy(0, 0)), static_cast<float>(sxy(0, 1)), static_cast<float>(sxy(1, 1))};
    // Float rounding must not make Σ_xy indefinite (check_deposit).
    const double limit = std::sqrt(static_cast<double>(d.spread[0]) * d.spread[2]);
    if (std::abs(static_cast<double>(d.spread[1])) > limit) d.spread[1] = static_cast<float>(std::copysign(limit, d.spread[1]));
    Eigen::Matrix2d sent;
    sent << d.spread[0], d.spread[1], d.spread[1], d.spread[2];
    d.amount = static_cast<float>(ravankar_deposit_amount(sent, c_->deposit));  // γ, Ravankar 2016 eq. (12): informative
    for (RegionId r : geo_->regions_within(at, c_->deposit.sensor_range_m / s)) {
      d.region = r;
      out.deposits.push_back(d);
    }
  }

  const RavankarConfig* c_;
  const MapGeometry* geo_;
  uint32_t id_;
  Rng rng_;
  bool leader_ = false;
  uint64_t start_tick_ = 0;
  Eigen::Vector3d truth_ = Eigen::Vector3d::Zero();  // [m, m, rad]
  RavankarBelief belief_;
  std::size_t next_waypoint_ = 0;
  RavankarFollowerMode mode_ = RavankarFollowerMode::Waiting;
  Cell target_{};
  double sensed_ = 0.0;
  double explore_heading_ = 0.0;  // [rad]
  double trail_heading_ = 0.0;    // [rad] direction of the last move along the trail (estimate)
  Eigen::Vector2d last_trail_position_ = Eigen::Vector2d::Zero();
  std::set<std::pair<int32_t, int32_t>> visited_;
  uint8_t heading_ = 0;
};

class RavankarPlace final : public PlaceModel {
 public:
  RavankarPlace(const ScenarioConfig& s, const MapGeometry& geo, RegionId region)
      : c_(&s.config_of<RavankarConfig>()), region_(region), rect_(geo.region_rect(region)), field_(rect_, s.config_of<RavankarConfig>().deposit.max_deposit) {}

  std::optional<std::string> apply(const DepositMsg& d, uint32_t /*tick*/, std::vector<TargetEventMsg>& /*events*/) override {
    if (static_cast<DepositKind>(d.kind) != DepositKind::Ellipse) {
      return "deposit kind " + std::to_string(d.kind) + " is not used by the Ravankar policy";
    }
    const double s = c_->cell_size_m;
    Eigen::Matrix2d sigma;
    sigma << d.spread[0], d.spread[1], d.spread[1], d.spread[2];
    // Only the cells of this region within z_rng of the footprint centre.
    const auto reach = static_cast<int32_t>(std::ceil(c_->deposit.sensor_range_m / s));
    const int32_t x0 = std::max(rect_.x0, d.cell.x - reach);
    const int32_t y0 = std::max(rect_.y0, d.cell.y - reach);
    const int32_t x1 = std::min(rect_.x0 + rect_.w, d.cell.x + reach + 1);
    const int32_t y1 = std::min(rect_.y0 + rect_.h, d.cell.y + reach + 1);
    if (x0 >= x1 || y0 >= y1) return std::nullopt;  // nothing of the footprint lands here
    // Ravankar 2016 eq. (12), Ravankar 2016 eq. (14); the field adds up to the cap (Ravankar 2016 Fig. 26(b)).
    field_.add(ravankar_spread(centre_m(d.cell, s), sigma, {x0, y0, x1 - x0, y1 - y0}, c_->deposit));
    return std::nullopt;
  }

  HaloRing begin_step(uint32_t /*tick*/, std::vector<TargetEventMsg>& /*events*/) override {
    return HaloRing{region_, {}, {}};  // no diffusion in the paper
  }
  void accept_halo(const Rect& /*neighbour_rect*/, const HaloRing& /*ring*/) override {}
  // Ravankar 2016 eq. (22) over one tick: P <- P_a + (P - P_a)·e^(-K·dt).
  void finish_step() override { field_.evaporate(c_->dt_s, c_->evaporation); }
  [[nodiscard]] float value(int /*layer*/, Cell c) const override {
    return static_cast<float>(field_.value(c).value_or(0.0));
  }

 private:
  const RavankarConfig* c_;
  RegionId region_;
  Rect rect_;
  RavankarField field_;
};

}  // namespace

RavankarChoice ravankar_follower_choice(Cell at, const std::function<std::optional<float>(Cell)>& value,
                                        const std::function<bool(Cell)>& visited, const RavankarFollowerParams& p) {
  RavankarChoice out;
  // Ring 1 (the 8 neighbours), then ring 2: a follower that overshot a bend
  // of the trail (its next trail cell already visited) finds it again.
  std::vector<Cell> ring2;
  for (int32_t dy = -kFollowerSearchRings; dy <= kFollowerSearchRings; ++dy) {
    for (int32_t dx = -kFollowerSearchRings; dx <= kFollowerSearchRings; ++dx) {
      if (std::max(std::abs(dx), std::abs(dy)) == kFollowerSearchRings) ring2.push_back({dx, dy});
    }
  }
  for (const std::vector<Cell>* ring : {&kRing1, static_cast<const std::vector<Cell>*>(&ring2)}) {
    bool found = false;
    double best = 0.0;
    for (const Cell& o : *ring) {
      const Cell n{at.x + o.x, at.y + o.y};
      if (visited(n)) continue;
      const double v = value(n).value_or(0.0F);
      if (!found || v > best) {
        found = true;
        best = v;
        out.target = n;
      }
    }
    // Ravankar 2016 eq. (24): a trail below δ·P0 is rejected.
    if (found && ravankar_follows(best, p)) {
      out.mode = RavankarFollowerMode::Following;
      out.sensed = best;
      return out;
    }
  }
  const double here = value(at).value_or(0.0F);
  out.target = at;
  out.sensed = here;
  out.mode = ravankar_follows(here, p) ? RavankarFollowerMode::Holding : RavankarFollowerMode::Exploring;
  return out;
}

double ravankar_reject_heading(double heading_rad, RavankarConfig::RejectExplore mode) {
  return wrap_two_pi(mode == RavankarConfig::RejectExplore::Retreat ? heading_rad + kPi : heading_rad);
}

PolicyTraits ravankar_traits(const ScenarioConfig& s) {
  PolicyTraits t;
  t.layers = {"pheromone"};
  const RavankarConfig& c = s.config_of<RavankarConfig>();
  const double range_cells = c.deposit.sensor_range_m / c.cell_size_m;
  t.sensor_radius = range_cells;
  // A follower reads the 8 neighbours of the cell under its estimate, which
  // lies near its true cell: the tiles within z_rng + 1 cell.
  t.view_radius = std::ceil(range_cells) + 1.0;
  t.reads_neighbours = false;  // the pheromone trail only
  // The faster of the two speeds for one tick, four times for the wheel
  // noise and the position fixes (measured: at most 1.08 cells at 0.5 m/s) [cell/tick].
  t.max_step = 4.0 * std::max(c.leader_speed_mps, c.explore_speed_mps) * c.dt_s / c.cell_size_m;
  return t;
}

std::unique_ptr<UavPolicy> make_ravankar_uav(const ScenarioConfig& s, const MapGeometry& geo, const World& /*world*/,
                                             uint32_t id) {
  return std::make_unique<RavankarUav>(s, geo, id);
}

std::unique_ptr<PlaceModel> make_ravankar_place(const ScenarioConfig& s, const MapGeometry& geo, RegionId region) {
  return std::make_unique<RavankarPlace>(s, geo, region);
}

std::map<std::string, double> ravankar_field_summary(const ScenarioConfig& s, const FieldLookup& value) {
  const RavankarConfig& c = s.config_of<RavankarConfig>();
  const double threshold = c.follower.delta * c.follower.reference_deposit;
  double total = 0.0;
  double max = 0.0;
  double above = 0.0;
  for (int32_t y = 0; y < s.height; ++y) {
    for (int32_t x = 0; x < s.width; ++x) {
      const double v = value(0, {x, y});
      total += v;
      max = std::max(max, v);
      if (v >= threshold) above += 1.0;
    }
  }
  return {{"pheromone_total", total}, {"cells_at_or_above_threshold", above}, {"pheromone_max", max}};
}

}  // namespace pheromesh::core
