#include "place_app.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <numeric>

namespace pheromesh::placeagent {

using core::Cell;
using core::DepositKind;
using core::Layer;

uint64_t DepositLedger::rejected() const {
  return std::accumulate(rejected_by_reason.begin(), rejected_by_reason.end(), uint64_t{0},
                         [](uint64_t a, const auto& kv) { return a + kv.second; });
}

PlaceApp::PlaceApp(PlaceConfig cfg, core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus)
    : cfg_(std::move(cfg)),
      scenario_(std::move(scenario)),
      geo_(scenario_.geometry()),
      bus_(std::move(bus)),
      log_(spdlog::default_logger()),
      field_(geo_, cfg_.region, scenario_.layers),
      marks_(scenario_.aco.revisit_period),
      tiles_(geo_.region_tiles(cfg_.region)),
      neighbours_(geo_.neighbour_regions(cfg_.region)) {
  rate_ = scenario_.tick_rate_hz;
}

void PlaceApp::apply_deposits() {
  inbox_.clear();
  bus_->take_deposits(inbox_);
  // Canonical order: by UAV id, then sequence number (DESIGN.md, "Time").
  std::sort(inbox_.begin(), inbox_.end(),
            [](const auto& a, const auto& b) { return a.uav != b.uav ? a.uav < b.uav : a.seq < b.seq; });
  for (const auto& d : inbox_) {
    ++ledger_.received;
    std::optional<std::string> reason = core::check_deposit(d, geo_, cfg_.region);
    if (!reason) {
      auto it = last_seq_.find(d.uav);
      if (it != last_seq_.end() && d.seq <= it->second) reason = "duplicate or out-of-order sequence number";
    }
    if (reason) {
      const uint64_t n = ++ledger_.rejected_by_reason[*reason];
      if (n <= 3) log_->warn("rejected deposit from uav {} seq {}: {}", d.uav, d.seq, *reason);
      continue;
    }
    last_seq_[d.uav] = d.seq;
    ++ledger_.applied;
    switch (static_cast<DepositKind>(d.kind)) {
      case DepositKind::PathVisit:
        field_.add_path_visit(d.cell);
        break;
      case DepositKind::ObstacleMark:
        field_.set_obstacle_switch(d.cell);
        break;
      case DepositKind::TargetMark:
        if (auto ev = marks_.mark(d.cell, tick_)) {
          field_.set_target_switch(d.cell, false);
          field_.set_target_state(d.cell, core::kTargetMarked);
          bus_->publish_target_event({cfg_.region, tick_, static_cast<uint8_t>(ev->kind), ev->cell, ev->response_ticks});
          log_->info("target at ({},{}) {} by uav {}", d.cell.x, d.cell.y,
                     ev->kind == core::MarkEvent::Kind::FirstMarked ? "marked" : "revisited", d.uav);
        }
        break;
    }
  }
}

void PlaceApp::exchange_halos(const core::HaloRing& own) {
  bus_->publish_halo({cfg_.region, tick_, own.target, own.obstacle});
  halo_inbox_.clear();
  bus_->take_halos(halo_inbox_);
  std::map<core::RegionId, bool> fresh;
  for (auto& h : halo_inbox_) {
    if (auto reason = core::check_halo(h, geo_)) {
      log_->warn("dropped halo from region {}: {}", h.region, *reason);
      continue;
    }
    core::HaloRing ring{h.region, std::move(h.target), std::move(h.obstacle)};
    field_.accept_halo(geo_.region_rect(h.region), ring);
    fresh[h.region] = true;
  }
  // Realtime clock: a neighbour that sent nothing new this tick leaves its last
  // ring in the halo; count it so a stalled neighbour is visible in health.
  for (auto r : neighbours_) {
    if (!fresh.contains(r)) ++halos_missing_;
  }
}

void PlaceApp::publish_tiles(bool force) {
  for (std::size_t ti = 0; ti < tiles_.size(); ++ti) {
    const core::Rect tr = geo_.tile_rect(tiles_[ti]);
    for (int l = 0; l < core::kLayerCount; ++l) {
      core::TileMsg m;
      m.layer = static_cast<uint8_t>(l);
      m.tile = tiles_[ti];
      m.tick = tick_;
      m.region = cfg_.region;
      m.width = static_cast<uint16_t>(tr.w);
      m.height = static_cast<uint16_t>(tr.h);
      m.values.reserve(static_cast<std::size_t>(tr.area()));
      for (int32_t y = tr.y0; y < tr.y0 + tr.h; ++y) {
        for (int32_t x = tr.x0; x < tr.x0 + tr.w; ++x) m.values.push_back(field_.value(static_cast<Layer>(l), {x, y}));
      }
      // Only changed tiles travel; TRANSIENT_LOCAL durability keeps the last
      // one for late joiners.
      auto& last = published_[{static_cast<int>(ti), l}];
      if (!force && last == m.values) continue;
      last = m.values;
      bus_->publish_tile(m);
    }
  }
}

void PlaceApp::publish_health(bool finished) {
  bus_->publish_health({cfg_.region, tick_, static_cast<float>(rate_), ledger_.received, ledger_.applied,
                        ledger_.rejected(), halos_missing_, finished});
}

void PlaceApp::step() {
  apply_deposits();
  for (const auto& ev : marks_.advance(tick_)) {
    field_.set_target_switch(ev.cell, true);  // kτ = 1: revisit signal, Shao 2020 eq. (1)
    field_.set_target_state(ev.cell, core::kTargetDue);
    bus_->publish_target_event({cfg_.region, tick_, static_cast<uint8_t>(ev.kind), ev.cell, 0});
    log_->info("target at ({},{}) due for a revisit", ev.cell.x, ev.cell.y);
  }
  const core::HaloRing ring = field_.begin_step();
  exchange_halos(ring);
  field_.finish_step();
  publish_tiles(tick_ == 0);
  ++tick_;
}

int PlaceApp::run() {
  bus_->subscribe_deposits(cfg_.region);
  bus_->subscribe_halos(neighbours_);
  const core::Rect r = geo_.region_rect(cfg_.region);
  log_->info("place agent for region {} [{}..{})x[{}..{}) with {} tiles, {} neighbours, {:.1f} Hz over {}", cfg_.region,
             r.x0, r.x0 + r.w, r.y0, r.y0 + r.h, tiles_.size(), neighbours_.size(), rate_, bus_->vendor());
  runtime::TickClock clock(rate_);
  auto last_health = std::chrono::steady_clock::now();
  while (!runtime::shutdown_requested() && (cfg_.max_ticks == 0 || tick_ < cfg_.max_ticks)) {
    step();
    if (std::chrono::steady_clock::now() - last_health >= std::chrono::milliseconds(500)) {
      rate_ = clock.measured_rate() > 0 ? clock.measured_rate() : rate_;
      publish_health(false);
      last_health = std::chrono::steady_clock::now();
    }
    if (!clock.wait_next()) break;
  }
  // Drain: deposits that arrived after the last tick are still applied (or
  // rejected) and counted, then the final health is published and flushed.
  step();
  publish_health(true);
  bus_->flush(std::chrono::seconds(3));
  log_->info("region {} finished at tick {}: deposits received {}, applied {}, rejected {}", cfg_.region, tick_,
             ledger_.received, ledger_.applied, ledger_.rejected());
  for (const auto& [reason, n] : ledger_.rejected_by_reason) log_->info("  rejected {}: {}", n, reason);
  return 0;
}

}  // namespace pheromesh::placeagent
