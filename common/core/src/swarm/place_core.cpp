#include "pheromesh/core/place_core.hpp"

#include <algorithm>
#include <limits>
#include <numeric>

namespace pheromesh::core {

uint64_t DepositLedger::rejected() const {
  return std::accumulate(rejected_by_reason.begin(), rejected_by_reason.end(), uint64_t{0},
                         [](uint64_t a, const auto& kv) { return a + kv.second; });
}

PlaceCore::PlaceCore(const ScenarioConfig& scenario, RegionId region)
    : geo_(scenario.geometry()),
      region_(region),
      layers_(static_cast<int>(policy_traits(scenario).layers.size())),
      model_(make_place_model(scenario, geo_, region)),
      tiles_(geo_.region_tiles(region)),
      neighbours_(geo_.neighbour_regions(region)),
      swarm_(scenario.uavs) {
  const auto ranges = policy_traits(scenario).layer_ranges;
  ring_range_ = ranges.empty() ? ValueRange{-std::numeric_limits<float>::max(), std::numeric_limits<float>::max()}
                               : ranges.front();
  for (const auto& r : ranges) ring_range_ = {std::min(ring_range_.lo, r.lo), std::max(ring_range_.hi, r.hi)};
}

HaloRing PlaceCore::begin_tick(std::vector<DepositMsg>& deposits, uint32_t tick, std::vector<TargetEventMsg>& events,
                               std::vector<std::string>* rejections, const DepositReach* reach) {
  // Canonical order (DESIGN.md, "Time"): by UAV id, then sequence number.
  std::sort(deposits.begin(), deposits.end(),
            [](const auto& a, const auto& b) { return a.uav != b.uav ? a.uav < b.uav : a.seq < b.seq; });
  for (const auto& d : deposits) {
    ++ledger_.received;
    std::optional<std::string> reason = check_deposit(d, geo_, region_, layers_);
    // Plausibility (plausibility.hpp): refused, and kept out of last_seq_, so
    // that a forger cannot lock a real UAV out.
    if (!reason && check_uav_id(d.uav, swarm_)) {
      reason = "uav id outside the swarm";
      ledger_.refused.add(Refusal::UnknownUav);
    }
    auto it = last_seq_.find(d.uav);
    const std::optional<uint32_t> last = it == last_seq_.end() ? std::nullopt : std::optional<uint32_t>(it->second.seq);
    if (!reason && last && d.seq <= *last) reason = "duplicate or out-of-order sequence number";
    if (!reason && seq_far_ahead(d, tick)) {
      reason = "sequence number far ahead of the uav's";
      ledger_.refused.add(Refusal::SeqFarAhead);
    }
    // Where it lands (after the sequence number: a forged far-ahead seq is
    // counted as such), before its seq is latched.
    if (!reason && reach != nullptr && *reach && (*reach)(d)) {
      reason = "out of its uav's reach (check_deposit_reach)";
      ledger_.refused.add(Refusal::ImplausibleDeposit);
    }
    if (!reason) {
      last_seq_[d.uav] = {d.seq, tick};
      reason = model_->apply(d, tick, events);
    }
    if (reason) {
      ++ledger_.rejected_by_reason[*reason];
      if (rejections != nullptr) {
        rejections->push_back("uav " + std::to_string(d.uav) + " seq " + std::to_string(d.seq) + ": " + *reason);
      }
      continue;
    }
    ++ledger_.applied;
  }
  return model_->begin_step(tick, events);
}

bool PlaceCore::refuses(const DepositMsg& d, uint32_t tick) const {
  return check_uav_id(d.uav, swarm_).has_value() || seq_far_ahead(d, tick);
}

bool PlaceCore::seq_far_ahead(const DepositMsg& d, uint32_t tick) const {
  auto it = last_seq_.find(d.uav);
  if (it == last_seq_.end()) return check_seq_reachable(d.seq, std::nullopt, tick).has_value();
  return check_seq_reachable(d.seq, it->second.seq, tick - std::min(it->second.tick, tick)).has_value();
}

bool PlaceCore::refuses_outright(const DepositMsg& d, uint32_t tick) const {
  return check_deposit(d, geo_, region_, layers_).has_value() || refuses(d, tick);
}

void PlaceCore::reject(const std::vector<DepositMsg>& deposits, const std::string& reason) {
  ledger_.received += deposits.size();
  if (!deposits.empty()) ledger_.rejected_by_reason[reason] += deposits.size();
}

bool PlaceCore::accept_halo(const HaloMsg& h) {
  if (check_halo(h, geo_)) return false;
  if (check_values_in_range(h.target, ring_range_, "halo") || check_values_in_range(h.obstacle, ring_range_, "halo")) {
    ledger_.refused.add(Refusal::ValueOutOfRange);
    return false;
  }
  if (h.target.empty() && h.obstacle.empty()) return true;  // a policy without diffusion
  const HaloRing ring{h.region, h.target, h.obstacle};
  model_->accept_halo(geo_.region_rect(h.region), ring);
  return true;
}

void PlaceCore::finish_tick() { model_->finish_step(); }

TileMsg PlaceCore::tile_layer(TileCoord t, int layer, uint32_t tick) const {
  const Rect tr = geo_.tile_rect(t);
  TileMsg m;
  m.layer = static_cast<uint8_t>(layer);
  m.tile = t;
  m.tick = tick;
  m.region = region_;
  m.width = static_cast<uint16_t>(tr.w);
  m.height = static_cast<uint16_t>(tr.h);
  m.values.resize(static_cast<std::size_t>(tr.area()));
  model_->copy_rect(layer, tr, m.values.data());
  return m;
}

bool PlaceCore::tile(TileCoord t, uint32_t tick, std::vector<TileMsg>& out) const {
  if (!geo_.valid_tile(t) || geo_.region_of_tile(t) != region_) return false;
  for (int l = 0; l < layers_; ++l) out.push_back(tile_layer(t, l, tick));
  return true;
}

void PlaceCore::tiles(uint32_t tick, TileSelection which, std::vector<TileMsg>& out) {
  for (std::size_t ti = 0; ti < tiles_.size(); ++ti) {
    for (int l = 0; l < layers_; ++l) {
      TileMsg m = tile_layer(tiles_[ti], l, tick);
      auto& last = published_[{ti, l}];
      if (which == TileSelection::Changed && last == m.values) continue;
      last = m.values;
      out.push_back(std::move(m));
    }
  }
}

HaloMsg trim_halo(const HaloMsg& full, const MapGeometry& geo, RegionId receiver) {
  HaloMsg part{full.region, full.tick, {}, {}, full.replica};
  if (full.target.empty() && full.obstacle.empty()) return part;
  for (const std::size_t k : ring_indices_facing(geo, geo.region_rect(full.region), geo.region_rect(receiver))) {
    part.target.push_back(k < full.target.size() ? full.target[k] : 0.0F);
    part.obstacle.push_back(k < full.obstacle.size() ? full.obstacle[k] : 0.0F);
  }
  return part;
}

std::optional<HaloMsg> expand_halo(const HaloMsg& part, const MapGeometry& geo, RegionId receiver) {
  if (part.region >= geo.region_count() || receiver >= geo.region_count()) return std::nullopt;
  HaloMsg full{part.region, part.tick, {}, {}, part.replica};
  if (part.target.empty() && part.obstacle.empty()) return full;
  const Rect sender = geo.region_rect(part.region);
  const auto facing = ring_indices_facing(geo, sender, geo.region_rect(receiver));
  if (part.target.size() != facing.size() || part.obstacle.size() != facing.size()) return std::nullopt;
  full.target.assign(ring_size(sender), 0.0F);
  full.obstacle.assign(ring_size(sender), 0.0F);
  for (std::size_t i = 0; i < facing.size(); ++i) {
    full.target[facing[i]] = part.target[i];
    full.obstacle[facing[i]] = part.obstacle[i];
  }
  return full;
}

}  // namespace pheromesh::core
