#include "pheromesh/core/view_server.hpp"

#include <algorithm>
#include <cmath>

#include "pheromesh/core/uav_core.hpp"

namespace pheromesh::core {

ViewServer::ViewServer(const MapGeometry& geo, int layers, double view_radius)
    : geo_(geo), layers_(layers), radius_(static_cast<int32_t>(std::ceil(view_radius))) {}

void ViewServer::update_tile(const TileMsg& t) {
  auto [it, fresh] = tiles_.try_emplace({t.tile.tx, t.tile.ty, static_cast<int>(t.layer)}, t);
  if (!fresh && t.tick >= it->second.tick) it->second = t;
}

void ViewServer::update_state(const UavStateMsg& s) {
  auto it = states_.find(s.uav);
  if (it != states_.end()) {
    if (s.tick < it->second.tick) return;
    const TileCoord before = geo_.tile_of(state_cell(it->second));
    over_[{before.tx, before.ty}].erase(s.uav);
    it->second = s;
  } else {
    states_.emplace(s.uav, s);
  }
  const TileCoord now = geo_.tile_of(state_cell(s));
  over_[{now.tx, now.ty}].insert(s.uav);
}

void ViewServer::update_field(const FieldMsg& f) {
  for (const auto& t : f.tiles) update_tile(t);
  for (const auto& s : f.uavs) update_state(s);
  Arrived& a = fields_[f.region];
  if (f.tick != a.tick || a.chunks != f.chunks) {
    if (f.tick < a.tick) return;
    a = Arrived{f.tick, f.chunks, {}};
  }
  a.seen.insert(f.chunk);
}

bool ViewServer::holds_fields(uint32_t tick, std::span<const RegionId> regions) const {
  return std::all_of(regions.begin(), regions.end(), [&](RegionId r) {
    auto it = fields_.find(r);
    return it != fields_.end() && it->second.tick == tick && it->second.seen.size() >= it->second.chunks;
  });
}

std::string ViewServer::missing_fields(uint32_t tick, std::span<const RegionId> regions) const {
  std::string out;
  for (RegionId r : regions) {
    auto it = fields_.find(r);
    if (it != fields_.end() && it->second.tick == tick && it->second.seen.size() >= it->second.chunks) continue;
    if (!out.empty()) out += "; ";
    out += "region " + std::to_string(r) + ": ";
    if (it == fields_.end()) {
      out += "none";
    } else {
      out += "tick " + std::to_string(it->second.tick) + ", " + std::to_string(it->second.seen.size()) + " of " +
             std::to_string(it->second.chunks) + " chunks";
    }
  }
  return out;
}

std::vector<TileCoord> ViewServer::neighbourhood(Cell c) const { return geo_.tiles_within(c, radius_); }

const UavStateMsg* ViewServer::state(uint32_t uav) const {
  auto it = states_.find(uav);
  return it == states_.end() ? nullptr : &it->second;
}

bool ViewServer::compose(uint32_t uav, uint32_t tick, uint32_t max_age, ViewMsg& out) const {
  const UavStateMsg* self = state(uav);
  if (self == nullptr) return false;
  out.uav = uav;
  out.tick = tick;
  out.tiles.clear();
  out.uavs.clear();
  const Cell centre = geo_.in_map(self->view) ? self->view : state_cell(*self);
  for (const TileCoord t : neighbourhood(centre)) {
    for (int l = 0; l < layers_; ++l) {
      if (auto it = tiles_.find({t.tx, t.ty, l}); it != tiles_.end()) out.tiles.push_back(it->second);
    }
    auto o = over_.find({t.tx, t.ty});
    if (o == over_.end()) continue;
    for (uint32_t other : o->second) {
      if (other == uav) continue;
      const UavStateMsg& s = states_.at(other);
      if (s.finished || s.tick + max_age < self->tick) continue;
      out.uavs.push_back(s);
    }
  }
  // By id, like the readers of the tiles would have delivered them per UAV.
  std::sort(out.uavs.begin(), out.uavs.end(), [](const auto& a, const auto& b) { return a.uav < b.uav; });
  return true;
}

std::vector<FieldMsg> make_field_chunks(RegionId region, uint32_t tick, const std::vector<TileMsg>& tiles,
                                        const std::vector<UavStateMsg>& states) {
  const std::size_t by_tiles = (tiles.size() + kMaxFieldTiles - 1) / kMaxFieldTiles;
  const std::size_t by_states = (states.size() + kMaxFieldUavs - 1) / kMaxFieldUavs;
  const std::size_t n = std::max<std::size_t>({1, by_tiles, by_states});
  std::vector<FieldMsg> out(n);
  for (std::size_t c = 0; c < n; ++c) {
    FieldMsg& f = out[c];
    f.region = region;
    f.chunk = static_cast<uint16_t>(c);
    f.chunks = static_cast<uint16_t>(n);
    f.tick = tick;
    const std::size_t t0 = std::min(tiles.size(), c * kMaxFieldTiles);
    const std::size_t t1 = std::min(tiles.size(), t0 + kMaxFieldTiles);
    f.tiles.assign(tiles.begin() + static_cast<std::ptrdiff_t>(t0), tiles.begin() + static_cast<std::ptrdiff_t>(t1));
    const std::size_t s0 = std::min(states.size(), c * kMaxFieldUavs);
    const std::size_t s1 = std::min(states.size(), s0 + kMaxFieldUavs);
    f.uavs.assign(states.begin() + static_cast<std::ptrdiff_t>(s0), states.begin() + static_cast<std::ptrdiff_t>(s1));
  }
  return out;
}

}  // namespace pheromesh::core
