// How a place agent runs: realtime on its own clock, lockstep on the
// conductor's (core::LockstepFollower, runtime::LockstepLoop), and the
// endpoints it runs with.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "pheromesh/runtime/lockstep_loop.hpp"
#include "place_app.hpp"

namespace pheromesh::placeagent {

using Clock = std::chrono::steady_clock;

namespace {
// Exit code of a replica that missed lockstep ticks (docs/faults.md).
constexpr int kReplicaBehind = 8;
}  // namespace

int PlaceApp::run_realtime() {
  runtime::TickClock clock(rate_);
  auto last_health = Clock::now();
  uint32_t tick = 0;
  while (!runtime::shutdown_requested() && !commands_->ended()) {
    runtime::note_tick_start(gaps_, *log_, tick);
    relay_uplinks();  // the commands among them
    // Paused from the console: no evaporation, no diffusion, deposits wait
    // in the reader; health still goes out.
    if (!commands_->paused()) {
      step(tick++);
    } else {
      take_home_states(tick);  // the ground station still hears the UAVs
    }
    // The ground station starts the UAVs once every region's place agent is
    // linked: its health says so at once, not at the next half second.
    const bool just_linked = !linked_ && note_linked();
    if (just_linked || Clock::now() - last_health >= std::chrono::milliseconds(500)) {
      rate_ = clock.measured_rate() > 0 ? clock.measured_rate() : rate_;
      publish_health(tick, HealthKind::Running);
      last_health = Clock::now();
    }
    if (!clock.wait_next()) break;
  }
  // Drain: deposits that arrived after the last tick are still applied (or
  // rejected) and counted before the final health; the whole field goes to
  // the ground station.
  last_tick_ = true;
  step(tick);
  relay_uplinks();
  finish(tick);
  return 0;
}

bool PlaceApp::note_linked() {
  // Every other region's place agent reads the deposits it forwards and the
  // tiles it sends for their UAVs' views, and each neighbour its ring: a
  // sample written to a reader not yet matched waits for the match and the
  // writer's next heartbeat (1 s in a large swarm), and so would the first
  // tick.
  if (!linked_) {
    const auto& neighbours = core_.neighbours();
    linked_ = std::all_of(other_regions_.begin(), other_regions_.end(),
                          [&](core::RegionId r) {
                            return bus_->matched_deposit_readers(r) >= 1 && bus_->matched_tile_readers(r) >= 1;
                          }) &&
              std::all_of(neighbours.begin(), neighbours.end(),
                          [&](core::RegionId n) { return bus_->matched_halo_readers(cfg_.region, n) >= 1; });
  }
  return linked_;
}

void PlaceApp::report_ready_once() {
  // Before tick 0: Ready once every other region's place agent reads the
  // deposits this one forwards (the conductor starts tick 0 when every
  // process is ready).
  if (ready_ || follower_.last_done()) return;
  if (!note_linked()) return;
  // A health first: it makes this process a place agent at the ground
  // station (core/place_vouch.hpp), which takes the states it relays in UAV
  // phase 0 only from one.
  publish_health(0, HealthKind::Running);
  resend_.phase_done(
      {core::process_key(core::kRolePlace, cfg_.region), 0, static_cast<uint8_t>(core::ClockPhase::Ready), 0, {}});
  ready_ = true;
  log_->debug("matched every other region's place agent: ready");
}

runtime::PhaseOutcome PlaceApp::run_place_phase(const core::ClockMsg& c) {
  if (stage_ == Stage::Done || !phase_clock_ || phase_clock_->tick != c.tick) {
    if (replicated_ && follower_.skips(c.tick)) {
      // The swarm went on without this replica (it was stopped or cut off
      // longer than a lease and another replica served the region): its field
      // missed ticks and must not be served again.
      log_->error(
          "region {} replica {}: the lockstep clock is at tick {} but this replica finished tick {} last; it missed "
          "ticks while it was stopped or cut off and leaves (another replica serves the region)",
          cfg_.region, cfg_.replica, c.tick, *follower_.last_done());
      return runtime::PhaseOutcome::Leave;
    }
    note_absent();
    if (!ready_) {
      log_->warn(
          "tick {} starts before every other region's place agent was matched: forwarded deposits may be rejected",
          c.tick);
      ready_ = true;
    }
    // Every tile, every tick: a UAV waits for tiles of exactly this tick.
    phase_clock_ = c;
    TickDemand demand;
    for (const auto& rc : c.deposits) demand.deposits += rc.region == cfg_.region ? rc.count : 0;
    for (const auto& rc : c.states) demand.states += rc.region == cfg_.region ? rc.count : 0;
    demand.served = &phase_clock_->served;
    log_->debug("tick {}: the clock asks for {} deposits and {} home UAV states", c.tick, demand.deposits,
                demand.states);
    begin_step(c.tick, demand);
  }
  if (!advance_step()) return runtime::PhaseOutcome::Pending;
  publish_health(c.tick, HealthKind::Running);
  // No flush here: every reader of what this phase wrote waits for exactly
  // this tick's samples (fields, halos, views, forwarded deposits by count),
  // and the re-sender covers a sample that does not come out. A flush would
  // wait for the acknowledgement of every matched reader, also of a killed
  // process, whose readers stay matched until its participant lease ends.
  const uint32_t id = replicated_ ? core::place_id(cfg_.region, cfg_.replica) : cfg_.region;
  resend_.phase_done({core::process_key(core::kRolePlace, id), c.tick, c.phase, 0, {}});
  return runtime::PhaseOutcome::Continue;
}

int PlaceApp::run_lockstep() {
  bus_->subscribe_clock();
  runtime::LockstepLoop loop{*bus_,
                             follower_,
                             resend_,
                             audit_,
                             *log_,
                             cfg_.common.lease_ms,
                             [&] {
                               report_ready_once();
                               relay_idle();
                             },
                             [&](const core::ClockMsg& c) { return run_place_phase(c); }};
  loop.relay = [&](const core::ClockMsg& c) { relay_clock(c); };
  // Its place phase answers samples (docs/architecture.md, "Answering in the
  // receive thread"): each of these runs a round where it arrived, which
  // relays what came (before_round) and advances the phase under way.
  loop.inputs = {bus::TopicKind::Clock,     bus::TopicKind::PhaseDone, bus::TopicKind::UavHome,
                 bus::TopicKind::Detection, bus::TopicKind::Broadcast, bus::TopicKind::Command,
                 bus::TopicKind::Deposit,   bus::TopicKind::Halo,      bus::TopicKind::PlaceField};
  const auto end = loop.run();
  log_->debug("lockstep tree: relayed {} clocks to the UAVs served and {} of their reports", clocks_relayed_,
              reports_relayed_);
  switch (end) {
    case runtime::LockstepEnd::Left:
      return kReplicaBehind;
    case runtime::LockstepEnd::ConductorLost:
      log_summary(static_cast<uint32_t>(follower_.last_done().value_or(0)));
      return runtime::kExitConductorLost;
    case runtime::LockstepEnd::Stopped:
    case runtime::LockstepEnd::ShutDown:
      break;
  }
  // Wait for SIGTERM from the launcher; deposits arriving now (none in a
  // clean run) are counted, not applied to the field, so the final field
  // stays that of the last conducted tick. Polling the bus keeps this
  // process's writers alive (manual-by-topic liveliness), so the ground
  // station does not report it lost meanwhile.
  while (!runtime::shutdown_requested() && !commands_->ended()) {
    relay_idle();  // the UAVs' last states and departures, the commands among them
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  take_home_states(current_tick_);  // and what relay_idle's batch still holds
  inbox_.clear();
  take_deposits();
  if (!inbox_.empty()) log_->warn("{} deposits arrived after the last tick; rejected", inbox_.size());
  core_.reject(inbox_, "arrived after the last lockstep tick");
  finish(static_cast<uint32_t>(follower_.last_done().value_or(0)));
  return 0;
}

int PlaceApp::run() {
  // Every endpoint this place agent runs with, created once: deposits for
  // this region, its home UAVs' states, the other place agents' served UAVs
  // and the tiles they send for its views, halos, and the writers of
  // forwarded deposits, of served UAVs and tiles, and of its home UAVs' views.
  // A place agent started again begins empty, as a rebooted tag would: the
  // deposits its dead life took are that life's (the ground station keeps its
  // counts, core::RunRecorder::on_health), and replaying them from the UAVs'
  // writer histories would count them twice.
  bus_->subscribe_deposits(cfg_.region, /*history=*/cfg_.life <= 1);
  bus_->subscribe_home_states(cfg_.region, /*history=*/cfg_.life <= 1);  // the states carry deposits too
  if (cfg_.common.lockstep()) bus_->subscribe_uav_reports(cfg_.region);  // the lockstep tree
  bus_->subscribe_uplinks(cfg_.region);                                  // relays between its UAVs and the swarm
  // Lockstep: the place clock lists every region's served UAVs; no `p`.
  bus_->subscribe_place_exchange(cfg_.region, /*served=*/!cfg_.common.lockstep());
  bus_->subscribe_halos(core_.neighbours(), cfg_.region);
  bus_->offer_halos(core_.neighbours(), cfg_.region);
  bus_->offer_deposits(other_regions_);
  bus_->offer_place_exchange(other_regions_, /*served=*/!cfg_.common.lockstep());
  bus_->offer_views(home_uavs_);
  if (cfg_.common.lockstep()) {
    // And to the UAVs it backs up, which it adopts once their home is
    // listed absent (adopt): in the receive thread, where no endpoint may
    // be created. A lockstep UAV discovers its backup from the start.
    bus_->offer_views(backed_up_);
  }
  bus_->offer_place_reports();
  commands_ = std::make_unique<runtime::SwarmCommands>(*bus_, log_);
  // The run, for monitors that attach with only the domain id.
  if (auto m = runtime::scenario_message(cfg_.common, scenario_, core::place_id(cfg_.region, cfg_.replica)); !m) {
    log_->warn("{}", m.error().message);
  } else if (!bus_->publish_scenario(m.value())) {
    log_->warn("cannot publish the scenario for monitors");
  }
  const core::Rect r = geo_.region_rect(cfg_.region);
  log_->info("place agent for region {} [{}..{})x[{}..{}) with {} tiles, {} neighbours, {} clock{} over {}{}",
             cfg_.region, r.x0, r.x0 + r.w, r.y0, r.y0 + r.h, core_.owned_tiles().size(), core_.neighbours().size(),
             cfg_.common.clock, cfg_.common.lockstep() ? "" : fmt::format(" at {:.1f} Hz", rate_), bus_->vendor(),
             !replicated_        ? std::string()
             : cfg_.replica == 0 ? std::string(", primary of a replicated region")
                                 : fmt::format(", hot standby {}", cfg_.replica));
  return cfg_.common.lockstep() ? run_lockstep() : run_realtime();
}

}  // namespace pheromesh::placeagent
