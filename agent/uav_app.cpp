#include "uav_app.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <thread>

namespace pheromesh::agent {

using core::Cell;
using core::DepositKind;
using core::Layer;

namespace {
std::pair<int32_t, int32_t> key(Cell c) { return {c.x, c.y}; }
// A target mark is re-sent at most this often while the place agent has not
// yet published the target as marked (its tile may lag a tick or two).
constexpr uint32_t kMarkResendTicks = 5;
}  // namespace

// ------------------------------------------------------------------ TileCache
void TileCache::update(const core::TileMsg& m) {
  auto& t = tiles_[{m.tile.tx, m.tile.ty}];
  auto& slot = t.layers[m.layer];
  if (!slot.empty() && m.tick < t.tick[m.layer]) return;  // older than what we have
  slot = m.values;
  t.tick[m.layer] = m.tick;
}

std::optional<float> TileCache::value(Layer l, Cell c) const {
  if (!geo_->in_map(c)) return std::nullopt;
  const core::TileCoord tc = geo_->tile_of(c);
  auto it = tiles_.find({tc.tx, tc.ty});
  if (it == tiles_.end()) return std::nullopt;
  const auto& v = it->second.layers[static_cast<std::size_t>(l)];
  if (v.empty()) return std::nullopt;
  const core::Rect r = geo_->tile_rect(tc);
  return v[static_cast<std::size_t>((c.y - r.y0) * r.w + (c.x - r.x0))];
}

std::optional<std::array<float, 3>> TileCache::pheromones(Cell c) const {
  auto t = value(Layer::Target, c);
  auto o = value(Layer::Obstacle, c);
  auto p = value(Layer::Path, c);
  if (!t || !o || !p) return std::nullopt;
  return std::array<float, 3>{*t, *o, *p};
}

void TileCache::forget_except(const std::vector<core::TileCoord>& keep) {
  for (auto it = tiles_.begin(); it != tiles_.end();) {
    const bool kept = std::any_of(keep.begin(), keep.end(), [&](const core::TileCoord& t) {
      return t.tx == it->first.first && t.ty == it->first.second;
    });
    it = kept ? std::next(it) : tiles_.erase(it);
  }
}

// --------------------------------------------------------------------- UavApp
UavApp::UavApp(UavConfig cfg, core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus)
    : cfg_(std::move(cfg)),
      scenario_(std::move(scenario)),
      geo_(scenario_.geometry()),
      world_(geo_, scenario_.obstacles, scenario_.targets),
      bus_(std::move(bus)),
      log_(spdlog::default_logger()),
      rng_(core::stream_seed(scenario_.seed, "uav", cfg_.id)),
      cache_(geo_) {
  pos_ = core::start_cell(scenario_, cfg_.id);
  heading_ = static_cast<core::Heading>(rng_.uniform_below(8));
}

void UavApp::receive() {
  tile_inbox_.clear();
  bus_->take_tiles(tile_inbox_);
  tile_samples_received_ += tile_inbox_.size();
  for (const auto& t : tile_inbox_) {
    if (auto reason = core::check_tile(t, geo_)) {
      if (++samples_rejected_ <= 3) log_->warn("dropped tile ({},{}) layer {}: {}", t.tile.tx, t.tile.ty, t.layer, *reason);
      continue;
    }
    cache_.update(t);
  }
  state_inbox_.clear();
  bus_->take_uav_states(state_inbox_);
  for (const auto& s : state_inbox_) {
    if (s.uav == cfg_.id) continue;
    if (auto reason = core::check_uav_state(s, geo_)) {
      if (++samples_rejected_ <= 3) log_->warn("dropped state of uav {}: {}", s.uav, *reason);
      continue;
    }
    neighbours_[s.uav] = s;
  }
}

void UavApp::move() {
  core::LocalView view;
  view.pheromones = [this](Cell c) { return cache_.pheromones(c); };
  view.blocked = [this](Cell c) { return !geo_.in_map(c) || known_obstacles_.contains(key(c)); };
  const core::Decision d = core::decide(pos_, heading_, view, scenario_.aco, rng_);
  if (d.chosen) {
    last_step_ = core::step_of(d.chosen->heading);
    pos_ = d.chosen->next;
    heading_ = d.chosen->heading;
    return;
  }
  // Dead end ahead (the five forward headings are blocked): turn back, the
  // least sharp turn first. Not in the paper, which assumes a way forward.
  for (int turn : {3, -3, 4}) {
    const core::Heading h = core::rotate(heading_, turn);
    const Cell s = core::step_of(h);
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

void UavApp::deposit(DepositKind kind, Cell cell, core::RegionId region, float amount) {
  // A deposit written while no place agent of that region is matched would be
  // lost silently; count it as undeliverable instead of sent.
  if (bus_->matched_deposit_readers(region) == 0) {
    ++deposits_undeliverable_;
    return;
  }
  core::DepositMsg m{cfg_.id, ++seq_, tick_, region, static_cast<uint8_t>(kind), cell, amount};
  if (bus_->publish_deposit(m)) ++deposits_sent_;
}

void UavApp::sense_and_deposit() {
  const auto reading = world_.sense(pos_, scenario_.aco.sensor_radius);
  // Algorithm 1 lines 6-9: mark obstacles in the sensor range (kε = 1).
  for (const Cell& o : reading.obstacles) {
    known_obstacles_.insert(key(o));
    if (marked_obstacles_.insert(key(o)).second) deposit(DepositKind::ObstacleMark, o, geo_.region_of(o), 1.0F);
  }
  // Algorithm 1 lines 3-5: mark targets in the sensor range; the place agent
  // owning the target's cell runs the revisit timer.
  std::set<int32_t> now_in_range;
  for (int32_t t : reading.targets) {
    now_in_range.insert(t);
    const Cell c = world_.targets()[static_cast<std::size_t>(t)];
    if (!targets_in_range_.contains(t)) bus_->publish_detection({cfg_.id, tick_, t, c});
    const auto state = cache_.value(Layer::TargetState, c);
    const bool needs_mark = !state || *state != core::kTargetMarked;
    auto last = target_mark_sent_tick_.find(t);
    const bool recently = last != target_mark_sent_tick_.end() && tick_ - last->second < kMarkResendTicks;
    if (needs_mark && !recently) {
      deposit(DepositKind::TargetMark, c, geo_.region_of(c), 1.0F);
      target_mark_sent_tick_[t] = tick_;
    }
  }
  targets_in_range_ = std::move(now_in_range);
  // Path pheromone decrease around the UAV (Shao 2020 eqs. (5)-(7)) is
  // computed by every place agent owning a cell within D0.
  for (core::RegionId r : geo_.regions_within(pos_, scenario_.layers.d0)) deposit(DepositKind::PathVisit, pos_, r, 1.0F);
}

void UavApp::publish_state(bool finished) {
  core::UavStateMsg s;
  s.uav = cfg_.id;
  s.tick = tick_;
  s.x = pos_.x;
  s.y = pos_.y;
  s.vx = last_step_.x;
  s.vy = last_step_.y;
  s.heading = static_cast<uint8_t>(heading_);
  s.role = static_cast<uint8_t>(core::Role::Searcher);
  s.deposits_sent = deposits_sent_;
  s.tile_samples_received = tile_samples_received_;
  s.finished = finished;
  bus_->publish_uav_state(s, geo_.tile_of(pos_));
}

void UavApp::update_neighbourhood() {
  // Tiles within the sensor radius plus the next step.
  const auto r = static_cast<int32_t>(std::ceil(scenario_.aco.sensor_radius)) + 1;
  std::vector<core::TileCoord> hood = geo_.tiles_within(pos_, r);
  if (hood != hood_) {
    bus_->set_neighbourhood(hood);
    cache_.forget_except(hood);
    hood_ = std::move(hood);
  }
}

int UavApp::run() {
  const double rate = scenario_.tick_rate_hz;
  const uint32_t ticks = scenario_.ticks;
  update_neighbourhood();
  // Wait (bounded) until every region's place agent is matched, so the first
  // deposits are not lost to discovery.
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::milliseconds(static_cast<int64_t>(cfg_.wait_for_places_s * 1000));
  for (;;) {
    uint32_t missing = 0;
    for (core::RegionId r = 0; r < geo_.region_count(); ++r) missing += bus_->matched_deposit_readers(r) == 0 ? 1 : 0;
    if (missing == 0) break;
    if (std::chrono::steady_clock::now() > deadline || runtime::shutdown_requested()) {
      log_->warn("starting with {} place agent(s) not discovered", missing);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  log_->info("uav {} starts at ({},{}) heading {} for {} ticks at {:.1f} Hz over {}", cfg_.id, pos_.x, pos_.y,
             static_cast<int>(heading_), ticks, rate, bus_->vendor());
  sense_and_deposit();
  publish_state(false);
  runtime::TickClock clock(rate);
  while (tick_ < ticks && clock.wait_next()) {
    ++tick_;
    receive();
    move();
    update_neighbourhood();
    sense_and_deposit();
    publish_state(false);
  }
  publish_state(true);
  const bool acked = bus_->flush(std::chrono::seconds(5));
  log_->info("uav {} finished at tick {} at ({},{}): deposits sent {}, undeliverable {}, samples rejected {}{}", cfg_.id,
             tick_, pos_.x, pos_.y, deposits_sent_, deposits_undeliverable_, samples_rejected_,
             acked ? "" : " (not every sample was acknowledged)");
  return 0;
}

}  // namespace pheromesh::agent
