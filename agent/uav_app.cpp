#include "uav_app.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <thread>

namespace pheromesh::agent {

using Clock = std::chrono::steady_clock;

UavApp::UavApp(UavConfig cfg, core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus)
    : cfg_(std::move(cfg)),
      scenario_(std::move(scenario)),
      geo_(scenario_.geometry()),
      world_(geo_, scenario_.obstacles, scenario_.targets),
      bus_(std::move(bus)),
      log_(spdlog::default_logger()),
      core_(scenario_, world_, cfg_.id, cfg_.common.lockstep()),
      layers_(static_cast<int>(core::policy_traits(scenario_).layers.size())) {}

void UavApp::receive() {
  tile_inbox_.clear();
  bus_->take_tiles(tile_inbox_);
  tile_samples_received_ += tile_inbox_.size();
  for (const auto& t : tile_inbox_) {
    if (auto reason = core::check_tile(t, geo_, layers_)) {
      if (++samples_rejected_ <= 3) log_->warn("dropped tile ({},{}) layer {}: {}", t.tile.tx, t.tile.ty, t.layer, *reason);
      continue;
    }
    core_.receive_tile(t);
  }
  state_inbox_.clear();
  bus_->take_uav_states(state_inbox_);
  for (const auto& s : state_inbox_) {
    if (auto reason = core::check_uav_state(s, geo_)) {
      if (++samples_rejected_ <= 3) log_->warn("dropped state of uav {}: {}", s.uav, *reason);
      continue;
    }
    core_.receive_neighbour(s);
  }
  broadcast_inbox_.clear();
  bus_->take_broadcasts(broadcast_inbox_);
  for (const auto& b : broadcast_inbox_) {
    if (auto reason = core::check_broadcast(b)) {
      if (++samples_rejected_ <= 3) log_->warn("dropped broadcast of uav {}: {}", b.uav, *reason);
      continue;
    }
    core_.receive_broadcast(b);
  }
}

void UavApp::wait_for_tick(uint32_t tick, const core::ClockMsg& announced) {
  const auto deadline = Clock::now() + std::chrono::seconds(30);
  for (;;) {
    receive();
    uint32_t missing = 0;
    for (const auto& t : core_.neighbourhood()) {
      const auto oldest = core_.tiles().oldest_tick(t);
      missing += (!oldest || *oldest < tick) ? 1 : 0;
    }
    const bool peers = core_.holds_tick(tick, announced.occupancy, announced.broadcasts);
    if (missing == 0 && peers) {
      if (log_->should_log(spdlog::level::debug)) {
        std::string occ;
        for (const auto& t : announced.occupancy) occ += fmt::format(" ({},{}):{}", t.tile.tx, t.tile.ty, t.count);
        log_->debug("tick {} announced{} and {} broadcasts", tick, occ, announced.broadcasts);
      }
      return;
    }
    if (Clock::now() > deadline || runtime::shutdown_requested()) {
      log_->error("tick {}: {} neighbourhood tiles{} did not arrive; deciding without them", tick, missing,
                  peers ? "" : " and some neighbour states or broadcasts");
      return;
    }
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
}

void UavApp::step(uint32_t tick, bool finished) {
  written_.clear();
  broadcast_written_ = false;
  if (!finished) {
    core_.step(tick, out_);
    for (const auto& d : out_.deposits) {
      // A deposit written while no place agent of that region is matched
      // would be lost silently; count it as undeliverable instead of sent.
      if (bus_->matched_deposit_readers(d.region) == 0) {
        ++deposits_undeliverable_;
      } else if (bus_->publish_deposit(d)) {
        ++deposits_sent_;
        ++written_[d.region];
      }
    }
    for (const auto& d : out_.detections) bus_->publish_detection(d);
    if (out_.broadcast) broadcast_written_ = bus_->publish_broadcast(*out_.broadcast);
    bus_->set_neighbourhood(core_.neighbourhood());
  }
  core::UavStateMsg s = core_.last_state();
  if (!finished) {
    log_->debug("tick {} at ({:.9g}, {:.9g}) v ({:.9g}, {:.9g}) role {}: saw {} neighbours, {} broadcasts, {} tiles", tick,
                s.x, s.y, s.vx, s.vy, s.role, core_.last_view_neighbours(), core_.last_view_broadcasts(),
                core_.neighbourhood().size());
  }
  s.deposits_sent = deposits_sent_;
  s.tile_samples_received = tile_samples_received_;
  s.finished = finished;
  bus_->publish_uav_state(s, geo_.tile_of(core::state_cell(s)));
}

void UavApp::handle_commands() {
  for (const auto& c : commands_->take()) {
    if (c.kind == static_cast<uint8_t>(core::CommandKind::Obstacle)) {
      const auto cells = world_.add_obstacle({c.x, c.y, c.w, c.h});
      log_->info("pop-up obstacle: {} new obstacle cells", cells);
    } else if (c.kind == static_cast<uint8_t>(core::CommandKind::Target)) {
      const auto index = world_.add_target({c.x, c.y});
      log_->info("new target {} at ({},{})", index, c.x, c.y);
    }
  }
}

void UavApp::wait_for_place_agents() {
  // Wait (bounded) until every region's place agent is matched, so the first
  // deposits are not lost to discovery.
  const auto deadline = Clock::now() + std::chrono::milliseconds(static_cast<int64_t>(cfg_.wait_for_places_s * 1000));
  for (;;) {
    uint32_t missing = 0;
    for (core::RegionId r = 0; r < geo_.region_count(); ++r) missing += bus_->matched_deposit_readers(r) == 0 ? 1 : 0;
    if (missing == 0) return;
    if (Clock::now() > deadline || runtime::shutdown_requested()) {
      log_->warn("starting with {} place agent(s) not discovered", missing);
      return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

int UavApp::run_realtime(uint32_t ticks) {
  step(0, false);
  runtime::TickClock clock(scenario_.tick_rate_hz);
  uint32_t tick = 0;
  while (tick < ticks && clock.wait_next()) {
    handle_commands();
    if (commands_->paused()) {
      receive();  // keeps the inboxes drained and the liveliness asserted
      continue;
    }
    ++tick;
    receive();
    step(tick, false);
  }
  return static_cast<int>(tick);
}

int UavApp::run_lockstep(uint32_t ticks) {
  bus_->subscribe_clock();
  std::vector<core::ClockMsg> cmds;
  int64_t done = -1;
  bool stop = false;
  while (!stop && !runtime::shutdown_requested()) {
    cmds.clear();
    bus_->take_clock(cmds);
    for (const auto& c : cmds) {
      if (c.phase == static_cast<uint8_t>(core::ClockPhase::Stop)) stop = true;
      if (c.phase != static_cast<uint8_t>(core::ClockPhase::Uav) || static_cast<int64_t>(c.tick) <= done) continue;
      // UAV phase of tick k: read the tiles of place tick k-1, decide, move,
      // deposit; acknowledged deposits are in the place agents' queues before
      // we report done.
      if (c.tick > 0) wait_for_tick(c.tick - 1, c);
      handle_commands();
      step(c.tick, false);
      if (!bus_->flush(std::chrono::seconds(10))) log_->warn("tick {}: not every sample was acknowledged in 10 s", c.tick);
      // Report what this phase wrote: the conductor announces it to the
      // place agents (deposits) and to the UAVs (broadcasts), which wait for it.
      core::PhaseDoneMsg report{core::process_key(core::kRoleUav, cfg_.id), c.tick, c.phase, broadcast_written_ ? 1U : 0U,
                              {}};
      for (const auto& [region, n] : written_) report.deposits.push_back({region, n});
      bus_->publish_phase_done(report);
      bus_->flush(std::chrono::seconds(10));
      done = c.tick;
      if (c.tick >= ticks) stop = true;
    }
    if (cmds.empty()) std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  return static_cast<int>(std::max<int64_t>(done, 0));
}

int UavApp::run() {
  const uint32_t ticks = scenario_.ticks;
  bus_->set_neighbourhood(core_.neighbourhood());
  bus_->subscribe_broadcasts();
  commands_ = std::make_unique<runtime::SwarmCommands>(*bus_, log_);
  if (cfg_.seq_base > 0) core_.set_first_seq(cfg_.seq_base);
  wait_for_place_agents();
  log_->info("uav {} ({}) starts at ({},{}) for {} ticks, {} clock, over {}", cfg_.id, core::policy_name(scenario_.policy),
             core_.cell().x, core_.cell().y, ticks, cfg_.common.clock, bus_->vendor());
  const int last = cfg_.common.lockstep() ? run_lockstep(ticks) : run_realtime(ticks);
  step(static_cast<uint32_t>(last), true);
  const bool acked = bus_->flush(std::chrono::seconds(5));
  log_->info("uav {} finished at tick {} at ({},{}): deposits sent {}, undeliverable {}, samples rejected {}{}", cfg_.id,
             last, core_.cell().x, core_.cell().y, deposits_sent_, deposits_undeliverable_, samples_rejected_,
             acked ? "" : " (not every sample was acknowledged)");
  return 0;
}

}  // namespace pheromesh::agent
