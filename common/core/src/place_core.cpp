#include "pheromesh/core/place_core.hpp"

#include <algorithm>
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
      neighbours_(geo_.neighbour_regions(region)) {}

HaloRing PlaceCore::begin_tick(std::vector<DepositMsg>& deposits, uint32_t tick, std::vector<TargetEventMsg>& events,
                               std::vector<std::string>* rejections) {
  // Canonical order (DESIGN.md, "Time"): by UAV id, then sequence number.
  std::sort(deposits.begin(), deposits.end(),
            [](const auto& a, const auto& b) { return a.uav != b.uav ? a.uav < b.uav : a.seq < b.seq; });
  for (const auto& d : deposits) {
    ++ledger_.received;
    std::optional<std::string> reason = check_deposit(d, geo_, region_, layers_);
    if (!reason) {
      auto it = last_seq_.find(d.uav);
      if (it != last_seq_.end() && d.seq <= it->second) reason = "duplicate or out-of-order sequence number";
    }
    if (!reason) {
      last_seq_[d.uav] = d.seq;
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

void PlaceCore::reject(const std::vector<DepositMsg>& deposits, const std::string& reason) {
  ledger_.received += deposits.size();
  if (!deposits.empty()) ledger_.rejected_by_reason[reason] += deposits.size();
}

bool PlaceCore::accept_halo(const HaloMsg& h) {
  if (check_halo(h, geo_)) return false;
  if (h.target.empty() && h.obstacle.empty()) return true;  // a policy without diffusion
  const HaloRing ring{h.region, h.target, h.obstacle};
  model_->accept_halo(geo_.region_rect(h.region), ring);
  return true;
}

void PlaceCore::finish_tick() { model_->finish_step(); }

void PlaceCore::tiles(uint32_t tick, bool changed_only, std::vector<TileMsg>& out) {
  for (std::size_t ti = 0; ti < tiles_.size(); ++ti) {
    const Rect tr = geo_.tile_rect(tiles_[ti]);
    for (int l = 0; l < layers_; ++l) {
      TileMsg m;
      m.layer = static_cast<uint8_t>(l);
      m.tile = tiles_[ti];
      m.tick = tick;
      m.region = region_;
      m.width = static_cast<uint16_t>(tr.w);
      m.height = static_cast<uint16_t>(tr.h);
      m.values.reserve(static_cast<std::size_t>(tr.area()));
      for (int32_t y = tr.y0; y < tr.y0 + tr.h; ++y) {
        for (int32_t x = tr.x0; x < tr.x0 + tr.w; ++x) m.values.push_back(model_->value(l, {x, y}));
      }
      auto& last = published_[{ti, l}];
      if (changed_only && last == m.values) continue;
      last = m.values;
      out.push_back(std::move(m));
    }
  }
}

}  // namespace pheromesh::core
