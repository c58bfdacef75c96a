#include "place_app.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <set>
#include <thread>

#include "pheromesh/runtime/await.hpp"
#include "pheromesh/runtime/lockstep_loop.hpp"

namespace pheromesh::placeagent {

using Clock = std::chrono::steady_clock;

namespace {
// Exit code when the lockstep conductor vanished (runtime::run_process uses 2-4).
constexpr int kConductorLost = 7;
// Exit code of a replica that missed lockstep ticks (docs/faults.md).
constexpr int kReplicaBehind = 8;
// Realtime: a home UAV not heard for this many place ticks gets no more
// views (it died or finished); in lockstep every view is sent.
constexpr uint32_t kViewsAfterSilence = 20;
// Realtime: neighbour states at most this many ticks older than the UAV's
// own go into its view (UavCore keeps the same window).
constexpr uint32_t kNeighbourAge = 4;
}  // namespace

PlaceApp::PlaceApp(PlaceConfig cfg, core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus)
    : cfg_(std::move(cfg)),
      scenario_(std::move(scenario)),
      geo_(scenario_.geometry()),
      bus_(std::move(bus)),
      resend_(*bus_, cfg_.common.lockstep()),
      log_(spdlog::default_logger()),
      audit_(log_),
      follower_(core::ClockPhase::Place,
                core::ConductorWatch::for_lease(std::chrono::milliseconds(cfg_.common.lease_ms), Clock::now())),
      core_(scenario_, cfg_.region),
      rate_(scenario_.tick_rate_hz),
      gaps_(std::chrono::nanoseconds(static_cast<int64_t>(1e9 / scenario_.tick_rate_hz))),
      traits_(core::policy_traits(scenario_)),
      views_(geo_, static_cast<int>(traits_.layers.size()), traits_.view_radius),
      rules_{geo_, core_.layer_count(), traits_.layer_ranges, scenario_.uavs},
      desk_(cfg_.region, geo_.region_count(), scenario_.uavs, cfg_.common.standby || scenario_.standby) {
  for (uint32_t u = 0; u < scenario_.uavs; ++u) {
    if (core::home_region(u, geo_.region_count()) == cfg_.region) home_uavs_.push_back(u);
  }
  for (core::RegionId r = 0; r < geo_.region_count(); ++r) {
    if (r != cfg_.region) other_regions_.push_back(r);
  }
  replicated_ = cfg_.common.standby || scenario_.standby;
  present_others_ = other_regions_;
}

uint32_t PlaceApp::tick_ceiling() const {
  return demand_ ? core::lockstep_tick_ceiling(current_tick_) : runtime::realtime_tick_ceiling(scenario_.tick_rate_hz);
}

void PlaceApp::note_absent() {
  if (follower_.absent().size() == absent_seen_) return;
  absent_seen_ = follower_.absent().size();
  for (const auto& [r, tick] : follower_.absent()) {
    if (r == cfg_.region || r >= geo_.region_count() || !absent_.insert(r).second) continue;
    log_->warn("tick {}: the place agent of region {} is gone (no standby); its field and ring stay as they were", tick,
               r);
  }
  present_others_.clear();
  for (core::RegionId r : other_regions_) {
    if (!absent_.contains(r)) present_others_.push_back(r);
  }
}

void PlaceApp::take_deposits() {
  taken_.clear();
  bus_->take_deposits(taken_);
  for (const auto& d : taken_) {
    switch (desk_.take(d, current_tick_)) {
      case core::DepositRoute::Apply:
        inbox_.push_back(d);
        break;
      case core::DepositRoute::Forward:
        forward(d);
        break;
      case core::DepositRoute::Copy:
        break;
    }
  }
}

void PlaceApp::forward(const core::DepositMsg& d) {
  // A home UAV's deposit for another region: to the owner's place agent.
  if (is_absent(d.region)) {
    ++deposits_lost_;  // the conductor counts it lost (deposits_lost)
  } else if (bus_->matched_deposit_readers(d.region) == 0) {
    core_.reject({d}, "owner place agent of region " + std::to_string(d.region) + " not reachable to forward to");
  } else if (bus_->publish_deposit(d, d.region)) {
    ++deposits_forwarded_;
  } else {
    core_.reject({d}, "forwarding to region " + std::to_string(d.region) + " failed");
  }
}

void PlaceApp::take_home_states(uint32_t tick) {
  state_inbox_.clear();
  bus_->take_uav_states(state_inbox_);
  const uint32_t ceiling = tick_ceiling();
  for (const auto& st : state_inbox_) {
    const bool known = !core::check_uav_id(st.uav, scenario_.uavs);
    if (known && core::home_region(st.uav, geo_.region_count()) != cfg_.region) continue;  // not ours (a stray writer)
    const core::UavStateMsg* before = views_.state(st.uav);
    const core::Cell start = core::uav_start(scenario_, traits_, st.uav);
    if (!audit_.admit(core::check_home_state(st, before, start, traits_.max_step, ceiling, rules_))) continue;
    if (before == nullptr || st.tick > before->tick) heard_at_[st.uav] = tick;
    views_.update_state(st);
  }
}

uint32_t PlaceApp::home_states_of(uint32_t tick) const {
  return static_cast<uint32_t>(std::count_if(home_uavs_.begin(), home_uavs_.end(), [&](uint32_t u) {
    const core::UavStateMsg* st = views_.state(u);
    return st != nullptr && st->tick >= tick;
  }));
}

void PlaceApp::take_inputs(uint32_t tick) {
  inbox_.clear();
  take_deposits();
  take_home_states(tick);
  if (!demand_) return;
  // Lockstep: exactly the deposits the UAVs reported for this region and the
  // states of the home UAVs that took part in the UAV phase, as the clock
  // announced. Waiting for these exact samples replaces the UAVs' wait for
  // acknowledgements. Forged deposits carrying this tick must not stand in
  // for real ones (the place would apply the tick before all of them arrived).
  const auto deposits = [&] {
    return static_cast<uint32_t>(std::count_if(
        inbox_.begin(), inbox_.end(), [&](const auto& d) { return d.tick == tick && !core_.refuses(d, tick); }));
  };
  const auto r = runtime::await_samples(
      *bus_, {bus::TopicKind::Deposit, bus::TopicKind::UavHome}, {}, nullptr,
      [&] {
        take_deposits();
        take_home_states(tick);
      },
      [&] { return deposits() >= demand_->deposits && home_states_of(tick) >= demand_->states; });
  if (r != runtime::Awaited::Done) {
    log_->error("tick {}: {} of {} announced deposits and {} of {} home UAV states arrived; applying those", tick,
                deposits(), demand_->deposits, home_states_of(tick), demand_->states);
  }
}

void PlaceApp::exchange_halos(uint32_t tick) {
  // Neighbour rings. Realtime: whatever arrived (a neighbour that sent
  // nothing new leaves its last ring in the halo, counted as missing).
  // Lockstep: exactly the rings of this tick; an absent neighbour's last ring
  // stays in the halo (frozen).
  std::set<core::RegionId> fresh;
  const auto& neighbours = core_.neighbours();
  const auto awaited = static_cast<std::size_t>(
      std::count_if(neighbours.begin(), neighbours.end(), [&](core::RegionId n) { return !is_absent(n); }));
  const auto take = [&] {
    halo_inbox_.clear();
    bus_->take_halos(halo_inbox_);
    const uint32_t ceiling = tick_ceiling();
    for (const auto& h : halo_inbox_) {
      if (demand_ && (h.tick != tick || is_absent(h.region))) continue;
      if (auto reason = core::check_tick_reachable(h.tick, ceiling, "halo")) {
        audit_.refuse(core::Refusal::TickFarAhead, *reason);
      } else if (!core_.accept_halo(h)) {
        log_->warn("dropped malformed or out-of-range halo from region {}", h.region);
      } else {
        fresh.insert(h.region);
      }
    }
  };
  const auto r = runtime::await_samples(*bus_, {bus::TopicKind::Halo}, {}, &resend_, take,
                                        [&] { return !demand_ || fresh.size() >= awaited; });
  if (r != runtime::Awaited::Done) {
    log_->error("tick {}: rings of {} of {} neighbours did not arrive", tick, awaited - std::min(awaited, fresh.size()),
                awaited);
  }
  halos_missing_ += awaited - std::min(fresh.size(), awaited);
}

void PlaceApp::serve_views(uint32_t tick) {
  // This region's field and its home UAVs' latest states, to every place agent and the ground.
  home_states_.clear();
  for (uint32_t u : home_uavs_) {
    if (const core::UavStateMsg* st = views_.state(u)) home_states_.push_back(*st);
  }
  for (const auto& t : tiles_out_) views_.update_tile(t);
  for (auto& f : core::make_field_chunks(cfg_.region, tick, tiles_out_, home_states_)) {
    f.replica = cfg_.replica;
    resend_.field(f);
  }
  // Every other region's field: exactly this tick's (lockstep), or the latest.
  const auto take = [&] {
    field_inbox_.clear();
    bus_->take_fields(field_inbox_);
    const uint32_t ceiling = tick_ceiling();
    for (const auto& f : field_inbox_) {
      if (f.region != cfg_.region && audit_.admit(core::check_field_chunk(f, ceiling, rules_))) views_.update_field(f);
    }
  };
  const auto r = runtime::await_samples(*bus_, {bus::TopicKind::Field}, {}, &resend_, take,
                                        [&] { return !demand_ || views_.holds_fields(tick, present_others_); });
  if (r != runtime::Awaited::Done) {
    log_->error("tick {}: the fields of some regions did not arrive ({}); views use the latest", tick,
                views_.missing_fields(tick, present_others_));
  }
  for (uint32_t u : home_uavs_) {
    const core::UavStateMsg* st = views_.state(u);
    if (st == nullptr || st->finished) continue;
    if (!demand_ && tick - heard_at_[u] > kViewsAfterSilence) continue;
    if (views_.compose(u, tick, demand_ ? 0 : kNeighbourAge, view_)) {
      view_.deposit_ack = desk_.ack(u);
      resend_.view(view_);
    }
  }
}

void PlaceApp::step(uint32_t tick, std::optional<TickDemand> demand) {
  current_tick_ = tick;
  demand_ = demand;
  resend_.begin_tick();
  take_inputs(tick);
  events_.clear();
  rejections_.clear();
  const core::HaloRing ring = core_.begin_tick(inbox_, tick, events_, &rejections_);
  for (const auto& r : rejections_) {
    if (core_.ledger().rejected() <= 20) log_->warn("rejected deposit from {}", r);
  }
  for (const auto& e : events_) {
    bus_->publish_target_event(e);
    log_->info("target at ({},{}) {} at tick {}", e.cell.x, e.cell.y,
               core::to_string(static_cast<core::TargetEventKind>(e.kind)), tick);
  }
  resend_.halo({cfg_.region, tick, ring.target, ring.obstacle});
  exchange_halos(tick);
  core_.finish_tick();
  tiles_out_.clear();
  core_.tiles(tick, false, tiles_out_);
  serve_views(tick);
}

void PlaceApp::publish_health(uint32_t tick, HealthKind kind) {
  const auto& l = core_.ledger();
  core::HealthMsg h{cfg_.region,  tick,           static_cast<float>(rate_), l.received,         l.applied,
                    l.rejected(), halos_missing_, kind == HealthKind::Final, gaps_.max_gap_ms(), gaps_.gaps_over_2()};
  h.replica = cfg_.replica;
  h.deposits_duplicate = desk_.copies();
  core::RefusalCounts all = audit_.refused();
  for (std::size_t i = 0; i < core::kRefusalCount; ++i) all.add(static_cast<core::Refusal>(i), l.refused.n[i]);
  h.refused = all.n;
  bus_->publish_health(h);
}

void PlaceApp::finish(uint32_t tick) {
  publish_health(tick, HealthKind::Final);
  // Only the final accounting, which the ground station alone reads (the
  // lockstep conductor holds the last fields before its Stop). Not the views,
  // fields or halos: a UAV or place agent killed during the run keeps its
  // readers matched until its participant lease ends (1 h) and would hold
  // the flush for its whole timeout (docs/dds.md, "No waiting on the dead").
  bus_->flush({bus::TopicKind::Health}, std::chrono::seconds(3));
  log_summary(tick);
}

void PlaceApp::log_summary(uint32_t tick) {
  const auto& l = core_.ledger();
  log_->info(
      "region {}{} finished at tick {}: deposits received {}, applied {}, rejected {}, duplicates dropped {}; "
      "forwarded {} of its {} home UAVs' to other regions; samples dropped {}; lockstep re-sends {}{}",
      cfg_.region, cfg_.replica > 0 ? " (standby " + std::to_string(cfg_.replica) + ")" : "", tick, l.received,
      l.applied, l.rejected(), desk_.copies(), deposits_forwarded_, home_uavs_.size(), audit_.dropped(),
      resend_.resends(),
      deposits_lost_ > 0 ? fmt::format("; {} deposits for absent regions lost", deposits_lost_) : std::string());
  for (const auto& [reason, n] : l.rejected_by_reason) log_->info("  rejected {}: {}", n, reason);
  for (std::size_t i = 0; i < core::kRefusalCount; ++i) {
    const uint64_t n = uint64_t{audit_.refused().n[i]} + l.refused.n[i];
    if (n > 0) log_->info("  refused as implausible ({}): {}", core::refusal_name(static_cast<core::Refusal>(i)), n);
  }
  if (!cfg_.common.lockstep()) runtime::log_clock_kept(gaps_, *log_, fmt::format("region {}", cfg_.region));
}

int PlaceApp::run_realtime() {
  runtime::TickClock clock(rate_);
  auto last_health = Clock::now();
  uint32_t tick = 0;
  while (!runtime::shutdown_requested() && !commands_->ended() && (cfg_.max_ticks == 0 || tick < cfg_.max_ticks)) {
    runtime::note_tick_start(gaps_, *log_, tick);
    commands_->take();
    // Paused from the console: no evaporation, no diffusion, deposits wait
    // in the reader; health still goes out.
    if (!commands_->paused()) step(tick++, std::nullopt);
    if (Clock::now() - last_health >= std::chrono::milliseconds(500)) {
      rate_ = clock.measured_rate() > 0 ? clock.measured_rate() : rate_;
      publish_health(tick, HealthKind::Running);
      last_health = Clock::now();
    }
    if (!clock.wait_next()) break;
  }
  // Drain: deposits that arrived after the last tick are still applied (or
  // rejected) and counted before the final health.
  step(tick, std::nullopt);
  finish(tick);
  return 0;
}

void PlaceApp::report_ready_once() {
  // Before tick 0: Ready once every other region's place agent reads the
  // deposits this one forwards (the conductor starts tick 0 when every
  // process is ready).
  if (ready_ || follower_.last_done()) return;
  const bool matched = std::all_of(other_regions_.begin(), other_regions_.end(),
                                   [&](core::RegionId r) { return bus_->matched_deposit_readers(r) >= 1; });
  if (!matched) return;
  resend_.phase_done(
      {core::process_key(core::kRolePlace, cfg_.region), 0, static_cast<uint8_t>(core::ClockPhase::Ready), 0, {}});
  ready_ = true;
  log_->debug("matched every other region's place agent: ready");
}

runtime::PhaseOutcome PlaceApp::run_place_phase(const core::ClockMsg& c) {
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
    log_->warn("tick {} starts before every other region's place agent was matched: forwarded deposits may be rejected",
               c.tick);
    ready_ = true;
  }
  // Every tile, every tick: a UAV waits for tiles of exactly this tick.
  TickDemand demand;
  for (const auto& rc : c.deposits) demand.deposits += rc.region == cfg_.region ? rc.count : 0;
  for (const auto& rc : c.states) demand.states += rc.region == cfg_.region ? rc.count : 0;
  step(c.tick, demand);
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
                             [&] { report_ready_once(); },
                             [&](const core::ClockMsg& c) { return run_place_phase(c); }};
  switch (loop.run()) {
    case runtime::LockstepEnd::Left:
      return kReplicaBehind;
    case runtime::LockstepEnd::ConductorLost:
      log_summary(static_cast<uint32_t>(follower_.last_done().value_or(0)));
      return kConductorLost;
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
    commands_->take();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  inbox_.clear();
  take_deposits();
  if (!inbox_.empty()) log_->warn("{} deposits arrived after the last tick; rejected", inbox_.size());
  core_.reject(inbox_, "arrived after the last lockstep tick");
  finish(static_cast<uint32_t>(follower_.last_done().value_or(0)));
  return 0;
}

int PlaceApp::run() {
  // Every endpoint this place agent runs with, created once: deposits for
  // this region, its home UAVs' states, every region's field, halos, and the
  // writers of forwarded deposits, of fields and of its home UAVs' views.
  bus_->subscribe_deposits(cfg_.region);
  bus_->subscribe_home_states(cfg_.region);
  bus_->subscribe_fields();
  bus_->subscribe_halos(core_.neighbours());
  for (core::RegionId r : other_regions_) (void)bus_->matched_deposit_readers(r);  // creates the forwarding writer
  bus_->offer_views(home_uavs_);
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
