#include "pheromesh/core/policy.hpp"

#include <algorithm>
#include <cmath>

namespace pheromesh::core {

// ------------------------------------------------------------------ TileCache
void TileCache::update(const TileMsg& m) {
  if (m.layer >= layers_) return;
  auto& t = tiles_[{m.tile.tx, m.tile.ty}];
  if (t.layers.empty()) {
    t.layers.resize(static_cast<std::size_t>(layers_));
    t.tick.assign(static_cast<std::size_t>(layers_), 0);
  }
  auto& slot = t.layers[m.layer];
  if (!slot.empty() && m.tick < t.tick[m.layer]) return;  // older than what we have
  slot = m.values;
  t.tick[m.layer] = m.tick;
}

std::optional<float> TileCache::value(int layer, Cell c) const {
  if (!geo_->in_map(c) || layer < 0 || layer >= layers_) return std::nullopt;
  const TileCoord tc = geo_->tile_of(c);
  auto it = tiles_.find({tc.tx, tc.ty});
  if (it == tiles_.end()) return std::nullopt;
  const auto& v = it->second.layers[static_cast<std::size_t>(layer)];
  if (v.empty()) return std::nullopt;
  const Rect r = geo_->tile_rect(tc);
  return v[static_cast<std::size_t>((c.y - r.y0) * r.w + (c.x - r.x0))];
}

std::optional<uint32_t> TileCache::oldest_tick(TileCoord t) const {
  auto it = tiles_.find({t.tx, t.ty});
  if (it == tiles_.end()) return std::nullopt;
  uint32_t oldest = UINT32_MAX;
  for (std::size_t l = 0; l < it->second.layers.size(); ++l) {
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

uint8_t heading_of_velocity(double vx, double vy, uint8_t fallback) {
  if (!std::isfinite(vx) || !std::isfinite(vy) || (vx == 0.0 && vy == 0.0)) return fallback;
  // Heading h points along step_of(h) (N is +y): the nearest of the eight.
  const double a = std::atan2(vy, vx);
  const auto k = static_cast<int>(std::lround(a / (std::acos(-1.0) / 4.0)));
  return static_cast<uint8_t>(((k % 8) + 8) % 8);
}

DepositMsg layer_add(const MapGeometry& geo, int layer, Cell c, double amount) {
  DepositMsg d;
  d.region = geo.region_of(c);
  d.kind = static_cast<uint8_t>(DepositKind::LayerAdd);
  d.layer = static_cast<uint8_t>(layer);
  d.cell = c;
  d.amount = static_cast<float>(amount);
  return d;
}

void set_state_from_metres(UavStateMsg& state, double x_m, double y_m, double before_x_m, double before_y_m,
                           double cell_size_m, uint8_t& heading) {
  state.x = x_m / cell_size_m - 0.5;
  state.y = y_m / cell_size_m - 0.5;
  state.vx = (x_m - before_x_m) / cell_size_m;
  state.vy = (y_m - before_y_m) / cell_size_m;
  heading = heading_of_velocity(state.vx, state.vy, heading);
  state.heading = heading;
}

}  // namespace pheromesh::core
