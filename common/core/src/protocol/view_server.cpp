#include "pheromesh/core/view_server.hpp"

#include <algorithm>
#include <cmath>

#include "pheromesh/core/uav_core.hpp"

namespace pheromesh::core {

ViewServer::ViewServer(const MapGeometry& geo, int layers, double view_radius, bool neighbours)
    : geo_(geo), layers_(layers), radius_(static_cast<int32_t>(std::ceil(view_radius))), neighbours_(neighbours) {}

void ViewServer::update_tile(const TileMsg& t, uint32_t arrived) {
  auto [it, fresh] = tiles_.try_emplace({t.tile.tx, t.tile.ty, static_cast<int>(t.layer)}, Held{t, arrived});
  if (!fresh && t.tick >= it->second.tile.tick) it->second = Held{t, std::max(arrived, it->second.arrived)};
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

bool ViewServer::arrive(std::map<RegionId, Arrived>& to, const FieldMsg& f) {
  Arrived& a = to[f.region];
  if (f.tick != a.tick || a.chunks != f.chunks) {
    if (f.tick < a.tick) return false;
    a = Arrived{f.tick, f.chunks, {}, {}, std::move(a.served), a.heard};
  }
  return a.seen.insert(f.chunk).second;
}

void ViewServer::update_served(const FieldMsg& f, uint32_t arrived) {
  for (const auto& s : f.uavs) update_state(s);
  if (!arrive(served_, f)) return;
  Arrived& a = served_[f.region];
  a.heard = std::max(a.heard, arrived);
  for (const auto& s : f.uavs) a.uavs.push_back(s.uav);
  if (a.complete(a.tick)) a.served = a.uavs;
}

void ViewServer::update_served(std::span<const ServedUav> served, uint32_t tick, std::span<const RegionId> regions,
                               uint32_t swarm, std::vector<std::string>& malformed) {
  std::map<RegionId, FieldMsg> by_region;
  for (RegionId r : regions) by_region[r] = FieldMsg{r, 0, 1, tick, {}, {}, 0, {}, 0};
  for (const ServedUav& u : served) {
    auto it = by_region.find(u.region);
    if (it == by_region.end()) continue;
    UavStateMsg s = neighbour_state(u, tick);
    if (u.uav >= swarm) {
      malformed.push_back("served uav " + std::to_string(u.uav) + ": not a UAV of the swarm of " +
                          std::to_string(swarm));
    } else if (auto reason = check_uav_state(s, geo_)) {
      malformed.push_back("served uav " + std::to_string(u.uav) + ": " + *reason);
    } else {
      it->second.uavs.push_back(std::move(s));
    }
  }
  for (const auto& [r, f] : by_region) update_served(f, tick);
}

void ViewServer::update_tiles(const FieldMsg& f, uint32_t arrived) {
  for (const auto& t : f.tiles) update_tile(t, arrived);
  arrive(tiles_from_, f);
}

bool ViewServer::holds_served(uint32_t tick, std::span<const RegionId> regions) const {
  return std::all_of(regions.begin(), regions.end(), [&](RegionId r) {
    auto it = served_.find(r);
    return it != served_.end() && it->second.complete(tick);
  });
}

bool ViewServer::holds_tiles(uint32_t tick, std::span<const RegionId> owners) const {
  return std::all_of(owners.begin(), owners.end(), [&](RegionId r) {
    auto it = tiles_from_.find(r);
    return it != tiles_from_.end() && it->second.complete(tick);
  });
}

std::string ViewServer::missing(const std::map<RegionId, Arrived>& from, uint32_t tick,
                                std::span<const RegionId> regions) {
  std::string out;
  for (RegionId r : regions) {
    auto it = from.find(r);
    if (it != from.end() && it->second.complete(tick)) continue;
    if (!out.empty()) out += "; ";
    out += "region " + std::to_string(r) + ": ";
    if (it == from.end()) {
      out += "none";
    } else {
      out += "tick " + std::to_string(it->second.tick) + ", " + std::to_string(it->second.seen.size()) + " of " +
             std::to_string(it->second.chunks) + " chunks";
    }
  }
  return out;
}

std::string ViewServer::missing_served(uint32_t tick, std::span<const RegionId> regions) const {
  return missing(served_, tick, regions);
}

std::string ViewServer::missing_tiles(uint32_t tick, std::span<const RegionId> owners) const {
  return missing(tiles_from_, tick, owners);
}

std::vector<uint32_t> ViewServer::served_by(RegionId region, uint32_t heard_since) const {
  auto it = served_.find(region);
  return it == served_.end() || it->second.heard < heard_since ? std::vector<uint32_t>{} : it->second.served;
}

Cell ViewServer::view_centre(const UavStateMsg& s) const { return geo_.in_map(s.view) ? s.view : state_cell(s); }

std::vector<TileCoord> ViewServer::needed_tiles(std::span<const uint32_t> uavs, int32_t margin) const {
  std::set<std::pair<int32_t, int32_t>> seen;
  std::vector<TileCoord> out;
  for (uint32_t u : uavs) {
    const UavStateMsg* s = state(u);
    if (s == nullptr) continue;
    for (const TileCoord t : geo_.tiles_within(view_centre(*s), radius_ + margin)) {
      if (seen.insert({t.tx, t.ty}).second) out.push_back(t);
    }
  }
  std::sort(out.begin(), out.end(), [](TileCoord a, TileCoord b) { return std::pair(a.tx, a.ty) < std::pair(b.tx, b.ty); });
  return out;
}

void ViewServer::tiles_for(RegionId home, uint32_t heard_since, int32_t margin, std::span<const TileMsg> own,
                           std::vector<TileMsg>& out) const {
  const std::vector<uint32_t> uavs = served_by(home, heard_since);
  if (uavs.empty()) return;
  std::map<std::pair<int32_t, int32_t>, std::vector<std::size_t>> by_tile;
  for (std::size_t i = 0; i < own.size(); ++i) by_tile[{own[i].tile.tx, own[i].tile.ty}].push_back(i);
  for (const TileCoord t : needed_tiles(uavs, margin)) {
    auto it = by_tile.find({t.tx, t.ty});
    if (it == by_tile.end()) continue;  // another region's tile
    for (std::size_t i : it->second) out.push_back(own[i]);
  }
}

std::vector<RegionId> ViewServer::owners_for(std::span<const uint32_t> uavs, int32_t margin, RegionId self) const {
  std::set<RegionId> owners;
  for (const TileCoord t : needed_tiles(uavs, margin)) {
    const RegionId r = geo_.region_of_tile(t);
    if (r != self) owners.insert(r);
  }
  return {owners.begin(), owners.end()};
}

std::vector<TileCoord> ViewServer::neighbourhood(Cell c) const { return geo_.tiles_within(c, radius_); }

const UavStateMsg* ViewServer::state(uint32_t uav) const {
  auto it = states_.find(uav);
  return it == states_.end() ? nullptr : &it->second;
}

bool ViewServer::compose(uint32_t uav, uint32_t tick, uint32_t max_age, uint32_t min_tile_tick, ViewMsg& out) const {
  const UavStateMsg* self = state(uav);
  if (self == nullptr) return false;
  out.uav = uav;
  out.tick = tick;
  out.tiles.clear();
  out.uavs.clear();
  for (const TileCoord t : neighbourhood(view_centre(*self))) {
    for (int l = 0; l < layers_; ++l) {
      // An older tile is one its owner no longer sends: the owner is gone
      // (its region is dark) or this UAV's view did not need it last tick.
      auto it = tiles_.find({t.tx, t.ty, l});
      if (it != tiles_.end() && it->second.arrived >= min_tile_tick) out.tiles.push_back(it->second.tile);
    }
    if (!neighbours_) continue;
    auto o = over_.find({t.tx, t.ty});
    if (o == over_.end()) continue;
    for (uint32_t other : o->second) {
      if (other == uav) continue;
      const UavStateMsg& s = states_.at(other);
      if (s.finished || s.tick + max_age < self->tick) continue;
      out.uavs.push_back(s);
    }
  }
  // At most kMaxViewUavs (the IDL bound; only a swarm of more UAVs can
  // crowd a view so): the nearest, ties by id.
  if (out.uavs.size() > kMaxViewUavs) {
    const auto d2 = [&](const UavStateMsg& s) {
      const double dx = s.x - self->x, dy = s.y - self->y;
      return dx * dx + dy * dy;
    };
    std::nth_element(out.uavs.begin(), out.uavs.begin() + static_cast<std::ptrdiff_t>(kMaxViewUavs), out.uavs.end(),
                     [&](const auto& a, const auto& b) {
                       const double da = d2(a), db = d2(b);
                       return da < db || (da == db && a.uav < b.uav);
                     });
    out.uavs.resize(kMaxViewUavs);
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
