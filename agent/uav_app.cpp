#include "uav_app.hpp"

#include <spdlog/spdlog.h>

#include "pheromesh/runtime/await.hpp"
#include "pheromesh/runtime/lockstep_loop.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <exception>
#include <mutex>
#include <span>
#include <thread>

namespace pheromesh::agent {

using Clock = std::chrono::steady_clock;

namespace {
// The writers a lockstep UAV hears the clock from (the lockstep tree): the
// place agents of its home and of its backup region, each with its standby.
uint32_t clock_relays(const UavConfig& cfg, const core::ScenarioConfig& scenario) {
  const uint32_t regions = scenario.geometry().region_count();
  const uint32_t gateways = core::backup_region(cfg.id, regions) == core::home_region(cfg.id, regions) ? 1 : 2;
  return gateways * (cfg.common.standby || scenario.standby ? 2 : 1);
}
}  // namespace

UavApp::UavApp(UavConfig cfg, core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus)
    : cfg_(std::move(cfg)),
      scenario_(std::move(scenario)),
      geo_(scenario_.geometry()),
      world_(geo_, scenario_.obstacles, scenario_.targets),
      bus_(std::move(bus)),
      resend_(*bus_, cfg_.common.lockstep()),
      follower_(core::ClockPhase::Uav,
                core::ConductorWatch::for_lease(std::chrono::milliseconds(cfg_.common.lease_ms), Clock::now()),
                clock_relays(cfg_, scenario_)),
      log_(spdlog::default_logger()),
      audit_(log_),
      core_(scenario_, world_, cfg_.id, cfg_.common.lockstep()),
      gaps_(std::chrono::nanoseconds(static_cast<int64_t>(1e9 / scenario_.tick_rate_hz))),
      layers_(static_cast<int>(core::policy_traits(scenario_).layers.size())),
      home_(core::home_region(cfg_.id, geo_.region_count())),
      gateway_(home_),
      home_watch_(core::HomeWatch::silence_for(cfg_.common.lease_ms, cfg_.common.standby || scenario_.standby),
                  geo_.region_count() > 1) {
  layer_ranges_ = core::policy_traits(scenario_).layer_ranges;
}

uint32_t UavApp::tick_ceiling() const {
  return cfg_.common.lockstep() ? core::lockstep_tick_ceiling(follower_.newest_tick())
                                : runtime::realtime_tick_ceiling(scenario_.tick_rate_hz);
}

void UavApp::handle_commands() {
  const auto commands = commands_->take();
  samples_received_ += commands.size();
  for (const auto& c : commands) {
    if (c.kind == static_cast<uint8_t>(core::CommandKind::Obstacle)) {
      const auto cells = world_.add_obstacle({c.x, c.y, c.w, c.h});
      log_->info("pop-up obstacle: {} new obstacle cells", cells);
    } else if (c.kind == static_cast<uint8_t>(core::CommandKind::Target)) {
      const auto index = world_.add_target({c.x, c.y});
      log_->info("new target {} at ({},{})", index, c.x, c.y);
    }
  }
}

void UavApp::wait_for_home() {
  // Wait (bounded) until the home place agent is matched, so the first
  // deposits (in the first states) are not lost to discovery (matching is
  // not data: no wait set).
  const auto deadline = Clock::now() + std::chrono::milliseconds(static_cast<int64_t>(cfg_.wait_for_places_s * 1000));
  // With standbys, every replica of the home reads this UAV's states.
  const uint32_t replicas = (cfg_.common.standby || scenario_.standby) ? 2 : 1;
  while (bus_->matched_state_readers() < replicas) {
    if (Clock::now() > deadline || runtime::shutdown_requested()) {
      log_->warn("starting before home place agent {} was discovered", home_);
      return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

void UavApp::wait_for_start() {
  // Realtime swarms fly together: this UAV announces itself (its state
  // before the first tick, which also lets its home compose a first view)
  // and waits for the ground station's start, which comes once every UAV
  // and place agent has been heard. Without it the first UAVs of a big swarm
  // fly while hundreds of others are still being discovered, on a host busy
  // with that discovery, and deposit into place agents not yet matched.
  if (!commands_->can_start()) return;  // no control key: nobody can sign a start
  core::UavStateMsg ready = core_.last_state();
  ready.view = core_.cell();
  // Awake once a period (core::start_wait_period), or at once for the start.
  const auto period = core::start_wait_period(std::chrono::milliseconds(cfg_.common.lease_ms));
  auto next_state = Clock::now();
  const auto take = [&] {
    handle_commands();
    receive();  // drains the view and keeps the state writer's liveliness asserted
    const auto now = Clock::now();
    if (now + period / 8 < next_state) return;  // woken early by a command (a timed wake-up may come a hair early)
    bus_->publish_uav_state(ready);             // again each period: the ground station may have joined late
    next_state = now + period;
  };
  const auto bound = std::chrono::milliseconds(static_cast<int64_t>(cfg_.wait_for_start_s * 1000));
  const auto r = runtime::await_samples(*bus_, {bus::TopicKind::Command}, {bound, period}, nullptr, take,
                                        [&] { return commands_->started(); });
  if (r == runtime::Awaited::TimedOut) {
    log_->warn("no start from the ground station within {} s; flying without it", cfg_.wait_for_start_s);
  }
}

std::optional<core::RegionId> UavApp::gateway_at(uint32_t tick) const {
  return core::gateway_region(cfg_.id, geo_.region_count(), [&](core::RegionId r) {
    const auto since = follower_.absent_since(r);
    return since && tick >= *since;
  });
}

void UavApp::switch_gateway(core::RegionId gateway, uint32_t tick) {
  log_->warn(
      "tick {}: home place agent {} is gone (no standby): state and deposits go to place agent {}, its backup "
      "gateway, from now on",
      tick, home_, gateway);
  gateway_ = gateway;
  receipts_.abandon();
  if (bus_->move_uplink(gateway)) {
    log_->info("tick {}: naming place agent {} in discovery now (a cell's backup gateway is not discovered ahead)",
               tick, gateway);
  }
  if (!cfg_.common.lockstep()) return;
  // Lockstep: the backup waits for exactly this UAV's state and deposits;
  // write them once its readers match (the re-sender covers the rest).
  const auto deadline = Clock::now() + std::chrono::milliseconds(static_cast<int64_t>(cfg_.wait_for_places_s * 1000));
  while (bus_->matched_state_readers() < 1 && Clock::now() < deadline && !runtime::shutdown_requested()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

int UavApp::run_realtime(uint32_t ticks) {
  step(0, StepKind::Fly);
  // Each tick runs as the view arrives, in the receive thread, or, without
  // a view, on the main thread's timer (core::ViewPacing); under `mutex`
  // either way.
  const auto period = std::chrono::nanoseconds(static_cast<int64_t>(1e9 / scenario_.tick_rate_hz));
  core::ViewPacing pacing(period, Clock::now());
  runtime::WakeTimer timer;
  std::mutex mutex;
  uint32_t tick = 0;
  home_watch_.start(Clock::now());
  // A view arrived: the tick it runs, if any (`mutex` held).
  bool stopping = false;  // the loop has ended: no tick more
  const auto view_came = [&] {
    const auto now = Clock::now();
    if (stopping || tick >= ticks || !pacing.view_runs_tick(now)) return;
    handle_commands();
    // Paused, or a gateway to change (which may make endpoints): the timer's.
    if (commands_->paused() || gateway_ != home_) return;
    run_paced_tick(tick, pacing, now, /*by_view=*/true);
    timer.set(tick >= ticks ? now : pacing.timer_at());  // the last: the main thread ends the loop
  };
  // The receive thread never waits for the main thread: the main thread may
  // hold `mutex` while it makes endpoints (a move to the backup gateway),
  // and a Fast DDS 2.9 receive thread held in a listener then deadlocks
  // with it (measured: a partitioned UAV hung, deaf to SIGTERM). It leaves
  // a note, which the main thread reads before it lets go of the mutex.
  // What a tick throws there (a plugin policy's step) is thrown again by the
  // main thread, never through the vendor's C frames.
  std::atomic<bool> view_waiting{false};
  std::exception_ptr failed;
  const std::array<bus::TopicKind, 1> views{bus::TopicKind::View};
  const bool in_receive_thread = bus_->on_data(views, [&] {
    std::unique_lock<std::mutex> lock(mutex, std::try_to_lock);
    if (!lock.owns_lock()) {
      view_waiting = true;
      return;
    }
    if (failed) return;
    try {
      view_came();
    } catch (...) {
      failed = std::current_exception();
      timer.set(Clock::now());
    }
  });
  // No callback outlives what it uses, however this function ends.
  struct Unhook {
    bus::Bus& bus;
    std::span<const bus::TopicKind> kinds;
    bool hooked;
    ~Unhook() {
      if (hooked) bus.on_data(kinds, {});
    }
  } unhook{*bus_, views, in_receive_thread};
  timer.set(pacing.timer_at());
  while (timer.wait()) {
    const std::lock_guard<std::mutex> lock(mutex);
    if (failed) std::rethrow_exception(failed);
    if (view_waiting.exchange(false)) view_came();
    if (tick >= ticks) break;
    const auto now = Clock::now();
    if (!pacing.timer_runs_tick(now)) {  // a view ran the tick meanwhile
      timer.set(pacing.timer_at());
      continue;
    }
    timer_came(tick, pacing, now);
    timer.set(pacing.timer_at());
    if (view_waiting.exchange(false)) view_came();
  }
  const std::lock_guard<std::mutex> lock(mutex);
  stopping = true;
  if (failed) std::rethrow_exception(failed);
  log_->info("{} ticks ran as their view arrived, {} on the timer", pacing.ticks_by_view(), pacing.ticks_by_timer());
  return static_cast<int>(tick);
}

void UavApp::run_paced_tick(uint32_t& tick, core::ViewPacing& pacing, Clock::time_point now, bool by_view) {
  pacing.ran(now, by_view);
  ticks_late_ = pacing.late_ticks();
  runtime::note_tick_start(gaps_, *log_, tick + 1);
  ++tick;
  receive();
  // The home's silence is judged after the views that were waiting were
  // taken (core::HomeWatch): the backup serves this UAV from this tick on.
  if (!by_view && home_watch_.move_to_backup(Clock::now())) {
    switch_gateway(core::backup_region(cfg_.id, geo_.region_count()), tick);
  }
  step(tick, StepKind::Fly);
}

void UavApp::timer_came(uint32_t& tick, core::ViewPacing& pacing, Clock::time_point now) {
  handle_commands();
  if (commands_->paused()) {
    receive();                        // keeps the inboxes drained and the liveliness asserted
    home_watch_.start(Clock::now());  // a paused swarm sends no views
    pacing.restart(now);
    gaps_.restart();
    return;
  }
  run_paced_tick(tick, pacing, now, /*by_view=*/false);
}

void UavApp::report_ready_once() {
  // Before tick 0: Ready once this UAV's home place agent reads its states
  // (with its deposits) and reports (it relays the state to the ground
  // station); the conductor starts tick 0 when every process is ready.
  if (ready_ || follower_.last_done() || bus_->matched_state_readers() < 1 || bus_->matched_report_readers() < 1)
    return;
  resend_.phase_done(
      {core::process_key(core::kRoleUav, cfg_.id), 0, static_cast<uint8_t>(core::ClockPhase::Ready), 0, {}});
  ready_ = true;
  log_->debug("matched home place agent {}: ready", home_);
}

void UavApp::run_uav_phase(const core::ClockMsg& c, uint32_t ticks) {
  if (!ready_) {
    log_->warn("tick {} starts before home place agent {} was matched: deposits may be undeliverable", c.tick, home_);
    ready_ = true;
  }
  if (const auto gateway = gateway_at(c.tick); gateway != gateway_) {
    if (gateway) {
      switch_gateway(*gateway, c.tick);
    } else {
      gateway_ = std::nullopt;
      log_->warn(
          "tick {}: home place agent {} and backup {} are gone (no standby): from now on this UAV acts on empty "
          "views and its deposits are lost",
          c.tick, home_, core::backup_region(cfg_.id, geo_.region_count()));
    }
  }
  // UAV phase of tick k: read the tiles of place tick k-1, decide, move,
  // deposit. No wait for acknowledgements: the place phase announces how
  // many deposits and states of this tick each place agent must hold, and it
  // waits for those exact samples (an acknowledgement waits for the writer's
  // next heartbeat, ~100 ms on Cyclone 0.10; docs/dds.md).
  if (c.tick > 0) wait_for_tick(c.tick - 1, c);
  handle_commands();
  resend_.begin_tick();
  step(c.tick, StepKind::Fly);
  // What this phase wrote goes to the conductor, which announces it to the
  // place agents (deposits) and to the UAVs (broadcasts): its gateway
  // reports it from the state just written (core::UplinkReports), one
  // sample less per UAV tick. With no gateway (home and backup gone, no
  // standby) this UAV reports itself, its deposits lost on the way.
  if (!gateway_) {
    core::PhaseDoneMsg report{
        core::process_key(core::kRoleUav, cfg_.id), c.tick, c.phase, broadcast_written_ ? 1U : 0U, {}};
    for (const auto& [region, n] : written_) report.deposits.push_back({region, n});
    resend_.phase_done(report);
  }
  // After the last UAV phase this UAV waits for the conductor's stop, which
  // comes after the last place phase: the launcher stops the place agents
  // once every UAV has ended, and they must have finished it.
  if (c.tick >= ticks) log_->debug("tick {}: the last UAV phase; waiting for the conductor's stop", c.tick);
}

int UavApp::run_lockstep(uint32_t ticks) {
  runtime::LockstepLoop loop{*bus_,
                             follower_,
                             resend_,
                             audit_,
                             *log_,
                             cfg_.common.lease_ms,
                             [&] { report_ready_once(); },
                             [&](const core::ClockMsg& c) {
                               run_uav_phase(c, ticks);
                               return runtime::PhaseOutcome::Continue;
                             }};
  // A phase whose view (with its clock) and broadcasts are here runs in the
  // thread that received the last of them: one wake-up a tick, not two.
  loop.ready = [&](const core::ClockMsg& c) { return ready_for(c); };
  loop.inputs = {bus::TopicKind::Clock, bus::TopicKind::RelayedClock, bus::TopicKind::View, bus::TopicKind::Broadcast};
  conductor_lost_ = loop.run() == runtime::LockstepEnd::ConductorLost;
  return static_cast<int>(follower_.last_done().value_or(0));
}

int UavApp::run() {
  const uint32_t ticks = scenario_.ticks;
  // Every endpoint this UAV flies with, created once: state (with its
  // deposits), detections, broadcasts and reports up to its home place agent, its view
  // from it; the swarm's broadcasts, the ground station's commands (and the
  // lockstep clock) as its home and its backup relay them. It talks to no
  // one else (docs/architecture.md, "Relays").
  const std::array<core::RegionId, 2> gateways{home_, core::backup_region(cfg_.id, geo_.region_count())};
  const auto joining = Clock::now();
  bus_->join_uav(cfg_.id, home_, core::policy_traits(scenario_).broadcasts);
  bus_->join_gateways(gateways);
  bus_->subscribe_broadcasts();
  commands_ = std::make_unique<runtime::SwarmCommands>(*bus_, log_);
  if (cfg_.common.lockstep()) bus_->join_clock_tree(gateways);
  if (cfg_.seq_base > 0) core_.set_first_seq(cfg_.seq_base);
  if (!cfg_.common.lockstep()) wait_for_home();  // lockstep: the conductor waits for every process's Ready
  // How long the endpoints and, in realtime, the match of the home took: a
  // big swarm's discovery shows here, UAV by UAV.
  log_->info("uav {} ({}) starts at ({},{}) for {} ticks, {} clock, home place agent {}, over {} ({:.1f} s after {})",
             cfg_.id, scenario_.policy, core_.cell().x, core_.cell().y, ticks, cfg_.common.clock, home_, bus_->vendor(),
             std::chrono::duration<double>(Clock::now() - joining).count(),
             cfg_.common.lockstep() ? "joining" : "joining, its home matched");
  if (!cfg_.common.lockstep()) wait_for_start();
  const int last = cfg_.common.lockstep() ? run_lockstep(ticks) : run_realtime(ticks);
  if (conductor_lost_) return runtime::kExitConductorLost;  // nobody to report a last state to
  // The home confirms the last deposits in its next view: wait for it (a
  // dead home never does; those deposits are counted unconfirmed).
  wait_for_receipts(std::chrono::milliseconds(std::max<uint32_t>(2 * cfg_.common.lease_ms, 1000)));
  step(static_cast<uint32_t>(last), StepKind::Finish);
  // Only what the ground station and the home need at the end (the deposits
  // were confirmed above): a flush of every writer would also wait for the
  // readers of processes killed during the run, which stay matched until
  // their participant lease ends (1 h; docs/dds.md, "No waiting on the dead").
  const bool acked = bus_->flush({bus::TopicKind::UavState, bus::TopicKind::Detection}, std::chrono::seconds(5));
  log_->info(
      "uav {} finished at tick {} at ({},{}): deposits sent {}, unconfirmed {}, "
      "undeliverable {}, samples rejected {}{}",
      cfg_.id, last, core_.cell().x, core_.cell().y, deposits_sent_, receipts_.unconfirmed(), deposits_undeliverable_,
      audit_.dropped(), acked ? "" : " (not every sample was acknowledged)");
  if (receipts_.unconfirmed() > 0) {
    log_->warn("uav {}: {} deposits were never confirmed by the place agent they went to (counted lost)", cfg_.id,
               receipts_.unconfirmed());
  }
  if (!cfg_.common.lockstep()) {
    runtime::log_clock_kept(gaps_, *log_, fmt::format("uav {}", cfg_.id), fmt::format(", {} late ticks", ticks_late_));
  }
  return 0;
}

}  // namespace pheromesh::agent
