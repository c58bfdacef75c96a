#include "pheromesh/core/uav_core.hpp"

#include <algorithm>
#include <cmath>

namespace pheromesh::core {

namespace {
// Neighbour states and broadcasts older than this are forgotten [tick].
constexpr uint32_t kKeepTicks = 4;
}  // namespace

Cell state_cell(const UavStateMsg& s) {
  return {static_cast<int32_t>(std::lround(s.x)), static_cast<int32_t>(std::lround(s.y))};
}

UavCore::UavCore(const ScenarioConfig& scenario, const World& world, uint32_t id, bool exact_ticks)
    : scenario_(&scenario),
      geo_(scenario.geometry()),
      id_(id),
      exact_(exact_ticks),
      traits_(policy_traits(scenario)),
      cache_(geo_, static_cast<int>(traits_.layers.size())),
      policy_(make_uav_policy(scenario, geo_, world, id)) {
  last_state_.uav = id;
  const Cell c = policy_->cell();
  last_state_.x = c.x;
  last_state_.y = c.y;
  update_neighbourhood();
}

namespace {
// A neighbour is known by its pose (and whether it finished), whoever sent
// it: a lockstep place phase lists the other regions' UAVs by pose only
// (ClockMsg::served), and the simulator's views must show the same. Every
// state held is one of these, so its counters are already zero.
void hold_pose(UavStateMsg& held, const UavStateMsg& s) {
  held.uav = s.uav;
  held.tick = s.tick;
  held.x = s.x;
  held.y = s.y;
  held.vx = s.vx;
  held.vy = s.vy;
  held.heading = s.heading;
  held.role = s.role;
  held.view = s.view;
  held.finished = s.finished;
}
}  // namespace

void UavCore::receive_neighbour(const UavStateMsg& s) {
  if (s.uav == id_) return;
  auto& by_tick = neighbours_[s.uav];
  if (auto it = by_tick.find(s.tick); it != by_tick.end()) {
    hold_pose(it->second, s);
    return;
  }
  if (by_tick.size() < kKeepTicks) {
    hold_pose(by_tick[s.tick], s);
    return;
  }
  // Full: the oldest tick goes, unless this one is older still. Its node is
  // reused (a view brings each neighbour's state every tick: no allocation).
  if (s.tick < by_tick.begin()->first) return;
  auto node = by_tick.extract(by_tick.begin());
  node.key() = s.tick;
  hold_pose(node.mapped(), s);
  by_tick.insert(std::move(node));
}

void UavCore::receive_broadcast(const BroadcastMsg& b) {
  broadcasts_[b.tick][b.uav] = b;
  while (broadcasts_.size() > kKeepTicks) broadcasts_.erase(broadcasts_.begin());
}

bool UavCore::in_hood(const UavStateMsg& s) const {
  const Cell c = state_cell(s);
  if (!geo_.in_map(c)) return false;
  const TileCoord t = geo_.tile_of(c);
  return std::find(hood_.begin(), hood_.end(), t) != hood_.end();
}

bool UavCore::holds_tick(uint32_t t, const std::vector<TileCount>& occupancy, uint32_t broadcasts) const {
  for (const TileCount& tc : occupancy) {
    if (std::find(hood_.begin(), hood_.end(), tc.tile) == hood_.end()) continue;
    uint32_t want = tc.count;
    if (last_state_.tick == t && geo_.tile_of(state_cell(last_state_)) == tc.tile && want > 0) --want;  // this UAV
    uint32_t have = 0;
    for (const auto& [uav, by_tick] : neighbours_) {
      auto it = by_tick.find(t);
      if (it != by_tick.end() && geo_.tile_of(state_cell(it->second)) == tc.tile) ++have;
    }
    if (have < want) return false;
  }
  auto it = broadcasts_.find(t);
  const std::size_t have = it == broadcasts_.end() ? 0 : it->second.size();
  return have >= broadcasts;
}

void UavCore::update_neighbourhood() {
  const auto r = static_cast<int32_t>(std::ceil(traits_.view_radius));
  std::vector<TileCoord> hood = geo_.tiles_within(policy_->cell(), r);
  if (hood != hood_) {
    cache_.forget_except(hood);
    hood_ = std::move(hood);
  }
}

void UavCore::step(uint32_t tick, Output& out) {
  out.deposits.clear();
  out.detections.clear();
  out.broadcast.reset();
  // What this UAV sees: the states and broadcasts of the previous tick
  // (exact), or the latest ones (realtime), of UAVs over its neighbourhood.
  view_states_.clear();
  for (auto n = neighbours_.begin(); n != neighbours_.end();) {
    const auto& by_tick = n->second;
    // A UAV not heard for more than kKeepTicks ticks can show in no view from
    // now on (exact: none of tick-1; realtime: too old) nor count for
    // holds_tick, which asks of later ticks: it goes, so that this
    // loop, the neighbours' lookups and holds_tick pass over the UAVs around
    // this one, not over every UAV it ever saw (a late state of it starts
    // it again, as it would have been kept).
    if (by_tick.empty() || by_tick.rbegin()->first + kKeepTicks < tick) {
      n = neighbours_.erase(n);
      continue;
    }
    ++n;
    const UavStateMsg* s = nullptr;
    if (exact_) {
      if (tick == 0) continue;
      auto it = by_tick.find(tick - 1);
      if (it != by_tick.end()) s = &it->second;
    } else if (by_tick.rbegin()->first + kKeepTicks >= tick) {
      s = &by_tick.rbegin()->second;
    }
    if (s != nullptr && !s->finished && in_hood(*s)) view_states_.push_back(*s);
  }
  view_broadcasts_.clear();
  if (exact_) {
    auto it = tick > 0 ? broadcasts_.find(tick - 1) : broadcasts_.end();
    if (it != broadcasts_.end()) {
      for (const auto& [uav, b] : it->second) view_broadcasts_.push_back(b);
    }
  } else {
    for (const auto& [t, by_uav] : broadcasts_) {
      if (t < broadcasts_consumed_) continue;
      for (const auto& [uav, b] : by_uav) view_broadcasts_.push_back(b);
      broadcasts_consumed_ = t + 1;
    }
  }

  actions_.clear();
  const UavView view{tick, &cache_, view_states_, view_broadcasts_};
  policy_->step(view, actions_);
  update_neighbourhood();

  for (auto& d : actions_.deposits) {
    d.uav = id_;
    d.seq = ++seq_;
    d.tick = tick;
    out.deposits.push_back(d);
  }
  for (auto& d : actions_.detections) {
    d.uav = id_;
    d.tick = tick;
    out.detections.push_back(d);
  }
  if (actions_.broadcast) {
    BroadcastMsg b = *actions_.broadcast;
    b.uav = id_;
    b.tick = tick;
    receive_broadcast(b);  // a UAV hears its own broadcast
    out.broadcast = std::move(b);
  }
  out.state = actions_.state;
  out.state.uav = id_;
  out.state.tick = tick;
  last_state_ = out.state;
}

}  // namespace pheromesh::core
