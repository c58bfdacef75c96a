#include "pheromesh/core/uav_core.hpp"

#include <algorithm>
#include <cmath>

namespace pheromesh::core {

namespace {
std::pair<int32_t, int32_t> key(Cell c) { return {c.x, c.y}; }
// A target mark is re-sent at most this often while the place agent has not
// yet published the target as marked (its tile may lag a tick or two).
constexpr uint32_t kMarkResendTicks = 5;
}  // namespace

// ------------------------------------------------------------------ TileCache
void TileCache::update(const TileMsg& m) {
  auto& t = tiles_[{m.tile.tx, m.tile.ty}];
  auto& slot = t.layers[m.layer];
  if (!slot.empty() && m.tick < t.tick[m.layer]) return;  // older than what we have
  slot = m.values;
  t.tick[m.layer] = m.tick;
}

std::optional<float> TileCache::value(Layer l, Cell c) const {
  if (!geo_->in_map(c)) return std::nullopt;
  const TileCoord tc = geo_->tile_of(c);
  auto it = tiles_.find({tc.tx, tc.ty});
  if (it == tiles_.end()) return std::nullopt;
  const auto& v = it->second.layers[static_cast<std::size_t>(l)];
  if (v.empty()) return std::nullopt;
  const Rect r = geo_->tile_rect(tc);
  return v[static_cast<std::size_t>((c.y - r.y0) * r.w + (c.x - r.x0))];
}

std::optional<std::array<float, 3>> TileCache::pheromones(Cell c) const {
  auto t = value(Layer::Target, c);
  auto o = value(Layer::Obstacle, c);
  auto p = value(Layer::Path, c);
  if (!t || !o || !p) return std::nullopt;
  return std::array<float, 3>{*t, *o, *p};
}

std::optional<uint32_t> TileCache::oldest_tick(TileCoord t) const {
  auto it = tiles_.find({t.tx, t.ty});
  if (it == tiles_.end()) return std::nullopt;
  uint32_t oldest = UINT32_MAX;
  for (std::size_t l = 0; l < kLayerCount; ++l) {
    if (it->second.layers[l].empty()) return std::nullopt;
    oldest = std::min(oldest, it->second.tick[l]);
  }
  return oldest;
}

void TileCache::forget_except(const std::vector<TileCoord>& keep) {
  for (auto it = tiles_.begin(); it != tiles_.end();) {
    const bool kept = std::any_of(keep.begin(), keep.end(), [&](const TileCoord& t) {
      return t.tx == it->first.first && t.ty == it->first.second;
    });
    it = kept ? std::next(it) : tiles_.erase(it);
  }
}

// -------------------------------------------------------------------- UavCore
UavCore::UavCore(const ScenarioConfig& scenario, const World& world, uint32_t id)
    : scenario_(&scenario),
      geo_(scenario.geometry()),
      world_(&world),
      id_(id),
      rng_(stream_seed(scenario.seed, "uav", id)),
      cache_(geo_) {
  pos_ = start_cell(scenario, id);
  heading_ = static_cast<Heading>(rng_.uniform_below(8));
  update_neighbourhood();
}

void UavCore::receive_neighbour(const UavStateMsg& s) {
  if (s.uav != id_) neighbours_[s.uav] = s;
}

void UavCore::move() {
  LocalView view;
  view.pheromones = [this](Cell c) { return cache_.pheromones(c); };
  view.blocked = [this](Cell c) { return !geo_.in_map(c) || known_obstacles_.contains(key(c)); };
  const Decision d = decide(pos_, heading_, view, scenario_->aco, rng_);
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
    const Cell s = step_of(h);
    const Cell next{pos_.x + s.x, pos_.y + s.y};
    if (!view.blocked(next)) {
      last_step_ = s;
      pos_ = next;
      heading_ = h;
      return;
    }
  }
  last_step_ = {0, 0};
}

void UavCore::add_deposit(DepositKind kind, Cell cell, RegionId region, uint32_t tick, Output& out) {
  out.deposits.push_back({id_, ++seq_, tick, region, static_cast<uint8_t>(kind), cell, 1.0F});
}

void UavCore::sense_and_deposit(uint32_t tick, Output& out) {
  const auto reading = world_->sense(pos_, scenario_->aco.sensor_radius);
  // Algorithm 1 lines 6-9: mark obstacles in the sensor range (kε = 1).
  for (const Cell& o : reading.obstacles) {
    known_obstacles_.insert(key(o));
    if (marked_obstacles_.insert(key(o)).second) add_deposit(DepositKind::ObstacleMark, o, geo_.region_of(o), tick, out);
  }
  // Algorithm 1 lines 3-5: mark targets in the sensor range; the place agent
  // owning the target's cell runs the revisit timer.
  std::set<int32_t> now_in_range;
  for (int32_t t : reading.targets) {
    now_in_range.insert(t);
    const Cell c = world_->targets()[static_cast<std::size_t>(t)];
    if (!targets_in_range_.contains(t)) out.detections.push_back({id_, tick, t, c});
    const auto state = cache_.value(Layer::TargetState, c);
    const bool needs_mark = !state || *state != kTargetMarked;
    auto last = target_mark_sent_tick_.find(t);
    const bool recently = last != target_mark_sent_tick_.end() && tick - last->second < kMarkResendTicks;
    if (needs_mark && !recently) {
      add_deposit(DepositKind::TargetMark, c, geo_.region_of(c), tick, out);
      target_mark_sent_tick_[t] = tick;
    }
  }
  targets_in_range_ = std::move(now_in_range);
  // Path pheromone decrease around the UAV (Shao 2020 eqs. (5)-(7)) is
  // computed by every place agent owning a cell within D0.
  for (RegionId r : geo_.regions_within(pos_, scenario_->layers.d0)) add_deposit(DepositKind::PathVisit, pos_, r, tick, out);
}

void UavCore::update_neighbourhood() {
  const auto r = static_cast<int32_t>(std::ceil(scenario_->aco.sensor_radius)) + 1;
  std::vector<TileCoord> hood = geo_.tiles_within(pos_, r);
  if (hood != hood_) {
    cache_.forget_except(hood);
    hood_ = std::move(hood);
  }
}

void UavCore::step(uint32_t tick, Output& out) {
  out.deposits.clear();
  out.detections.clear();
  if (tick > 0) move();
  update_neighbourhood();
  sense_and_deposit(tick, out);
  out.state = {};
  out.state.uav = id_;
  out.state.tick = tick;
  out.state.x = pos_.x;
  out.state.y = pos_.y;
  out.state.vx = last_step_.x;
  out.state.vy = last_step_.y;
  out.state.heading = static_cast<uint8_t>(heading_);
  out.state.role = static_cast<uint8_t>(Role::Searcher);
}

}  // namespace pheromesh::core
