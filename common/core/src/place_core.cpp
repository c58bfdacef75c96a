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
      field_(geo_, region, scenario.layers),
      marks_(scenario.aco.revisit_period),
      tiles_(geo_.region_tiles(region)),
      neighbours_(geo_.neighbour_regions(region)) {}

HaloRing PlaceCore::begin_tick(std::vector<DepositMsg>& deposits, uint32_t tick, std::vector<TargetEventMsg>& events,
                               std::vector<std::string>* rejections) {
  // Canonical order (DESIGN.md, "Time"): by UAV id, then sequence number.
  std::sort(deposits.begin(), deposits.end(),
            [](const auto& a, const auto& b) { return a.uav != b.uav ? a.uav < b.uav : a.seq < b.seq; });
  for (const auto& d : deposits) {
    ++ledger_.received;
    std::optional<std::string> reason = check_deposit(d, geo_, region_);
    if (!reason) {
      auto it = last_seq_.find(d.uav);
      if (it != last_seq_.end() && d.seq <= it->second) reason = "duplicate or out-of-order sequence number";
    }
    if (reason) {
      ++ledger_.rejected_by_reason[*reason];
      if (rejections != nullptr) {
        rejections->push_back("uav " + std::to_string(d.uav) + " seq " + std::to_string(d.seq) + ": " + *reason);
      }
      continue;
    }
    last_seq_[d.uav] = d.seq;
    ++ledger_.applied;
    switch (static_cast<DepositKind>(d.kind)) {
      case DepositKind::PathVisit:
        field_.add_path_visit(d.cell);
        break;
      case DepositKind::ObstacleMark:
        field_.set_obstacle_switch(d.cell);  // kε = 1, Shao 2020 eq. (3)
        break;
      case DepositKind::TargetMark:
        if (auto ev = marks_.mark(d.cell, tick)) {
          field_.set_target_switch(d.cell, false);
          field_.set_target_state(d.cell, kTargetMarked);
          events.push_back({region_, tick, static_cast<uint8_t>(ev->kind), ev->cell, ev->response_ticks});
        }
        break;
    }
  }
  for (const auto& ev : marks_.advance(tick)) {
    field_.set_target_switch(ev.cell, true);  // kτ = 1: revisit signal, Shao 2020 eq. (1)
    field_.set_target_state(ev.cell, kTargetDue);
    events.push_back({region_, tick, static_cast<uint8_t>(ev.kind), ev.cell, 0});
  }
  return field_.begin_step();
}

void PlaceCore::reject(const std::vector<DepositMsg>& deposits, const std::string& reason) {
  ledger_.received += deposits.size();
  if (!deposits.empty()) ledger_.rejected_by_reason[reason] += deposits.size();
}

bool PlaceCore::accept_halo(const HaloMsg& h) {
  if (check_halo(h, geo_)) return false;
  const HaloRing ring{h.region, h.target, h.obstacle};
  field_.accept_halo(geo_.region_rect(h.region), ring);
  return true;
}

void PlaceCore::finish_tick() { field_.finish_step(); }

void PlaceCore::tiles(uint32_t tick, bool changed_only, std::vector<TileMsg>& out) {
  for (std::size_t ti = 0; ti < tiles_.size(); ++ti) {
    const Rect tr = geo_.tile_rect(tiles_[ti]);
    for (int l = 0; l < kLayerCount; ++l) {
      TileMsg m;
      m.layer = static_cast<uint8_t>(l);
      m.tile = tiles_[ti];
      m.tick = tick;
      m.region = region_;
      m.width = static_cast<uint16_t>(tr.w);
      m.height = static_cast<uint16_t>(tr.h);
      m.values.reserve(static_cast<std::size_t>(tr.area()));
      for (int32_t y = tr.y0; y < tr.y0 + tr.h; ++y) {
        for (int32_t x = tr.x0; x < tr.x0 + tr.w; ++x) m.values.push_back(field_.value(static_cast<Layer>(l), {x, y}));
      }
      auto& last = published_[{ti, l}];
      if (changed_only && last == m.values) continue;
      last = m.values;
      out.push_back(std::move(m));
    }
  }
}

}  // namespace pheromesh::core
