#include "place_app.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "pheromesh/runtime/lockstep_loop.hpp"

namespace pheromesh::placeagent {

using Clock = std::chrono::steady_clock;

namespace {
// Exit code of a replica that missed lockstep ticks (docs/faults.md).
constexpr int kReplicaBehind = 8;
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
      desk_(cfg_.region, geo_.region_count(), scenario_.uavs,
            cfg_.common.standby || scenario_.standby || cfg_.common.lockstep()),
      state_writers_(std::chrono::milliseconds(cfg_.common.lease_ms) * (cfg_.common.lockstep() ? 6 : 1)),
      // A place agent writes its served UAVs every tick: silent for a lease, it is dead.
      forwarders_(std::max<core::PlaceVouch::Clock::duration>(std::chrono::seconds(1),
                                                              std::chrono::milliseconds(cfg_.common.lease_ms))) {
  for (uint32_t u = 0; u < scenario_.uavs; ++u) {
    if (core::home_region(u, geo_.region_count()) == cfg_.region) home_uavs_.push_back(u);
  }
  gateway_uavs_ = home_uavs_;
  for (core::RegionId r = 0; r < geo_.region_count(); ++r) {
    if (r != cfg_.region) other_regions_.push_back(r);
  }
  replicated_ = cfg_.common.standby || scenario_.standby;
  names_ = {scenario_.uavs, geo_.region_count(), core::replicas_of(replicated_)};
  resend_.resend_deposits(true);  // lockstep only: the forwarded ones (the owners drop copies)
  present_others_ = other_regions_;
  // Realtime: a tile no owner sent for two seconds (at least 10 ticks) is
  // left out of views; the owner is gone, and its region is dark.
  tiles_stale_after_ = std::max<uint32_t>(10, static_cast<uint32_t>(std::ceil(2.0 * scenario_.tick_rate_hz)));
  if (!cfg_.common.lockstep()) to_ground_ = core::FieldToGround::at_rate(scenario_.tick_rate_hz, cfg_.field_hz);
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
    // Its UAVs whose backup this region is talk to this place agent now.
    for (uint32_t u = 0; u < scenario_.uavs; ++u) {
      if (core::home_region(u, geo_.region_count()) == r &&
          core::backup_region(u, geo_.region_count()) == cfg_.region) {
        adopt(u, views_.state(u));
      }
    }
  }
  present_others_.clear();
  for (core::RegionId r : other_regions_) {
    if (!absent_.contains(r)) present_others_.push_back(r);
  }
}

void PlaceApp::adopt(uint32_t uav, const core::UavStateMsg* state_before) {
  if (adopted_.contains(uav)) return;
  adopted_[uav] = {state_before != nullptr ? state_before->deposits_sent : 0, desk_.taken_from(uav)};
  gateway_uavs_.push_back(uav);
  desk_.serve(uav);
  bus_->offer_views(std::vector<uint32_t>{uav});
  log_->warn("uav {} talks to this place agent, its backup gateway, from now on (its home place agent {} is gone)", uav,
             core::home_region(uav, geo_.region_count()));
}

void PlaceApp::publish_health(uint32_t tick, HealthKind kind) {
  const auto& l = core_.ledger();
  core::HealthMsg h{cfg_.region,  tick,           static_cast<float>(rate_), l.received,         l.applied,
                    l.rejected(), halos_missing_, kind == HealthKind::Final, gaps_.max_gap_ms(), gaps_.gaps_over_2()};
  h.replica = cfg_.replica;
  h.deposits_duplicate = desk_.copies();
  h.bytes_received = bus_->stats().bytes_taken;
  h.linked = linked_;
  h.life = cfg_.life;
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
  if (forwards_failed_ > 0) {
    log_->info(
        "  not forwarded {}: their region's place agent was not reachable or the write failed (lost unless "
        "another replica of this region forwarded them)",
        forwards_failed_);
  }
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
  while (!runtime::shutdown_requested() && !commands_->ended()) {
    runtime::note_tick_start(gaps_, *log_, tick);
    relay_uplinks();  // the commands among them
    // Paused from the console: no evaporation, no diffusion, deposits wait
    // in the reader; health still goes out.
    if (!commands_->paused()) {
      step(tick++, std::nullopt);
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
  step(tick, std::nullopt);
  relay_uplinks();
  finish(tick);
  return 0;
}

bool PlaceApp::note_linked() {
  if (!linked_) {
    linked_ = std::all_of(other_regions_.begin(), other_regions_.end(),
                          [&](core::RegionId r) { return bus_->matched_deposit_readers(r) >= 1; });
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
  log_->debug("tick {}: the clock asks for {} deposits and {} home UAV states", c.tick, demand.deposits, demand.states);
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

void PlaceApp::relay_clock(const core::ClockMsg& c) {
  bus_->relay_clock(c, cfg_.region);
  ++clocks_relayed_;
}

void PlaceApp::route_carried(core::CarriedDeposits fate) {
  switch (fate) {
    case core::CarriedDeposits::Judge:
      uplinked_.insert(uplinked_.end(), carried_.begin(), carried_.end());
      break;
    case core::CarriedDeposits::Reject:
      refused_carried_.insert(refused_carried_.end(), carried_.begin(), carried_.end());
      break;
    case core::CarriedDeposits::Refuse:
      audit_.refuse(core::Refusal::RefusedStateDeposit,
                    fmt::format("{} deposit(s) carried by a state of no UAV of the swarm", carried_.size()),
                    carried_.size());
      break;
  }
}

void PlaceApp::reject_carried() {
  // Taken (the UAV's view confirms them; lockstep: they count among the
  // deposits its state says it sent) but neither applied nor forwarded; a
  // copy (a re-sent state) once.
  rejected_carried_.clear();
  for (const auto& d : refused_carried_) {
    if (desk_.take(d, current_tick_) != core::DepositRoute::Copy) rejected_carried_.push_back(d);
  }
  refused_carried_.clear();
  core_.reject(rejected_carried_, core::kRejectedWithState);
  audit_.refuse(core::Refusal::RefusedStateDeposit,
                fmt::format("{} deposit(s) carried by a state its gateway refused", rejected_carried_.size()),
                rejected_carried_.size());
}

void PlaceApp::relay_reports() {
  // A report goes on as it came (the ground station checks it): the
  // conductor keys it by its UAV, and with standbys the reader takes the
  // owning replica's copy (exclusive ownership, bus/qos.hpp).
  // Only a report of a UAV it can be the gateway of, from the UAV's own
  // process (core::judge_uav_report), as its detections and broadcasts.
  reports_.clear();
  bus_->take_uav_reports(reports_);
  const auto now = Clock::now();
  for (const auto& m : reports_) {
    const uint32_t uav = m.process & 0xFFFFFFU;
    if (!audit_.admit(core::judge_uav_report(m, cfg_.region, names_, from_uav_process(uav, m.participant, now)))) {
      continue;
    }
    bus_->publish_phase_done(m);
    ++reports_relayed_;
  }
}

void PlaceApp::keep_tree() {
  if (!cfg_.common.lockstep()) return;
  std::vector<core::ClockMsg> accepted;
  runtime::take_clock(*bus_, follower_, audit_, &accepted);
  for (const auto& c : accepted) relay_clock(c);
  relay_uplinks();
}

void PlaceApp::relay_idle() {
  // Between phases: the states of the UAV phase under way go to the ground
  // station now (its conductor waits for them), and are this place agent's
  // for the place phase that follows. A UAV whose home the clock lists
  // absent from this tick on sends its state here already: adopt it first.
  note_absent();
  take_home_states(current_tick_);
  relay_uplinks();
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
  loop.wake_on_reports = true;
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
  bus_->subscribe_place_exchange(cfg_.region);
  bus_->subscribe_halos(core_.neighbours(), cfg_.region);
  bus_->offer_deposits(other_regions_);
  bus_->offer_place_exchange(other_regions_);
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
