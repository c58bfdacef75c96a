// The Shao 2020 search policy (Shao 2020 Sec. 4): ACO decisions on semantic pheromones
// (Shao 2020 eq. (9), Shao 2020 eq. (10), Shao 2020 eq. (11)), target and obstacle marks, path pheromone around the UAV
// (Shao 2020 eq. (5), Shao 2020 eq. (6), Shao 2020 eq. (7)), and the place agents' layers (Shao 2020 eq. (1), Shao 2020 eq. (2), Shao 2020 eq. (3), Shao 2020 eq. (4), Shao 2020 eq. (5), Shao 2020 eq. (6), Shao 2020 eq. (7), Shao 2020 eq. (8)) with revisit timers.
#include <algorithm>
#include <cmath>
#include <set>

#include "pheromesh/core/marks.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/rng.hpp"
#include "pheromesh/shao/aco.hpp"
#include "pheromesh/shao/lawnmower.hpp"
#include "pheromesh/shao/policy.hpp"

namespace pheromesh::core {

namespace {

std::pair<int32_t, int32_t> key(Cell c) { return {c.x, c.y}; }
// A target mark is re-sent at most this often while the place agent has not
// yet published the target as marked (its tile may lag a tick or two).
constexpr uint32_t kMarkResendTicks = 5;
// shao_search_frontier: a sector mean of target pheromone above this is a
// revisit signal in sight (the layer is exactly 0 where no target emits).
constexpr double kTargetInSight = 1e-6;
// A path pheromone this far below σ0 marks a cell as visited (float rounding
// of the place agent's update stays far below it; the smallest decrease, at
// D = 1, is 0.12 σ0, Shao 2020 eq. (7)).
constexpr float kPathTouched = 1e-3F;
constexpr uint32_t kFrontierRecheckTicks = 25;

class ShaoSearchUav final : public UavPolicy {
 public:
  ShaoSearchUav(const ScenarioConfig& s, const MapGeometry& geo, const World& world, uint32_t id, bool frontier = false,
                bool mark_on_arrival = false)
      : s_(&s),
        geo_(&geo),
        world_(&world),
        rng_(stream_seed(s.seed, "uav", id)),
        mark_on_arrival_(mark_on_arrival),
        frontier_(frontier) {
    pos_ = start_cell(s, id);
    heading_ = static_cast<Heading>(rng_.uniform_below(8));
    if (frontier_) {
      visited_.width = geo.width();
      visited_.height = geo.height();
      visited_.visited.assign(static_cast<std::size_t>(geo.width()) * static_cast<std::size_t>(geo.height()), 0);
    }
  }
  ShaoSearchUav(const ScenarioConfig& s, const MapGeometry& geo, const World& world, uint32_t id, Cell at,
                Heading heading)
      : s_(&s), geo_(&geo), world_(&world), rng_(stream_seed(s.seed, "uav-search", id)), pos_(at), heading_(heading) {}

  void step(const UavView& view, UavActions& out) override {
    if (view.tick > 0) move(*view.tiles, view.tick);
    sense_and_deposit(view, out);
    out.state.x = pos_.x;
    out.state.y = pos_.y;
    out.state.vx = last_step_.x;
    out.state.vy = last_step_.y;
    out.state.heading = static_cast<uint8_t>(heading_);
    out.state.role = static_cast<uint8_t>(Role::Searcher);
  }
  [[nodiscard]] Cell cell() const override { return pos_; }

 private:
  void move(const TileCache& tiles, uint32_t tick) {
    LocalView view;
    view.pheromones = [&tiles](Cell c) -> std::optional<std::array<float, 3>> {
      auto t = tiles.value(static_cast<int>(Layer::Target), c);
      auto o = tiles.value(static_cast<int>(Layer::Obstacle), c);
      auto p = tiles.value(static_cast<int>(Layer::Path), c);
      if (!t || !o || !p) return std::nullopt;
      return std::array<float, 3>{*t, *o, *p};
    };
    view.blocked = [this](Cell c) { return !geo_->in_map(c) || known_obstacles_.contains(key(c)); };
    if (going_to_ && go_to_target(view)) return;
    if (frontier_ && frontier_move(tiles, view, tick)) return;
    const Decision d = decide(pos_, heading_, view, s_->aco, rng_);
    if (d.chosen) {
      last_step_ = step_of(d.chosen->heading);
      pos_ = d.chosen->next;
      heading_ = d.chosen->heading;
      return;
    }
    // Dead end ahead (the five forward headings are blocked): turn back, the
    // least sharp turn first. Not in the paper, which assumes a way forward.
    for (int turn : {3, -3, 4}) {
      const Heading h = rotate(heading_, turn);
      const Cell st = step_of(h);
      const Cell next{pos_.x + st.x, pos_.y + st.y};
      if (!view.blocked(next)) {
        last_step_ = st;
        pos_ = next;
        heading_ = h;
        return;
      }
    }
    last_step_ = {0, 0};
  }

  // One step to forward candidate i (0..4 = turn -2..2 eighths, as evaluate_candidates).
  void take_candidate(std::size_t i) {
    heading_ = rotate(heading_, static_cast<int>(i) - 2);
    last_step_ = step_of(heading_);
    pos_ = Cell{pos_.x + last_step_.x, pos_.y + last_step_.y};
  }

  // Shao 2020 Algorithm 1 line 4 read literally ("go there, mark them"): one
  // step towards the target to mark, forward headings only. False if no
  // forward step leads there (the paper's rule decides this tick).
  bool go_to_target(const LocalView& view) {
    const Cell goal = world_->targets()[static_cast<std::size_t>(*going_to_)];
    const auto i = frontier_candidate(pos_, heading_, goal, geo_->width(), geo_->height(), view.blocked);
    if (!i) return false;
    take_candidate(*i);
    return true;
  }

  // shao_search_frontier (docs/policies/shao.md): unless a target pheromone
  // is in one of the five forward sectors (a revisit signal, followed with the
  // paper's rule), take the forward step that brings the most cells this UAV
  // does not know to be visited into its sensor range; if none brings any,
  // fly towards the nearest such cell. False: no such cell or no forward way
  // to it; the paper's rule decides.
  bool frontier_move(const TileCache& tiles, const LocalView& view, uint32_t tick) {
    remember_visited(tiles);
    for (const Candidate& c : evaluate_candidates(pos_, heading_, view, s_->aco)) {
      if (c.accessible && c.tau > kTargetInSight) return false;
    }
    if (const auto i = coverage_candidate(pos_, heading_, visited_, s_->aco.sensor_radius, view.blocked)) {
      take_candidate(*i);
      return true;
    }
    if (tick < exhausted_until_) return false;
    const auto goal = nearest_unvisited(pos_, visited_, view.blocked);
    if (!goal) {
      // Everything reachable is visited: recheck now and then (new obstacles
      // known, or a cell we missed), not every tick.
      exhausted_until_ = tick + kFrontierRecheckTicks;
      return false;
    }
    const auto i = frontier_candidate(pos_, heading_, *goal, geo_->width(), geo_->height(), view.blocked);
    if (!i) return false;
    take_candidate(*i);
    return true;
  }

  // Cells within the sensor radius of the UAV, and every cell of the tiles
  // it holds whose path pheromone is below σ0, are visited.
  void remember_visited(const TileCache& tiles) {
    const double sd = s_->aco.sensor_radius;
    const auto r = static_cast<int32_t>(std::floor(sd));
    for (int32_t dy = -r; dy <= r; ++dy) {
      for (int32_t dx = -r; dx <= r; ++dx) {
        const Cell c{pos_.x + dx, pos_.y + dy};
        if (geo_->in_map(c) && static_cast<double>(dx * dx + dy * dy) <= sd * sd) visited_.visited[geo_->index(c)] = 1;
      }
    }
    const auto reach = static_cast<int32_t>(std::ceil(sd)) + 1 + geo_->tile_size();
    const auto below = static_cast<float>(s_->layers.sigma0) - kPathTouched;
    for (int32_t y = std::max(0, pos_.y - reach); y <= std::min(geo_->height() - 1, pos_.y + reach); ++y) {
      for (int32_t x = std::max(0, pos_.x - reach); x <= std::min(geo_->width() - 1, pos_.x + reach); ++x) {
        const Cell c{x, y};
        const auto v = tiles.value(static_cast<int>(Layer::Path), c);
        if (v && *v < below) visited_.visited[geo_->index(c)] = 1;
      }
    }
  }

  void deposit(DepositKind kind, Cell c, RegionId region, UavActions& out) {
    DepositMsg d;
    d.region = region;
    d.kind = static_cast<uint8_t>(kind);
    d.cell = c;
    d.amount = 1.0F;
    out.deposits.push_back(d);
  }

  void sense_and_deposit(const UavView& view, UavActions& out) {
    const auto reading = world_->sense(pos_, s_->aco.sensor_radius);
    // Shao 2020 Algorithm 1 lines 6-9: mark obstacles in the sensor range (kε = 1).
    for (const Cell& o : reading.obstacles) {
      known_obstacles_.insert(key(o));
      if (marked_obstacles_.insert(key(o)).second) deposit(DepositKind::ObstacleMark, o, geo_->region_of(o), out);
    }
    // Shao 2020 Algorithm 1 lines 3-5: mark targets in the sensor range; the place agent
    // owning the target's cell runs the revisit timer.
    std::set<int32_t> now_in_range;
    std::optional<int32_t> nearest_unmarked;
    int64_t nearest_d2 = 0;
    for (int32_t t : reading.targets) {
      now_in_range.insert(t);
      const Cell c = world_->targets()[static_cast<std::size_t>(t)];
      if (!targets_in_range_.contains(t)) out.detections.push_back({0, view.tick, t, c});
      const auto state = view.tiles->value(static_cast<int>(Layer::TargetState), c);
      const bool needs_mark = !state || *state != kTargetMarked;
      if (!needs_mark) continue;
      if (mark_on_arrival_ && (c.x != pos_.x || c.y != pos_.y)) {
        // Not there yet: fly to the nearest target that needs a mark.
        const int64_t dx = c.x - pos_.x, dy = c.y - pos_.y;
        if (!nearest_unmarked || dx * dx + dy * dy < nearest_d2) {
          nearest_unmarked = t;
          nearest_d2 = dx * dx + dy * dy;
        }
        continue;
      }
      auto last = mark_sent_tick_.find(t);
      const bool recently = last != mark_sent_tick_.end() && view.tick - last->second < kMarkResendTicks;
      if (!recently) {
        deposit(DepositKind::TargetMark, c, geo_->region_of(c), out);
        mark_sent_tick_[t] = view.tick;
      }
    }
    targets_in_range_ = std::move(now_in_range);
    going_to_ = nearest_unmarked;
    // Path pheromone decrease around the UAV (Shao 2020 eq. (5), Shao 2020 eq. (6), Shao 2020 eq. (7)) is
    // computed by every place agent owning a cell within D0.
    for (RegionId r : geo_->regions_within(pos_, s_->layers.d0)) deposit(DepositKind::PathVisit, pos_, r, out);
  }

  const ScenarioConfig* s_;
  const MapGeometry* geo_;
  const World* world_;
  Rng rng_;
  Cell pos_{};
  Cell last_step_{};
  Heading heading_ = Heading::E;
  std::set<std::pair<int32_t, int32_t>> known_obstacles_;
  std::set<std::pair<int32_t, int32_t>> marked_obstacles_;
  std::map<int32_t, uint32_t> mark_sent_tick_;  // target index -> tick of the last mark sent
  std::set<int32_t> targets_in_range_;
  // mark on arrival (Shao 2020 Algorithm 1 line 4 read literally): the target flown to
  bool mark_on_arrival_ = false;
  std::optional<int32_t> going_to_;
  // shao_search_frontier only
  bool frontier_ = false;
  VisitedMap visited_;
  uint32_t exhausted_until_ = 0;
};

class ShaoPlace final : public PlaceModel {
 public:
  ShaoPlace(const ScenarioConfig& s, const MapGeometry& geo, RegionId region, bool beacons)
      : field_(geo, region, s.layers), marks_(s.aco.revisit_period) {
    if (!beacons) return;
    const Rect r = field_.rect();
    for (const Cell& t : s.targets) {
      if (r.contains(t)) field_.set_target_switch(t, true);
    }
    for (const Rect& o : s.obstacles) {
      for (int32_t y = std::max(o.y0, r.y0); y < std::min(o.y0 + o.h, r.y0 + r.h); ++y) {
        for (int32_t x = std::max(o.x0, r.x0); x < std::min(o.x0 + o.w, r.x0 + r.w); ++x) field_.set_obstacle_switch({x, y});
      }
    }
  }

  std::optional<std::string> apply(const DepositMsg& d, uint32_t tick, std::vector<TargetEventMsg>& events) override {
    switch (static_cast<DepositKind>(d.kind)) {
      case DepositKind::PathVisit:
        field_.add_path_visit(d.cell);
        return std::nullopt;
      case DepositKind::ObstacleMark:
        field_.set_obstacle_switch(d.cell);  // kε = 1, Shao 2020 eq. (3)
        return std::nullopt;
      case DepositKind::TargetMark:
        if (auto ev = marks_.mark(d.cell, tick)) {
          field_.set_target_switch(d.cell, false);
          field_.set_target_state(d.cell, kTargetMarked);
          events.push_back({field_.region(), tick, static_cast<uint8_t>(ev->kind), ev->cell, ev->response_ticks});
        }
        return std::nullopt;
      default:
        return "deposit kind " + std::to_string(d.kind) + " is not used by the Shao policies";
    }
  }

  HaloRing begin_step(uint32_t tick, std::vector<TargetEventMsg>& events) override {
    for (const auto& ev : marks_.advance(tick)) {
      field_.set_target_switch(ev.cell, true);  // kτ = 1: revisit signal, Shao 2020 eq. (1)
      field_.set_target_state(ev.cell, kTargetDue);
      events.push_back({field_.region(), tick, static_cast<uint8_t>(ev.kind), ev.cell, 0});
    }
    return field_.begin_step();
  }
  void accept_halo(const Rect& neighbour_rect, const HaloRing& ring) override {
    field_.accept_halo(neighbour_rect, ring);
  }
  void finish_step() override { field_.finish_step(); }
  [[nodiscard]] float value(int layer, Cell c) const override { return field_.value(static_cast<Layer>(layer), c); }
  void copy_rect(int layer, const Rect& r, float* out) const override {
    field_.copy_rect(static_cast<Layer>(layer), r, out);
  }

 private:
  RegionField field_;
  TargetMarks marks_;
};

}  // namespace

PolicyTraits shao_search_traits(const ScenarioConfig& s) {
  PolicyTraits t;
  for (int l = 0; l < kLayerCount; ++l) t.layers.emplace_back(layer_name(static_cast<Layer>(l)));
  t.sensor_radius = s.aco.sensor_radius;
  // The tiles within the sensor radius plus one step.
  t.view_radius = std::ceil(s.aco.sensor_radius) + 1.0;
  t.reads_neighbours = false;  // the field and the broadcasts only
  t.max_step = 1.5;  // [cell/tick] one grid step, √2 on a diagonal (Shao 2020 eq. (9) headings)
  // Path visits on its cell, target and obstacle marks where it senses them.
  t.deposit_reach = s.aco.sensor_radius;
  return t;
}

ShaoRoute shao_route(const ScenarioConfig& s) {
  if (s.policy != ShaoSearchConfig::kPolicy || s.policy_config == nullptr) return ShaoRoute::Pheromone;
  return s.config_of<ShaoSearchConfig>().route;
}

bool shao_mark_on_arrival(const ScenarioConfig& s) {
  if (s.policy != ShaoSearchConfig::kPolicy || s.policy_config == nullptr) return false;
  return s.config_of<ShaoSearchConfig>().mark_on_arrival;
}

std::unique_ptr<UavPolicy> make_shao_search_uav(const ScenarioConfig& s, const MapGeometry& geo, const World& world,
                                                uint32_t id) {
  switch (shao_route(s)) {
    case ShaoRoute::LawnmowerTransit:
      return make_shao_lawnmower_uav(s, geo, world, id);
    case ShaoRoute::Frontier:
      return std::make_unique<ShaoSearchUav>(s, geo, world, id, /*frontier=*/true, shao_mark_on_arrival(s));
    case ShaoRoute::Pheromone:
      break;
  }
  return std::make_unique<ShaoSearchUav>(s, geo, world, id, /*frontier=*/false, shao_mark_on_arrival(s));
}

std::unique_ptr<UavPolicy> make_shao_search_uav_at(const ScenarioConfig& s, const MapGeometry& geo, const World& world,
                                                   uint32_t id, Cell at, uint8_t heading) {
  return std::make_unique<ShaoSearchUav>(s, geo, world, id, at, static_cast<Heading>(heading % 8));
}

std::unique_ptr<PlaceModel> make_shao_place(const ScenarioConfig& s, const MapGeometry& geo, RegionId region,
                                            bool beacons) {
  return std::make_unique<ShaoPlace>(s, geo, region, beacons);
}

}  // namespace pheromesh::core
