// The Shostak & Petrenko GPS-denied stigmergy policy (Shostak 2024 Sec. 2, Shostak 2024 Sec. 3, Shostak 2024 Sec. 4, Shostak 2024 Sec. 5; the
// pure parts are in shostak.{hpp,cpp}, the choices in docs/policies/shostak.md).
//
// UAV (ShostakUav): knows only its own local frame (origin at its take-off
// cell, yaw fixed at take-off, Shostak 2024 Sec. 4.1) and a dead-reckoned pose in it. Each
// tick (one 0.2 s deposit period) it flies one step towards its waypoint,
// then deposits "explored" at the cell of its ESTIMATED position (Shostak 2024 eq. (1)),
// "hazard" +5 when an obstacle is within lidar range (Shostak 2024 Sec. 4.2), "target" +100
// and a TargetFound broadcast when it first sees a target (Shostak 2024 Sec. 5). Waypoints:
// the 0°/120°/240° dispersal leg (Shostak 2024 Sec. 5), then, each time one is reached, 20
// random candidates at 15 m (Shostak 2024 eq. (4)) scored φ^α·η^β from its tiles (eqs.
// (3), (5)) and drawn by roulette (Shostak 2024 eq. (6)); η prefers the bearing to a
// reported target, so the swarm converges on it (Shostak 2024 Sec. 4.3, Shostak 2024 Sec. 5).
//
// Place agent (ShostakPlace): the three capped layers of its region
// (ShostakLayers): deposits capped by Shostak 2024 eq. (1), evaporation by Shostak 2024 eq. (2) once per
// tick, no diffusion.
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <span>

#include "pheromesh/core/angles.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/rng.hpp"
#include "pheromesh/shostak/model.hpp"
#include "pheromesh/shostak/policy.hpp"

namespace pheromesh::core {

namespace {

using Vec3 = Eigen::Vector3d;

// Horizontal distance [m] from p to the cells of r (0 inside).
double distance_to_rect_m(const Vec3& p, const Rect& r, double cell_m) {
  const double x0 = r.x0 * cell_m;
  const double x1 = (r.x0 + r.w) * cell_m;
  const double y0 = r.y0 * cell_m;
  const double y1 = (r.y0 + r.h) * cell_m;
  const double dx = std::max({x0 - p.x(), 0.0, p.x() - x1});
  const double dy = std::max({y0 - p.y(), 0.0, p.y() - y1});
  return std::hypot(dx, dy);
}

// Centre of a map cell in map metres (z = 0).
Vec3 cell_centre_m(double x_cells, double y_cells, double cell_m) {
  return {(x_cells + 0.5) * cell_m, (y_cells + 0.5) * cell_m, 0.0};
}

class ShostakUav final : public UavPolicy {
 public:
  ShostakUav(const ScenarioConfig& s, const MapGeometry& geo, const World& world, uint32_t id)
      : s_(&s), cfg_(&s.config_of<ShostakConfig>()), geo_(&geo), world_(&world), id_(id), rng_(stream_seed(s.seed, "shostak-uav", id)) {
    const double cs = cfg_->layers.cell_size_m;
    const Cell c0 = start_cell(s, id);
    // Shostak 2024 Sec. 4.1: the local frame starts at the take-off point, on the ground.
    frame_.origin_world = cell_centre_m(c0.x, c0.y, cs);
    frame_.yaw_rad = id < cfg_->frame_yaw_rad.size() ? cfg_->frame_yaw_rad[id] : 0.0;
    est_.position_local = {0.0, 0.0, cfg_->altitude_m};
    true_world_ = shostak_local_to_world(frame_, est_.position_local);
    // Shostak 2024 Sec. 5: the dispersal leg at 2π·i/n in the UAV's own frame.
    heading_local_ = shostak_dispersal_heading(id, s.uavs);
    if (cfg_->dispersal_m > 0.0) waypoint_ = dispersal_waypoint();
  }

  void step(const UavView& view, UavActions& out) override {
    const Vec3 before = true_world_;
    if (view.tick > 0) {
      learn_targets(view.broadcasts);
      if (!waypoint_) decide(*view.tiles);
      if (waypoint_) fly();
    }
    sense_and_deposit(view, out);
    set_state_from_metres(out.state, true_world_.x(), true_world_.y(), before.x(), before.y(), cfg_->layers.cell_size_m,
                          heading_);
    out.state.role = static_cast<uint8_t>(Role::Searcher);
  }

  [[nodiscard]] Cell cell() const override {
    const Cell c = shostak_cell_of(true_world_, cfg_->layers.cell_size_m);
    return {std::clamp(c.x, 0, geo_->width() - 1), std::clamp(c.y, 0, geo_->height() - 1)};
  }

 private:
  // The dispersal waypoint, the leg shortened so that it ends on the map
  // (half a cell inside), as the UAV can tell from its own frame.
  [[nodiscard]] Vec3 dispersal_waypoint() const {
    const Vec3 start = est_.position_local;
    const uint32_t n = s_->uavs;
    double len = cfg_->dispersal_m;
    for (int k = 0; k < 64; ++k) {
      const Vec3 w = shostak_dispersal_waypoint(start, id_, n, len);
      if (in_map_m(shostak_local_to_world(frame_, w), 0.5)) return w;
      len *= 0.9;
    }
    return start;
  }

  [[nodiscard]] bool in_map_m(const Vec3& p, double margin_cells) const {
    const double cs = cfg_->layers.cell_size_m;
    const double m = margin_cells * cs;
    return p.x() >= m && p.y() >= m && p.x() <= geo_->width() * cs - m && p.y() <= geo_->height() * cs - m;
  }

  // Shostak 2024 Sec. 4.3 / Shostak 2024 Sec. 5: a TargetFound broadcast (x, y pairs in map cells). A report
  // within the detection radius of a known target is the same target.
  void learn_targets(std::span<const BroadcastMsg> broadcasts) {
    bool learned = false;
    for (const BroadcastMsg& b : broadcasts) {
      if (b.kind != static_cast<uint8_t>(BroadcastKind::TargetFound)) continue;
      for (std::size_t i = 0; i + 1 < b.values.size(); i += 2) {
        learned = remember_target(Eigen::Vector2d(b.values[i], b.values[i + 1])) || learned;
      }
    }
    // The others turn towards the target at once (Shostak 2024 Sec. 5: "start flying to the target").
    if (learned) waypoint_.reset();
  }

  bool remember_target(const Eigen::Vector2d& xy_cells) {
    const double merge = cfg_->detect_radius_m / cfg_->layers.cell_size_m;
    for (const auto& k : known_targets_) {
      if ((k - xy_cells).norm() <= merge) return false;
    }
    known_targets_.push_back(xy_cells);
    return true;
  }

  // Bearing [rad] in the local frame from the estimated position to the
  // nearest known target, or the current heading when none is known (our η,
  // ShostakAcoParams::eta_floor).
  [[nodiscard]] double preferred_azimuth_local() const {
    if (known_targets_.empty()) return heading_local_;
    const double cs = cfg_->layers.cell_size_m;
    const Vec3& p = est_.position_local;
    double best = std::numeric_limits<double>::infinity();
    double azimuth = heading_local_;
    for (const auto& t : known_targets_) {
      const Vec3 tl = shostak_world_to_local(frame_, cell_centre_m(t.x(), t.y(), cs));
      const double d = std::hypot(tl.x() - p.x(), tl.y() - p.y());
      if (d < best) {
        best = d;
        azimuth = std::atan2(tl.y() - p.y(), tl.x() - p.x());
      }
    }
    return azimuth;
  }

  // The nearest known target in the local frame (z = 0), or nullopt.
  [[nodiscard]] std::optional<Vec3> nearest_target_local() const {
    const double cs = cfg_->layers.cell_size_m;
    const Vec3& p = est_.position_local;
    std::optional<Vec3> best;
    double best_d = std::numeric_limits<double>::infinity();
    for (const auto& t : known_targets_) {
      const Vec3 tl = shostak_world_to_local(frame_, cell_centre_m(t.x(), t.y(), cs));
      const double d = std::hypot(tl.x() - p.x(), tl.y() - p.y());
      if (d < best_d) {
        best_d = d;
        best = tl;
      }
    }
    return best;
  }

  // Shostak 2024 Sec. 3.4, Shostak 2024 Sec. 3.5 in the UAV's own frame: candidates around the estimated
  // position (Shostak 2024 eq. (4)), each scored at the map cell it falls in (through the
  // frame) by Shostak 2024 eq. (3) and Shostak 2024 eq. (5), one drawn by Shostak 2024 eq. (6).
  void decide(const TileCache& tiles) {
    const double cs = cfg_->layers.cell_size_m;
    const ShostakLookup lookup = [&tiles](Cell c) -> std::optional<ShostakCellValues> {
      auto e = tiles.value(static_cast<int>(ShostakLayer::Explored), c);
      auto h = tiles.value(static_cast<int>(ShostakLayer::Hazard), c);
      auto t = tiles.value(static_cast<int>(ShostakLayer::Target), c);
      if (!e || !h || !t) return std::nullopt;
      return ShostakCellValues{*e, *h, *t};
    };
    // The shostak_beeline variant (ours): with a target known, straight to it.
    if (cfg_->converge == ShostakConfig::Converge::Beeline && !known_targets_.empty()) {
      if (const auto t = nearest_target_local()) {
        waypoint_ = shostak_beeline_waypoint(est_.position_local, *t, cfg_->aco.step_m);
        return;
      }
    }
    const double preferred = preferred_azimuth_local();
    const auto candidates = shostak_candidates(est_.position_local, cfg_->aco, rng_);
    std::vector<double> scores(candidates.size(), 0.0);
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      const auto v = lookup(shostak_cell_of(shostak_local_to_world(frame_, candidates[k].position), cs));
      if (!v) continue;  // unknown or off the map: never taken
      const double phi = shostak_attractiveness(*v, cfg_->attractiveness).phi;                  // Shostak 2024 eq. (3)
      scores[k] = shostak_score(phi, shostak_eta(candidates[k].azimuth_rad, preferred, cfg_->aco), cfg_->aco);  // Shostak 2024 eq. (5)
    }
    if (const auto k = shostak_roulette(scores, rng_)) {  // Shostak 2024 eq. (6)
      Vec3 w = candidates[*k].position;
      w.z() = std::clamp(w.z(), cfg_->min_altitude_m, cfg_->max_altitude_m);
      waypoint_ = w;
      return;
    }
    // No candidate on known cells (ours): one step back towards the take-off
    // point, which the UAV knows without any map.
    Vec3 back = -est_.position_local;
    back.z() = 0.0;
    if (back.norm() > 1e-9) {
      waypoint_ = est_.position_local + std::min(cfg_->aco.step_m, back.norm()) * back.normalized();
    }
  }

  // One tick of flight towards the waypoint at speed_mps. The autopilot steers
  // the ESTIMATED position; the true position moves by the commanded step and
  // the estimate by the same step through the drift model (Shostak 2024 Sec. 4.1, ours).
  void fly() {
    const Vec3 to = *waypoint_ - est_.position_local;
    const double step = cfg_->speed_mps * cfg_->dt_s;
    const bool reached = to.norm() <= step;
    const Vec3 cmd = reached ? to : Vec3(step * to.normalized());
    if (reached) waypoint_.reset();
    if (std::hypot(cmd.x(), cmd.y()) > 1e-9) heading_local_ = std::atan2(cmd.y(), cmd.x());
    const Vec3 moved = shostak_local_to_world(frame_, cmd) - shostak_local_to_world(frame_, Vec3::Zero());
    true_world_ += moved;
    // The true UAV stays over the map (it can only leave it through drift).
    const double cs = cfg_->layers.cell_size_m;
    constexpr double kInside = 1e-6;
    true_world_.x() = std::clamp(true_world_.x(), 0.0, geo_->width() * cs - kInside);
    true_world_.y() = std::clamp(true_world_.y(), 0.0, geo_->height() * cs - kInside);
    est_ = shostak_drift_step(est_, cmd, cfg_->drift, rng_);
  }

  void add(ShostakLayer layer, Cell c, double amount, UavActions& out) const {
    out.deposits.push_back(layer_add(*geo_, static_cast<int>(layer), c, amount));
  }

  void sense_and_deposit(const UavView& view, UavActions& out) {
    const auto& lp = cfg_->layers;
    const double cs = lp.cell_size_m;
    const Vec3 est_world = shostak_local_to_world(frame_, est_.position_local);
    const Cell here = shostak_cell_of(est_world, cs);
    const bool here_in_map = geo_->in_map(here);
    // Shostak 2024 eq. (1): +Δτ per deposit instant k·0.2 s within this tick (one per
    // tick at dt = 0.2 s; the instant t = 0 at tick 0).
    const double t1 = view.tick * cfg_->dt_s;
    const uint32_t due = view.tick == 0 ? 1 : shostak_deposits_due(t1 - cfg_->dt_s, t1, lp.deposit_period_s);
    if (due > 0 && here_in_map) add(ShostakLayer::Explored, here, due * lp.explored_increment, out);
    // Shostak 2024 Sec. 4.2: the lidar flags an obstacle within range: +5 hazard at the current cell.
    const bool obstacle = std::any_of(s_->obstacles.begin(), s_->obstacles.end(), [&](const Rect& r) {
      return distance_to_rect_m(true_world_, r, cs) <= cfg_->lidar_range_m;
    });
    if (obstacle && here_in_map) add(ShostakLayer::Hazard, here, lp.hazard_increment, out);
    // Shostak 2024 Sec. 5: a target in the camera footprint: +100 target at its cell and, if
    // nobody has reported it yet, the TargetFound broadcast. The UAV places
    // the target through its own estimate: estimated position plus the
    // measured offset, turned by its heading error.
    std::set<int32_t> now_in_range;
    BroadcastMsg found;
    found.kind = static_cast<uint8_t>(BroadcastKind::TargetFound);
    const auto& targets = world_->targets();
    for (std::size_t i = 0; i < targets.size(); ++i) {
      const Vec3 tw = cell_centre_m(targets[i].x, targets[i].y, cs);
      if (std::hypot(tw.x() - true_world_.x(), tw.y() - true_world_.y()) > cfg_->detect_radius_m) continue;
      const auto idx = static_cast<int32_t>(i);
      now_in_range.insert(idx);
      if (targets_in_range_.contains(idx)) continue;
      out.detections.push_back({0, view.tick, idx, targets[i]});
      const Vec3 offset_local = shostak_world_to_local(frame_, tw) - shostak_world_to_local(frame_, true_world_);
      const double c = std::cos(est_.yaw_error_rad);
      const double sn = std::sin(est_.yaw_error_rad);
      const Vec3 seen_local = est_.position_local + Vec3(c * offset_local.x() - sn * offset_local.y(),
                                                         sn * offset_local.x() + c * offset_local.y(), 0.0);
      const Vec3 seen_world = shostak_local_to_world(frame_, seen_local);
      const Cell tc = shostak_cell_of(seen_world, cs);
      if (geo_->in_map(tc)) add(ShostakLayer::Target, tc, lp.target_increment, out);
      const Eigen::Vector2d xy{seen_world.x() / cs - 0.5, seen_world.y() / cs - 0.5};
      if (remember_target(xy) && found.values.size() + 2 <= kMaxBroadcastValues) {
        found.values.push_back(xy.x());
        found.values.push_back(xy.y());
      }
    }
    targets_in_range_ = std::move(now_in_range);
    if (!found.values.empty()) out.broadcast = std::move(found);
  }

  const ScenarioConfig* s_;
  const ShostakConfig* cfg_;
  const MapGeometry* geo_;
  const World* world_;
  uint32_t id_;
  Rng rng_;
  ShostakLocalFrame frame_;
  ShostakPoseEstimate est_;               // what the UAV believes, in its frame
  Vec3 true_world_ = Vec3::Zero();        // ground truth in map metres (sensors, state)
  std::optional<Vec3> waypoint_;          // local frame [m]
  double heading_local_ = 0.0;            // azimuth of the last move, local frame [rad]
  uint8_t heading_ = 0;                   // 0..7 of the state
  std::vector<Eigen::Vector2d> known_targets_;  // reported targets, map cells
  std::set<int32_t> targets_in_range_;
};

class ShostakPlace final : public PlaceModel {
 public:
  ShostakPlace(const ScenarioConfig& s, const MapGeometry& geo, RegionId region)
      : layers_(geo.region_rect(region), s.config_of<ShostakConfig>().layers), dt_s_(s.config_of<ShostakConfig>().dt_s) {}

  std::optional<std::string> apply(const DepositMsg& d, uint32_t /*tick*/, std::vector<TargetEventMsg>& /*events*/) override {
    if (static_cast<DepositKind>(d.kind) != DepositKind::LayerAdd) {
      return "deposit kind " + std::to_string(d.kind) + " is not used by the shostak policy";
    }
    if (d.layer >= kShostakLayerCount) return "unknown layer " + std::to_string(d.layer);
    // Shostak 2024 eq. (1): τ <- min(τ + amount, τmax of the layer).
    if (!layers_.deposit(static_cast<ShostakLayer>(d.layer), d.cell, d.amount)) {
      return std::string("deposit outside the region or with a negative amount");
    }
    return std::nullopt;
  }
  HaloRing begin_step(uint32_t /*tick*/, std::vector<TargetEventMsg>& /*events*/) override { return {}; }  // no diffusion
  void accept_halo(const Rect& /*neighbour_rect*/, const HaloRing& /*ring*/) override {}
  void finish_step() override { layers_.evaporate(dt_s_); }  // Shostak 2024 eq. (2): ·(1-ρ)^dt
  [[nodiscard]] float value(int layer, Cell c) const override {
    return layers_.value(static_cast<ShostakLayer>(layer), c);
  }

 private:
  ShostakLayers layers_;
  double dt_s_;
};

}  // namespace

std::optional<Eigen::Vector3d> shostak_beeline_waypoint(const Eigen::Vector3d& from, const Eigen::Vector3d& target,
                                                        double step_m) {
  const Eigen::Vector2d to(target.x() - from.x(), target.y() - from.y());
  const double dist = to.norm();
  if (dist <= 1e-6) return std::nullopt;
  const Eigen::Vector2d step = std::min(step_m, dist) / dist * to;
  return Eigen::Vector3d(from.x() + step.x(), from.y() + step.y(), from.z());
}

PolicyTraits shostak_traits(const ScenarioConfig& s) {
  const ShostakConfig& c = s.config_of<ShostakConfig>();
  PolicyTraits t;
  for (int l = 0; l < kShostakLayerCount; ++l) t.layers.emplace_back(shostak_layer_name(static_cast<ShostakLayer>(l)));
  t.sensor_radius = c.detect_radius_m / c.layers.cell_size_m;
  // The tiles under the 15 m candidate ring (d·cos ψ <= d) plus one cell.
  t.view_radius = std::ceil(c.aco.step_m / c.layers.cell_size_m) + 1.0;
  t.reads_neighbours = false;  // the field and the broadcast targets only
  // Cruise speed for one tick, three times for the dead-reckoning drift [cell/tick].
  t.max_step = 3.0 * c.speed_mps * c.dt_s / c.layers.cell_size_m;
  // τmax of each layer (Shostak 2024 Sec. 2: [0, 10], [0, 10], [0, 100]).
  t.layer_ranges = {{0.0F, static_cast<float>(c.layers.explored_max)},
                    {0.0F, static_cast<float>(c.layers.hazard_max)},
                    {0.0F, static_cast<float>(c.layers.target_max)}};
  return t;
}

std::unique_ptr<UavPolicy> make_shostak_uav(const ScenarioConfig& s, const MapGeometry& geo, const World& world,
                                            uint32_t id) {
  return std::make_unique<ShostakUav>(s, geo, world, id);
}

std::unique_ptr<PlaceModel> make_shostak_place(const ScenarioConfig& s, const MapGeometry& geo, RegionId region) {
  return std::make_unique<ShostakPlace>(s, geo, region);
}

std::map<std::string, double> shostak_field_summary(const ScenarioConfig& s, const FieldLookup& value) {
  const auto explored = static_cast<int>(ShostakLayer::Explored);
  const auto hazard = static_cast<int>(ShostakLayer::Hazard);
  const auto target = static_cast<int>(ShostakLayer::Target);
  double explored_cells = 0, explored_sum = 0, explored_max = 0;
  double hazard_cells = 0, target_cells = 0, target_max = 0;
  for (int32_t y = 0; y < s.height; ++y) {
    for (int32_t x = 0; x < s.width; ++x) {
      const Cell c{x, y};
      const double e = value(explored, c);
      const double t = value(target, c);
      explored_sum += e;
      explored_max = std::max(explored_max, e);
      if (e > 0.0) ++explored_cells;
      if (value(hazard, c) > 0.0) ++hazard_cells;
      if (t > 0.0) ++target_cells;
      target_max = std::max(target_max, t);
    }
  }
  const double cells = static_cast<double>(s.width) * s.height;
  return {
      {"explored_cells", explored_cells},          // τ_e > 0: explored at some time of the run
      {"explored_fraction", cells > 0 ? explored_cells / cells : 0.0},
      {"explored_mean", cells > 0 ? explored_sum / cells : 0.0},
      {"explored_max", explored_max},
      {"hazard_cells", hazard_cells},
      {"target_cells", target_cells},
      {"target_max", target_max},
  };
}

}  // namespace pheromesh::core
