#include "pheromesh/console/frame_builder.hpp"

#include <algorithm>

#include "pheromesh/console/view.hpp"

namespace pheromesh::console {

namespace {

using Clock = FrameBuilder::Clock;

// Layers: quantised tiles that changed (all of a layer whose scale changed).
void add_changed_tiles(Frame& f, const ConsoleState& last, const FrameBuilder::Sources& s,
                       const core::MapGeometry& geo) {
  std::vector<float> max_of(last.layers.size(), 0.0F);
  for (const auto& [key, t] : s.tiles) {
    if (key.first < 0 || static_cast<std::size_t>(key.first) >= max_of.size()) continue;
    for (float v : t.values) max_of[key.first] = std::max(max_of[key.first], v);
  }
  std::vector<float> scale(last.layers.size());
  for (std::size_t l = 0; l < last.layers.size(); ++l) {
    scale[l] = next_scale(last.layers[l].scale, max_of[l]);
    if (scale[l] != last.layers[l].scale) f.scales.emplace_back(static_cast<uint16_t>(l), scale[l]);
  }
  std::vector<uint8_t> q;
  for (const auto& [key, t] : s.tiles) {
    if (key.first < 0 || static_cast<std::size_t>(key.first) >= last.layers.size()) continue;
    const auto l = static_cast<std::size_t>(key.first);
    quantise(t.values, scale[l], q);
    const auto& tiles = last.layers[l].tiles;
    auto it = tiles.find(key.second);
    if (scale[l] == last.layers[l].scale && it != tiles.end() && it->second.q == q) continue;
    f.tiles.push_back(
        {static_cast<uint16_t>(l), key.second.first, key.second.second, geo.tile_rect(t.tile), t.tick, q});
  }
}

void add_uav_views(Frame& f, const FrameBuilder::Sources& s, const std::map<uint32_t, Clock::time_point>& uav_heard,
                   Clock::time_point now) {
  for (const auto& [id, u] : s.rec.uavs()) {
    UavView v;
    v.id = id;
    v.x = u.last.x;
    v.y = u.last.y;
    v.heading = u.last.heading;
    v.role = u.last.role;
    v.tick = u.last.tick;
    auto heard = uav_heard.find(id);
    const bool quiet = heard == uav_heard.end() || now - heard->second > FrameBuilder::kUavStaleAfter;
    v.liveness = u.finished ? Liveness::Finished
                 : !u.alive ? Liveness::Dead
                 : (quiet && !s.paused) ? Liveness::Stale
                                        : Liveness::Alive;
    f.uavs.push_back(v);
  }
}

// Targets and obstacles.
void add_targets_and_obstacles(Frame& f, const FrameBuilder::Sources& s,
                               const std::map<int32_t, std::pair<uint32_t, uint32_t>>& found_by,
                               const std::map<std::pair<int32_t, int32_t>, bool>& revisit_due) {
  for (std::size_t i = 0; i < s.world.targets().size(); ++i) {
    TargetView t;
    t.cell = s.world.targets()[i];
    t.popup = i >= s.scenario_targets;
    if (auto first = s.rec.acquisitions().first(i)) {
      t.status = TargetStatus::Found;
      t.found_tick = *first;
      if (auto by = found_by.find(static_cast<int32_t>(i)); by != found_by.end()) t.found_by = by->second.first;
    }
    if (auto due = revisit_due.find({t.cell.x, t.cell.y}); due != revisit_due.end() && due->second) {
      t.status = TargetStatus::RevisitDue;
    }
    f.targets.push_back(t);
  }
  for (const auto& r : s.obstacles) f.obstacles.push_back({r, false});
  for (const auto& r : s.popup_obstacles) f.obstacles.push_back({r, true});
}

}  // namespace

Frame FrameBuilder::build(const ConsoleState& last, const Sources& s, Clock::time_point now, double t_s) {
  Frame f;
  f.version = last.version + 1;
  f.t_s = t_s;
  f.tick = s.rec.max_tick();
  f.paused = s.paused;
  add_changed_tiles(f, last, s, geo_);
  add_uav_views(f, s, uav_heard_, now);
  // Place agents
  for (core::RegionId r = 0; r < geo_.region_count(); ++r) {
    RegionView v;
    v.id = r;
    auto h = s.rec.health().find(r);
    if (h != s.rec.health().end()) {
      v.tick = h->second.tick;
      v.tick_rate_hz = h->second.tick_rate_hz;
      v.deposits_received = h->second.deposits_received;
      v.deposits_applied = h->second.deposits_applied;
      v.deposits_rejected = h->second.deposits_rejected;
      for (uint32_t n : h->second.refused) v.samples_refused += n;
      v.replica = s.rec.region_owner(r).value_or(h->second.replica);
      v.replicas_alive = s.rec.replicas_alive(r);
      auto& rate = region_rate_[r];
      if (rate.t == Clock::time_point{}) {
        rate = {now, v.deposits_applied, 0.0};
      } else if (const double dt = std::chrono::duration<double>(now - rate.t).count();
                 dt >= std::chrono::duration<double>(kRatePeriod).count()) {
        rate.per_s = static_cast<double>(v.deposits_applied - std::min(v.deposits_applied, rate.applied)) / dt;
        rate.t = now;
        rate.applied = v.deposits_applied;
      }
      v.deposits_per_s = rate.per_s;
      auto heard = region_heard_.find(r);
      const bool quiet = heard == region_heard_.end() || now - heard->second > kRegionStaleAfter;
      if (h->second.finished) {
        v.liveness = Liveness::Finished;
      } else if (s.rec.region_departed(r)) {
        v.liveness = Liveness::Dead;
      } else if (quiet && !s.paused) {
        v.liveness = Liveness::Stale;
      } else {
        v.liveness = Liveness::Alive;
      }
    }
    f.regions.push_back(v);
  }
  add_targets_and_obstacles(f, s, found_by_, revisit_due_);
  return f;
}

}  // namespace pheromesh::console
