#include "pheromesh/core/view_server.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "pheromesh/core/uav_core.hpp"

namespace pheromesh::core {

ViewServer::ViewServer(const MapGeometry& geo, int layers, double view_radius, bool neighbours)
    : geo_(geo), layers_(layers), radius_(static_cast<int32_t>(std::ceil(view_radius))), neighbours_(neighbours) {}

void ViewServer::update_tile(const TileMsg& t, uint32_t arrived) {
  // A tile no view reads (off the map, or a layer the policy has not) is
  // not kept: compose looks only at the map's tiles and the policy's layers.
  if (!geo_.valid_tile(t.tile) || t.layer >= layers_) return;
  auto& layers = tiles_[tile_key(t.tile)];
  if (layers.empty()) layers.resize(static_cast<std::size_t>(layers_));
  Held& h = layers[t.layer];
  if (!h.held) {
    h.tile = t;
    h.arrived = arrived;
    h.held = true;
  } else if (t.tick >= h.tile.tick) {
    h.tile = t;  // in place: the values' storage is reused
    h.arrived = std::max(arrived, h.arrived);
  }
}

void ViewServer::update_state(const UavStateMsg& s) {
  auto it = states_.find(s.uav);
  if (it != states_.end()) {
    if (s.tick < it->second.tick) return;
    if (neighbours_) {
      auto o = over_.find(tile_key(geo_.tile_of(state_cell(it->second))));
      if (o != over_.end()) {
        auto at = std::lower_bound(o->second.begin(), o->second.end(), s.uav);
        if (at != o->second.end() && *at == s.uav) o->second.erase(at);
      }
    }
    it->second = s;
  } else {
    states_.emplace(s.uav, s);
  }
  if (neighbours_) {
    auto& over = over_[tile_key(geo_.tile_of(state_cell(s)))];
    auto at = std::lower_bound(over.begin(), over.end(), s.uav);
    if (at == over.end() || *at != s.uav) over.insert(at, s.uav);
  }
}

bool ViewServer::arrive(std::map<RegionId, Arrived>& to, RegionId region, uint32_t tick, uint16_t chunk,
                        uint16_t chunks) {
  Arrived& a = to[region];
  if (tick != a.tick || a.chunks != chunks) {
    if (tick < a.tick) return false;
    // A new tick (or a new split of it): what arrived of the last one goes,
    // its storage stays; the newest complete list stays served.
    a.tick = tick;
    a.chunks = chunks;
    a.seen.clear();
    a.uavs.clear();
  }
  if (std::find(a.seen.begin(), a.seen.end(), chunk) != a.seen.end()) return false;
  a.seen.push_back(chunk);
  return true;
}

void ViewServer::update_served(const FieldMsg& f, uint32_t arrived) {
  for (const auto& s : f.uavs) update_state(s);
  if (!arrive(served_, f.region, f.tick, f.chunk, f.chunks)) return;
  Arrived& a = served_[f.region];
  a.heard = std::max(a.heard, arrived);
  for (const auto& s : f.uavs) a.uavs.push_back(s.uav);
  if (a.complete(a.tick)) a.served = a.uavs;
}

void ViewServer::update_served(std::span<const ServedUav> served, uint32_t tick, std::span<const RegionId> regions,
                               uint32_t swarm, std::vector<std::string>& malformed) {
  // Each listed region, in ascending order and once, as one whole chunk of
  // its served UAVs of `tick` in the order of the list.
  regions_.assign(regions.begin(), regions.end());
  std::sort(regions_.begin(), regions_.end());
  regions_.erase(std::unique(regions_.begin(), regions_.end()), regions_.end());
  listed_.clear();
  for (std::size_t i = 0; i < served.size(); ++i) {
    const ServedUav& u = served[i];
    if (!std::binary_search(regions_.begin(), regions_.end(), u.region)) continue;
    if (u.uav >= swarm) {
      malformed.push_back("served uav " + std::to_string(u.uav) + ": not a UAV of the swarm of " +
                          std::to_string(swarm));
    } else if (auto reason = check_uav_state(neighbour_state(u, tick), geo_)) {
      malformed.push_back("served uav " + std::to_string(u.uav) + ": " + *reason);
    } else {
      listed_.emplace_back(u.region, i);
    }
  }
  std::stable_sort(listed_.begin(), listed_.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  auto next = listed_.begin();
  for (RegionId r : regions_) {
    const auto first = next;
    for (; next != listed_.end() && next->first == r; ++next) update_state(neighbour_state(served[next->second], tick));
    if (!arrive(served_, r, tick, 0, 1)) continue;
    Arrived& a = served_[r];
    a.heard = std::max(a.heard, tick);
    for (auto it = first; it != next; ++it) a.uavs.push_back(served[it->second].uav);
    if (a.complete(a.tick)) a.served = a.uavs;
  }
}

void ViewServer::update_tiles(const FieldMsg& f, uint32_t arrived) {
  for (const auto& t : f.tiles) update_tile(t, arrived);
  arrive(tiles_from_, f.region, f.tick, f.chunk, f.chunks);
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
  // Each tile once (neighbourhoods overlap: many UAVs over few tiles), then sorted.
  std::vector<bool> seen(static_cast<std::size_t>(geo_.tiles_x()) * static_cast<std::size_t>(geo_.tiles_y()));
  std::vector<TileCoord> out;
  for (uint32_t u : uavs) {
    const UavStateMsg* s = state(u);
    if (s == nullptr) continue;
    for (const TileCoord t : geo_.tiles_within(view_centre(*s), radius_ + margin)) {
      const std::size_t i =
          static_cast<std::size_t>(t.ty) * static_cast<std::size_t>(geo_.tiles_x()) + static_cast<std::size_t>(t.tx);
      if (seen[i]) continue;
      seen[i] = true;
      out.push_back(t);
    }
  }
  const auto before = [](TileCoord a, TileCoord b) { return std::pair(a.tx, a.ty) < std::pair(b.tx, b.ty); };
  std::sort(out.begin(), out.end(), before);
  return out;
}

void ViewServer::tiles_for(RegionId home, uint32_t heard_since, int32_t margin, std::span<const TileMsg> own,
                           std::vector<TileMsg>& out) const {
  auto it = served_.find(home);
  if (it == served_.end() || it->second.heard < heard_since || it->second.served.empty()) return;
  // A merge of the needed tiles with `own` sorted by tile (stable: each
  // tile's layers keep their order in `own`).
  std::vector<std::size_t> order(own.size());
  for (std::size_t i = 0; i < own.size(); ++i) order[i] = i;
  const auto key = [&](std::size_t i) { return std::pair(own[i].tile.tx, own[i].tile.ty); };
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  auto at = order.begin();
  for (const TileCoord t : needed_tiles(it->second.served, margin)) {
    const std::pair want(t.tx, t.ty);
    at = std::lower_bound(at, order.end(), want, [&](std::size_t i, const auto& w) { return key(i) < w; });
    for (; at != order.end() && key(*at) == want; ++at) out.push_back(own[*at]);
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
  out.uavs.clear();
  std::size_t shown = 0;  // out.tiles' first `shown` are this view's: the others' storage is reused
  for (const TileCoord t : neighbourhood(view_centre(*self))) {
    const uint64_t key = tile_key(t);
    if (auto it = tiles_.find(key); it != tiles_.end()) {
      for (const Held& h : it->second) {
        // An older tile is one its owner no longer sends: the owner is gone
        // (its region is dark) or this UAV's view did not need it last tick.
        if (!h.held || h.arrived < min_tile_tick) continue;
        if (shown < out.tiles.size()) {
          out.tiles[shown] = h.tile;
        } else {
          out.tiles.push_back(h.tile);
        }
        ++shown;
      }
    }
    if (!neighbours_) continue;
    auto o = over_.find(key);
    if (o == over_.end()) continue;
    for (uint32_t other : o->second) {
      if (other == uav) continue;
      const UavStateMsg& s = states_.at(other);
      if (s.finished || s.tick + max_age < self->tick) continue;
      out.uavs.push_back(s);
    }
  }
  out.tiles.resize(shown);
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
