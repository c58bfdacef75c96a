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
      resend_(*bus_, cfg_.common.lockstep()),
      log_(spdlog::default_logger()),
      core_(scenario_, cfg_.region),
      rate_(scenario_.tick_rate_hz),
      gaps_(std::chrono::nanoseconds(static_cast<int64_t>(1e9 / scenario_.tick_rate_hz))),
      views_(geo_, static_cast<int>(core::policy_traits(scenario_).layers.size()), core::policy_traits(scenario_).view_radius),
      traits_(core::policy_traits(scenario_)),
      layer_ranges_(traits_.layer_ranges),
      max_step_(traits_.max_step) {
  for (uint32_t u = 0; u < scenario_.uavs; ++u) {
    if (core::home_region(u, geo_.region_count()) == cfg_.region) home_uavs_.push_back(u);
  }
  for (core::RegionId r = 0; r < geo_.region_count(); ++r) {
    if (r != cfg_.region) other_regions_.push_back(r);
  }
  replicated_ = cfg_.common.standby || scenario_.standby;
  present_others_ = other_regions_;
}

void PlaceApp::note_absent(const core::ClockMsg& c) {
  bool changed = false;
  for (core::RegionId r : c.absent) {
    if (r == cfg_.region || r >= geo_.region_count() || !absent_.insert(r).second) continue;
    changed = true;
    log_->warn("tick {}: the place agent of region {} is gone (no standby); its field and ring stay as they were", c.tick, r);
  }
  if (!changed) return;
  present_others_.clear();
  for (core::RegionId r : other_regions_) {
    if (!absent_.contains(r)) present_others_.push_back(r);
  }
}

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
// Swarms with standbys: deposit seqs remembered per UAV to drop a second
// copy (both replicas of a home forward each deposit, and lockstep UAVs
// re-send theirs after a quiet spell; the copies arrive within a tick or so).
constexpr std::size_t kSeenSeqs = 4096;
}  // namespace

uint32_t PlaceApp::tick_ceiling() const {
  return exact_ ? core::lockstep_tick_ceiling(current_tick_) : runtime::realtime_tick_ceiling(scenario_.tick_rate_hz);
}

void PlaceApp::refuse(core::Refusal r, const std::string& what) {
  refused_.add(r);
  if (refused_.total() <= 5) log_->warn("refused {} ({})", what, core::refusal_name(r));
}

void PlaceApp::keep_conductor_clock(std::vector<core::ClockMsg>& cmds) {
  // The first clock sample names the conductor: on an open domain anyone can
  // write a clock (a forged Stop would end the run), but no one can write
  // through another process's DDS writer.
  std::erase_if(cmds, [&](const core::ClockMsg& c) {
    if (!conductor_) conductor_ = c.writer;
    if (c.writer == *conductor_) return false;
    refuse(core::Refusal::ForeignClock,
           fmt::format("a clock sample of tick {} phase {} from another writer", c.tick, c.phase));
    return true;
  });
}

bool PlaceApp::duplicate(const core::DepositMsg& d) {
  // Only swarms with standbys send copies; elsewhere a repeated sequence
  // number is a replay, which PlaceCore rejects with its reason.
  if (!replicated_) return false;
  auto& seen = seen_seq_[d.uav];
  if (!seen.insert(d.seq).second) return true;
  if (seen.size() > kSeenSeqs) seen.erase(seen.begin());
  return false;
}

void PlaceApp::take_deposits() {
  taken_.clear();
  bus_->take_deposits(taken_);
  for (const auto& d : taken_) {
    // What this replica received from its own UAVs, confirmed in their views.
    // Only a seq the UAV can have reached: one forged far ahead would confirm
    // every deposit the UAV sends from then on (core/plausibility.hpp).
    if (core::home_region(d.uav, geo_.region_count()) == cfg_.region && !core::check_uav_id(d.uav, scenario_.uavs)) {
      auto it = acked_.find(d.uav);
      const auto last = it == acked_.end() ? std::nullopt : std::optional<uint32_t>(it->second.first);
      const uint32_t since = current_tick_ - (it == acked_.end() ? 0 : std::min(it->second.second, current_tick_));
      if ((!last || d.seq > *last) && !core::check_seq_reachable(d.seq, last, since)) acked_[d.uav] = {d.seq, current_tick_};
    }
    if (duplicate(d)) {
      ++duplicates_;
      continue;
    }
    if (d.region == cfg_.region || d.region >= geo_.region_count()) {
      inbox_.push_back(d);  // ours, or for no region at all (PlaceCore rejects it with the reason)
      continue;
    }
    // A home UAV's deposit for another region: to the owner's place agent.
    if (is_absent(d.region)) {
      ++deposits_lost_;  // the conductor counts it lost (deposits_lost)
      continue;
    }
    if (bus_->matched_deposit_readers(d.region) == 0) {
      core_.reject({d}, "owner place agent of region " + std::to_string(d.region) + " not reachable to forward to");
      continue;
    }
    if (bus_->publish_deposit(d, d.region)) {
      ++deposits_forwarded_;
    } else {
      core_.reject({d}, "forwarding to region " + std::to_string(d.region) + " failed");
    }
  }
}

void PlaceApp::take_home_states(uint32_t tick) {
  state_inbox_.clear();
  bus_->take_uav_states(state_inbox_);
  const uint32_t ceiling = tick_ceiling();
  for (const auto& st : state_inbox_) {
    if (auto reason = core::check_uav_id(st.uav, scenario_.uavs)) {
      refuse(core::Refusal::UnknownUav, "a state: " + *reason);
      continue;
    }
    if (core::home_region(st.uav, geo_.region_count()) != cfg_.region) continue;  // not ours (a stray writer)
    if (auto reason = core::check_uav_state(st, geo_)) {
      if (++samples_rejected_ <= 3) log_->warn("dropped state of uav {}: {}", st.uav, *reason);
      continue;
    }
    if (auto reason = core::check_tick_reachable(st.tick, ceiling, "state")) {
      refuse(core::Refusal::TickFarAhead, *reason);
      continue;
    }
    const core::UavStateMsg* before = views_.state(st.uav);
    // The place agent cannot tell a restarted UAV from a forger: a state whose
    // tick went back may start again from the UAV's start cell.
    if (auto reason = core::check_state_motion(st, before, core::uav_start(scenario_, traits_, st.uav), max_step_, true)) {
      refuse(core::Refusal::ImplausibleState, *reason);
      continue;
    }
    if (before == nullptr || st.tick > before->tick) heard_at_[st.uav] = tick;
    views_.update_state(st);
  }
}

void PlaceApp::serve_views(uint32_t tick, bool exact) {
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
  const auto deadline = Clock::now() + std::chrono::seconds(30);
  for (;;) {
    field_inbox_.clear();
    bus_->take_fields(field_inbox_);
    const uint32_t ceiling = tick_ceiling();
    for (const auto& f : field_inbox_) {
      if (f.region == cfg_.region) continue;
      bool ok = f.region < geo_.region_count();
      for (const auto& t : f.tiles) ok = ok && !core::check_tile(t, geo_, core_.layer_count());
      for (const auto& st : f.uavs) ok = ok && !core::check_uav_state(st, geo_);
      if (!ok) {
        if (++samples_rejected_ <= 3) log_->warn("dropped a malformed field chunk of region {}", f.region);
        continue;
      }
      if (auto reason = core::check_tick_reachable(f.tick, ceiling, "field chunk")) {
        refuse(core::Refusal::TickFarAhead, *reason);
        continue;
      }
      const auto out_of_range = std::find_if(f.tiles.begin(), f.tiles.end(),
                                             [&](const auto& t) { return core::check_tile_range(t, layer_ranges_); });
      if (out_of_range != f.tiles.end()) {
        refuse(core::Refusal::ValueOutOfRange, *core::check_tile_range(*out_of_range, layer_ranges_));
        continue;
      }
      const auto stranger = std::find_if(f.uavs.begin(), f.uavs.end(),
                                         [&](const auto& st) { return core::check_uav_id(st.uav, scenario_.uavs); });
      if (stranger != f.uavs.end()) {
        refuse(core::Refusal::UnknownUav, "a field chunk with " + *core::check_uav_id(stranger->uav, scenario_.uavs));
        continue;
      }
      views_.update_field(f);
    }
    if (!exact || views_.holds_fields(tick, present_others_)) break;
    if (Clock::now() > deadline || runtime::shutdown_requested()) {
      log_->error("tick {}: the fields of some regions did not arrive ({}); views use the latest", tick,
                  views_.missing_fields(tick, present_others_));
      break;
    }
    resend_.resend_if_quiet();
    bus_->wait({bus::TopicKind::Field}, std::min(deadline, Clock::now() + std::chrono::milliseconds(100)));
  }
  for (uint32_t u : home_uavs_) {
    const core::UavStateMsg* st = views_.state(u);
    if (st == nullptr || st->finished) continue;
    if (!exact && tick - heard_at_[u] > kViewsAfterSilence) continue;
    if (views_.compose(u, tick, exact ? 0 : kNeighbourAge, view_)) {
      auto a = acked_.find(u);
      view_.deposit_ack = a == acked_.end() ? 0 : a->second.first;
      resend_.view(view_);
    }
  }
}

void PlaceApp::step(uint32_t tick, bool exact, std::optional<uint32_t> expected_deposits) {
  current_tick_ = tick;
  exact_ = exact;
  resend_.begin_tick();
  inbox_.clear();
  take_deposits();
  if (expected_deposits) {
    const auto deadline = Clock::now() + std::chrono::seconds(30);
    // Forged deposits carrying this tick must not stand in for real ones
    // (the place would apply the tick before all of them arrived).
    const auto of_tick = [&] {
      return static_cast<uint32_t>(std::count_if(inbox_.begin(), inbox_.end(), [&](const auto& d) {
        return d.tick == tick && !core_.refuses(d, tick);
      }));
    };
    while (of_tick() < *expected_deposits) {
      if (Clock::now() > deadline || runtime::shutdown_requested()) {
        log_->error("tick {}: {} of {} announced deposits arrived; applying those", tick, of_tick(), *expected_deposits);
        break;
      }
      bus_->wait({bus::TopicKind::Deposit}, std::min(deadline, Clock::now() + std::chrono::milliseconds(100)));
      take_deposits();
    }
  }
  take_home_states(tick);
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
  // Neighbour rings. Realtime: whatever arrived (a neighbour that sent
  // nothing new leaves its last ring in the halo, counted as missing).
  // Lockstep: exactly the rings of this tick, waited for.
  std::set<core::RegionId> fresh;
  // Lockstep: an absent neighbour's last ring stays in the halo (frozen).
  const std::size_t awaited = static_cast<std::size_t>(
      std::count_if(core_.neighbours().begin(), core_.neighbours().end(), [&](core::RegionId n) { return !is_absent(n); }));
  const auto deadline = Clock::now() + std::chrono::seconds(30);
  for (;;) {
    halo_inbox_.clear();
    bus_->take_halos(halo_inbox_);
    const uint32_t ceiling = tick_ceiling();
    for (const auto& h : halo_inbox_) {
      if (exact && (h.tick != tick || is_absent(h.region))) continue;
      if (auto reason = core::check_tick_reachable(h.tick, ceiling, "halo")) {
        refuse(core::Refusal::TickFarAhead, *reason);
        continue;
      }
      if (!core_.accept_halo(h)) {
        log_->warn("dropped malformed or out-of-range halo from region {}", h.region);
        continue;
      }
      fresh.insert(h.region);
    }
    if (!exact || fresh.size() >= awaited) break;
    if (Clock::now() > deadline || runtime::shutdown_requested()) {
      log_->error("tick {}: rings of {} of {} neighbours did not arrive", tick, awaited - std::min(awaited, fresh.size()),
                  awaited);
      break;
    }
    resend_.resend_if_quiet();
    bus_->wait({bus::TopicKind::Halo}, std::min(deadline, Clock::now() + std::chrono::milliseconds(100)));
  }
  halos_missing_ += awaited - std::min(fresh.size(), awaited);
  core_.finish_tick();
  tiles_out_.clear();
  core_.tiles(tick, false, tiles_out_);
  serve_views(tick, exact);
}

void PlaceApp::publish_health(uint32_t tick, bool finished) {
  const auto& l = core_.ledger();
  core::HealthMsg h{cfg_.region, tick, static_cast<float>(rate_), l.received, l.applied, l.rejected(), halos_missing_,
                    finished, gaps_.max_gap_ms(), gaps_.gaps_over_2()};
  h.replica = cfg_.replica;
  h.deposits_duplicate = duplicates_;
  core::RefusalCounts all = refused_;
  for (std::size_t i = 0; i < core::kRefusalCount; ++i) all.add(static_cast<core::Refusal>(i), l.refused.n[i]);
  h.refused = all.n;
  bus_->publish_health(h);
}

void PlaceApp::log_summary(uint32_t tick) {
  const auto& l = core_.ledger();
  log_->info("region {}{} finished at tick {}: deposits received {}, applied {}, rejected {}, duplicates dropped {}; "
             "forwarded {} of its {} home UAVs' to other regions; samples dropped {}; lockstep re-sends {}{}",
             cfg_.region, cfg_.replica > 0 ? " (standby " + std::to_string(cfg_.replica) + ")" : "", tick, l.received,
             l.applied, l.rejected(), duplicates_, deposits_forwarded_, home_uavs_.size(), samples_rejected_,
             resend_.resends(),
             deposits_lost_ > 0 ? fmt::format("; {} deposits for absent regions lost", deposits_lost_) : std::string());
  for (const auto& [reason, n] : l.rejected_by_reason) log_->info("  rejected {}: {}", n, reason);
  for (std::size_t i = 0; i < core::kRefusalCount; ++i) {
    const uint64_t n = uint64_t{refused_.n[i]} + l.refused.n[i];
    if (n > 0) log_->info("  refused as implausible ({}): {}", core::refusal_name(static_cast<core::Refusal>(i)), n);
  }
  if (!cfg_.common.lockstep()) {
    log_->info("region {} kept its clock: longest gap between tick starts {} ms ({:.2f} periods), {} gaps over 2 periods",
               cfg_.region, gaps_.max_gap_ms(), gaps_.max_gap_periods(), gaps_.gaps_over_2());
  }
}

int PlaceApp::run_realtime() {
  runtime::TickClock clock(rate_);
  auto last_health = Clock::now();
  uint32_t tick = 0;
  while (!runtime::shutdown_requested() && !commands_->ended() && (cfg_.max_ticks == 0 || tick < cfg_.max_ticks)) {
    if (const auto gap = gaps_.on_tick_start(Clock::now()); gap && gaps_.gaps_over_2() <= 10) {
      log_->warn("tick {} started {} ms after the one before ({:.1f} tick periods)", tick,
                 std::chrono::duration_cast<std::chrono::milliseconds>(*gap).count(),
                 static_cast<double>(gap->count()) / static_cast<double>(gaps_.period().count()));
    }
    commands_->take();
    // Paused from the console: no evaporation, no diffusion, deposits wait
    // in the reader; health still goes out.
    if (!commands_->paused()) {
      step(tick, false);
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
  step(tick, false);
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
  auto watch = core::ConductorWatch::for_lease(std::chrono::milliseconds(cfg_.common.lease_ms), Clock::now());
  bool ready = false;
  while (!stop && !runtime::shutdown_requested()) {
    // Before tick 0: report Ready once every other region's place agent reads
    // the deposits this one forwards (the conductor starts tick 0 when every
    // process is ready).
    if (!ready && done_tick < 0 && std::all_of(other_regions_.begin(), other_regions_.end(), [&](core::RegionId r) {
          return bus_->matched_deposit_readers(r) >= 1;
        })) {
      resend_.phase_done({core::process_key(core::kRolePlace, cfg_.region), 0, static_cast<uint8_t>(core::ClockPhase::Ready), 0, {}});
      ready = true;
      log_->debug("matched every other region's place agent: ready");
    }
    cmds.clear();
    bus_->take_clock(cmds);
    keep_conductor_clock(cmds);
    if (!cmds.empty()) watch.on_clock(Clock::now());
    for (const auto& c : cmds) {
      note_absent(c);
      if (c.phase == static_cast<uint8_t>(core::ClockPhase::Stop)) {
        stop = true;
      } else if (c.phase == static_cast<uint8_t>(core::ClockPhase::Place) && static_cast<int64_t>(c.tick) > done_tick) {
        if (replicated_ && done_tick >= 0 && static_cast<int64_t>(c.tick) > done_tick + 1) {
          // The swarm went on without this replica (it was stopped or cut
          // off longer than a lease and another replica served the region):
          // its field missed ticks and must not be served again.
          log_->error("region {} replica {}: the lockstep clock is at tick {} but this replica finished tick {} last; it "
                      "missed ticks while it was stopped or cut off and leaves (another replica serves the region)",
                      cfg_.region, cfg_.replica, c.tick, done_tick);
          return kReplicaBehind;
        }
        if (!ready) {
          log_->warn("tick {} starts before every other region's place agent was matched: forwarded deposits may be rejected",
                     c.tick);
          ready = true;
        }
        // Every tile, every tick: a UAV waits for tiles of exactly this tick.
        uint32_t expected = 0;
        for (const auto& rc : c.deposits) expected += rc.region == cfg_.region ? rc.count : 0;
        step(c.tick, true, expected);
        publish_health(c.tick, false);
        // No flush here: every reader of what this phase wrote waits for
        // exactly this tick's samples (fields, halos, views, forwarded
        // deposits by count), and the re-sender covers a sample that does not
        // come out. A flush would wait for the acknowledgement of every
        // matched reader, also of a killed process, whose readers stay
        // matched until its participant lease ends (docs/dds.md).
        const uint32_t id = replicated_ ? core::place_id(cfg_.region, cfg_.replica) : cfg_.region;
        resend_.phase_done({core::process_key(core::kRolePlace, id), c.tick, c.phase, 0, {}});
        done_tick = c.tick;
      }
    }
    if (cmds.empty()) {
      if (watch.lost(Clock::now())) {
        log_->error("the conductor (ground station) is gone: no lockstep clock for {:.1f} s ({} leases of {} ms) after tick {}; "
                    "stopping",
                    std::chrono::duration<double>(watch.silence(Clock::now())).count(),
                    watch.limit() / std::chrono::milliseconds(cfg_.common.lease_ms), cfg_.common.lease_ms, done_tick);
        log_summary(static_cast<uint32_t>(std::max<int64_t>(done_tick, 0)));
        return kConductorLost;
      }
      if (resend_.resend_if_quiet()) log_->debug("tick {}: nothing new for 1 s; re-sent this tick's samples", done_tick);
      bus_->wait({bus::TopicKind::Clock}, Clock::now() + std::chrono::milliseconds(100));
    }
  }
  // Wait for SIGTERM from the launcher; deposits arriving now (none in a
  // clean run) are counted, not applied to the field, so the final field
  // stays that of the last conducted tick.
  // Polling the bus keeps this process's writers alive (manual-by-topic
  // liveliness), so the ground station does not report it lost meanwhile.
  while (!runtime::shutdown_requested() && !commands_->ended()) {
    commands_->take();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  inbox_.clear();
  take_deposits();
  if (!inbox_.empty()) log_->warn("{} deposits arrived after the last tick; rejected", inbox_.size());
  core_.reject(inbox_, "arrived after the last lockstep tick");
  const auto final_tick = static_cast<uint32_t>(std::max<int64_t>(done_tick, 0));
  publish_health(final_tick, true);
  bus_->flush(std::chrono::seconds(3));
  log_summary(final_tick);
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
  log_->info("place agent for region {} [{}..{})x[{}..{}) with {} tiles, {} neighbours, {} clock{} over {}{}", cfg_.region,
             r.x0, r.x0 + r.w, r.y0, r.y0 + r.h, core_.owned_tiles().size(), core_.neighbours().size(), cfg_.common.clock,
             cfg_.common.lockstep() ? "" : fmt::format(" at {:.1f} Hz", rate_), bus_->vendor(),
             !replicated_ ? std::string() : cfg_.replica == 0 ? std::string(", primary of a replicated region")
                                                              : fmt::format(", hot standby {}", cfg_.replica));
  return cfg_.common.lockstep() ? run_lockstep() : run_realtime();
}

}  // namespace pheromesh::placeagent
