#include "place_app.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <set>
#include <thread>

namespace pheromesh::placeagent {

using Clock = std::chrono::steady_clock;

PlaceApp::PlaceApp(PlaceConfig cfg, core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus)
    : cfg_(std::move(cfg)),
      scenario_(std::move(scenario)),
      geo_(scenario_.geometry()),
      bus_(std::move(bus)),
      log_(spdlog::default_logger()),
      core_(scenario_, cfg_.region),
      rate_(scenario_.tick_rate_hz) {}

void PlaceApp::step(uint32_t tick, bool wait_for_halos, bool all_tiles, std::optional<uint32_t> expected_deposits) {
  inbox_.clear();
  bus_->take_deposits(inbox_);
  if (expected_deposits) {
    const auto deadline = Clock::now() + std::chrono::seconds(30);
    const auto of_tick = [&] {
      return static_cast<uint32_t>(std::count_if(inbox_.begin(), inbox_.end(), [&](const auto& d) { return d.tick == tick; }));
    };
    while (of_tick() < *expected_deposits) {
      if (Clock::now() > deadline || runtime::shutdown_requested()) {
        log_->error("tick {}: {} of {} announced deposits arrived; applying those", tick, of_tick(), *expected_deposits);
        break;
      }
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      bus_->take_deposits(inbox_);
    }
  }
  events_.clear();
  rejections_.clear();
  const core::HaloRing ring = core_.begin_tick(inbox_, tick, events_, &rejections_);
  for (const auto& r : rejections_) {
    if (core_.ledger().rejected() <= 20) log_->warn("rejected deposit from {}", r);
  }
  for (const auto& e : events_) {
    bus_->publish_target_event(e);
    log_->info("target at ({},{}) {} at tick {}", e.cell.x, e.cell.y,
               e.kind == 0 ? "marked" : e.kind == 1 ? "due for a revisit" : "revisited", tick);
  }
  bus_->publish_halo({cfg_.region, tick, ring.target, ring.obstacle});
  // Neighbour rings. Realtime: whatever arrived (a neighbour that sent
  // nothing new leaves its last ring in the halo, counted as missing).
  // Lockstep: exactly the rings of this tick, waited for.
  std::set<core::RegionId> fresh;
  const auto deadline = Clock::now() + std::chrono::seconds(30);
  for (;;) {
    halo_inbox_.clear();
    bus_->take_halos(halo_inbox_);
    for (const auto& h : halo_inbox_) {
      if (wait_for_halos && h.tick != tick) continue;
      if (!core_.accept_halo(h)) {
        log_->warn("dropped malformed halo from region {}", h.region);
        continue;
      }
      fresh.insert(h.region);
    }
    if (!wait_for_halos || fresh.size() >= core_.neighbours().size()) break;
    if (Clock::now() > deadline || runtime::shutdown_requested()) {
      log_->error("tick {}: rings of {} of {} neighbours did not arrive", tick, core_.neighbours().size() - fresh.size(),
                  core_.neighbours().size());
      break;
    }
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  halos_missing_ += core_.neighbours().size() - std::min(fresh.size(), core_.neighbours().size());
  core_.finish_tick();
  tiles_out_.clear();
  core_.tiles(tick, !all_tiles, tiles_out_);
  for (const auto& t : tiles_out_) bus_->publish_tile(t);
}

void PlaceApp::publish_health(uint32_t tick, bool finished) {
  const auto& l = core_.ledger();
  bus_->publish_health({cfg_.region, tick, static_cast<float>(rate_), l.received, l.applied, l.rejected(), halos_missing_,
                        finished});
}

void PlaceApp::log_summary(uint32_t tick) {
  const auto& l = core_.ledger();
  log_->info("region {} finished at tick {}: deposits received {}, applied {}, rejected {}", cfg_.region, tick,
             l.received, l.applied, l.rejected());
  for (const auto& [reason, n] : l.rejected_by_reason) log_->info("  rejected {}: {}", n, reason);
}

int PlaceApp::run_realtime() {
  runtime::TickClock clock(rate_);
  auto last_health = Clock::now();
  uint32_t tick = 0;
  while (!runtime::shutdown_requested() && (cfg_.max_ticks == 0 || tick < cfg_.max_ticks)) {
    commands_->take();
    // Paused from the console: no evaporation, no diffusion, deposits wait
    // in the reader; health still goes out.
    if (!commands_->paused()) {
      step(tick, false, tick == 0);
      ++tick;
    }
    if (Clock::now() - last_health >= std::chrono::milliseconds(500)) {
      rate_ = clock.measured_rate() > 0 ? clock.measured_rate() : rate_;
      publish_health(tick, false);
      last_health = Clock::now();
    }
    if (!clock.wait_next()) break;
  }
  // Drain: deposits that arrived after the last tick are still applied (or
  // rejected) and counted before the final health.
  step(tick, false, false);
  publish_health(tick, true);
  bus_->flush(std::chrono::seconds(3));
  log_summary(tick);
  return 0;
}

int PlaceApp::run_lockstep() {
  bus_->subscribe_clock();
  std::vector<core::ClockMsg> cmds;
  int64_t done_tick = -1;
  bool stop = false;
  while (!stop && !runtime::shutdown_requested()) {
    cmds.clear();
    bus_->take_clock(cmds);
    for (const auto& c : cmds) {
      if (c.phase == static_cast<uint8_t>(core::ClockPhase::Stop)) {
        stop = true;
      } else if (c.phase == static_cast<uint8_t>(core::ClockPhase::Place) && static_cast<int64_t>(c.tick) > done_tick) {
        // Every tile, every tick: a UAV waits for tiles of exactly this tick.
        uint32_t expected = 0;
        for (const auto& rc : c.deposits) expected += rc.region == cfg_.region ? rc.count : 0;
        step(c.tick, true, true, expected);
        publish_health(c.tick, false);
        bus_->flush(std::chrono::seconds(10));
        bus_->publish_phase_done({core::process_key(core::kRolePlace, cfg_.region), c.tick, c.phase, 0, {}});
        bus_->flush(std::chrono::seconds(10));
        done_tick = c.tick;
      }
    }
    if (cmds.empty()) std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  // Wait for SIGTERM from the launcher; deposits arriving now (none in a
  // clean run) are counted, not applied to the field, so the final field
  // stays that of the last conducted tick.
  while (!runtime::shutdown_requested()) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  inbox_.clear();
  bus_->take_deposits(inbox_);
  if (!inbox_.empty()) log_->warn("{} deposits arrived after the last tick; rejected", inbox_.size());
  core_.reject(inbox_, "arrived after the last lockstep tick");
  const auto final_tick = static_cast<uint32_t>(std::max<int64_t>(done_tick, 0));
  publish_health(final_tick, true);
  bus_->flush(std::chrono::seconds(3));
  log_summary(final_tick);
  return 0;
}

int PlaceApp::run() {
  bus_->subscribe_deposits(cfg_.region);
  bus_->subscribe_halos(core_.neighbours());
  commands_ = std::make_unique<runtime::SwarmCommands>(*bus_, log_);
  const core::Rect r = geo_.region_rect(cfg_.region);
  log_->info("place agent for region {} [{}..{})x[{}..{}) with {} tiles, {} neighbours, {} clock{} over {}", cfg_.region,
             r.x0, r.x0 + r.w, r.y0, r.y0 + r.h, core_.owned_tiles().size(), core_.neighbours().size(), cfg_.common.clock,
             cfg_.common.lockstep() ? "" : fmt::format(" at {:.1f} Hz", rate_), bus_->vendor());
  return cfg_.common.lockstep() ? run_lockstep() : run_realtime();
}

}  // namespace pheromesh::placeagent
