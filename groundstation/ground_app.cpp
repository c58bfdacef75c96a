#include "ground_app.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <future>
#include <limits>
#include <thread>

#include "pheromesh/console/view.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/uav_core.hpp"
#include "pheromesh/runtime/report.hpp"

namespace pheromesh::groundstation {

using Clock = std::chrono::steady_clock;

namespace {
int64_t unix_ms_now() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}
}  // namespace

GroundApp::GroundApp(GroundConfig cfg, core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus)
    : cfg_(std::move(cfg)),
      launcher_(cfg_.launcher_fd),
      scenario_(std::move(scenario)),
      geo_(scenario_.geometry()),
      world_(geo_, scenario_.obstacles, scenario_.targets),
      bus_(std::move(bus)),
      // Only conduct() (lockstep) publishes through it. The clock goes out at
      // least every half lease: the UAVs and place agents take a long
      // silence for the conductor's death (core::ConductorWatch).
      resend_(*bus_, true, std::min(std::chrono::milliseconds(1000), std::chrono::milliseconds(cfg_.common.lease_ms) / 2)),
      log_(spdlog::default_logger()),
      rec_(scenario_, world_),
      frame_builder_(geo_),
      conductor_({cfg_.expect_uavs != 0 ? cfg_.expect_uavs : scenario_.uavs, geo_.region_count(),
                  std::chrono::milliseconds(static_cast<int64_t>(cfg_.phase_timeout_s * 1000)),
                  std::chrono::milliseconds(static_cast<int64_t>(cfg_.departed_grace_s * 1000)),
                  (cfg_.common.standby || scenario_.standby) ? 1U : 0U,
                  std::chrono::milliseconds(static_cast<int64_t>(cfg_.start_timeout_s * 1000))}),
      layers_(static_cast<int>(core::policy_traits(scenario_).layers.size())),
      layer_ranges_(core::policy_traits(scenario_).layer_ranges) {
  if (cfg_.expect_uavs == 0) cfg_.expect_uavs = scenario_.uavs;
  // Place agents have standby replicas (--standby, common to every process, or run.standby).
  cfg_.standby = cfg_.common.standby || scenario_.standby;
  run_t0_unix_ms_ = unix_ms_now();
  if (const char* t0 = std::getenv("PHEROMESH_RUN_T0_MS"); t0 != nullptr) {
    char* end = nullptr;
    const long long v = std::strtoll(t0, &end, 10);
    if (end != t0 && *end == '\0' && v > 0) {
      run_t0_unix_ms_ = v;
      launch_known_ = true;
    }
  }
}

void GroundApp::note_discovery() {
  const bool all = frame_builder_.uavs_heard() >= cfg_.expect_uavs && frame_builder_.regions_heard() >= geo_.region_count();
  if (all && !discovery_s_) {
    discovery_s_ = static_cast<double>(unix_ms_now() - run_t0_unix_ms_) / 1000.0;
    log_->info("discovery complete: every UAV ({}) and place agent ({}) heard {:.1f} s after the launch",
               cfg_.expect_uavs, geo_.region_count(), *discovery_s_);
  }
  // Realtime UAVs wait for the start to fly (UavApp::wait_for_start): once
  // every process is heard, or after a bound that grows with the swarm, so
  // one process that never came up does not hold the others back.
  if (start_sent_ || cfg_.common.lockstep() || cfg_.attach) return;
  const auto bound = std::chrono::milliseconds(static_cast<int64_t>(1000.0 * (30.0 + 0.1 * cfg_.expect_uavs)));
  if (!all && Clock::now() - started_at_ < bound) return;
  if (!all) {
    log_->warn("starting the swarm without {} of {} UAVs and {} of {} place agents, not heard within {} s",
               cfg_.expect_uavs - std::min<std::size_t>(cfg_.expect_uavs, frame_builder_.uavs_heard()), cfg_.expect_uavs,
               geo_.region_count() - std::min<std::size_t>(geo_.region_count(), frame_builder_.regions_heard()), geo_.region_count(),
               bound.count() / 1000);
  }
  start_sent_ = true;
  core::CommandMsg start;
  start.kind = static_cast<uint8_t>(core::CommandKind::Start);
  const auto a = publish_swarm_command(start);
  if (a.status == 200) {
    log_->info("{}", a.message);
  } else {
    log_->warn("cannot start the swarm: {}", a.message);
  }
}

void GroundApp::note_acquisitions() {
  for (const auto& d : rec_.take_first_acquisitions()) {
    frame_builder_.target_found(d.target, d.uav, d.tick);
    log_->info("target {} at ({},{}) first acquired by uav {} at tick {} ({}/{})", d.target, d.cell.x, d.cell.y, d.uav,
               d.tick, rec_.acquisitions().found(), world_.targets().size());
  }
}

uint32_t GroundApp::tick_ceiling() const {
  // Lockstep: the conductor's own clock. Realtime: the launch time shared by
  // every process of the run; a monitor attached later does not know it.
  if (cfg_.common.lockstep() && !cfg_.attach) return core::lockstep_tick_ceiling(conducted_tick_);
  if (cfg_.attach || !launch_known_) return std::numeric_limits<uint32_t>::max();
  return core::realtime_tick_ceiling(static_cast<double>(unix_ms_now() - run_t0_unix_ms_) / 1000.0, scenario_.tick_rate_hz);
}

void GroundApp::note_refused(core::Refusal r, const std::string& what) {
  rec_.count_refused(r);
  if (rec_.refused().total() <= 5) log_->warn("refused {} ({})", what, core::refusal_name(r));
}

void GroundApp::poll() {
  const uint32_t ceiling = tick_ceiling();
  rec_.set_tick_ceiling(ceiling);
  states_.clear();
  bus_->take_uav_states(states_);
  for (const auto& s : states_) {
    const uint64_t refused_before = rec_.refused().total();
    if (!rec_.on_uav_state(s)) {
      if (rec_.samples_rejected() <= 3 && rec_.refused().total() == refused_before) {
        log_->warn("dropped state of uav {}", s.uav);
      } else if (rec_.refused().total() <= 5) {
        log_->warn("refused state of uav {} at tick {} ({}, {}): implausible", s.uav, s.tick, s.x, s.y);
      }
      continue;
    }
    conductor_.heard_from(s.uav, Clock::now());
    const bool back = s.finished ? conductor_.on_uav_finished(s.uav)
                                 : conductor_.on_uav_state(s.uav, s.tick, geo_.tile_of(core::state_cell(s)));
    if (back && !s.finished) log_->info("uav {} is back at tick {}", s.uav, s.tick);
    frame_builder_.heard_uav(s.uav, Clock::now());
    if (uncertainty_ && !s.finished) uncertainty_->observe(core::state_cell(s), s.tick);
  }
  broadcasts_.clear();
  bus_->take_broadcasts(broadcasts_);
  for (const auto& b : broadcasts_) {
    if (core::check_broadcast(b)) {
      rec_.count_rejected_sample();
      continue;
    }
    if (core::check_uav_id(b.uav, scenario_.uavs)) {
      note_refused(core::Refusal::UnknownUav, "a broadcast of uav " + std::to_string(b.uav));
      continue;
    }
    conductor_.on_broadcast(b.uav, b.tick);
    conductor_.heard_from(b.uav, Clock::now());
  }
  std::vector<uint32_t> gone;
  bus_->take_departed_uavs(gone);
  for (uint32_t id : gone) {
    if (core::check_uav_id(id, scenario_.uavs)) continue;  // a forger's writer left, not a UAV
    auto it = rec_.uavs().find(id);
    const bool finished = it != rec_.uavs().end() && it->second.finished;
    if (conductor_.on_uav_departed(id, Clock::now()) && !finished) {
      log_->warn("uav {} lost (liveliness) at tick {}", id, it != rec_.uavs().end() ? it->second.last.tick : 0);
    }
    rec_.on_uav_departed(id);
  }
  detections_.clear();
  bus_->take_detections(detections_);
  for (const auto& d : detections_) rec_.on_detection(d);
  note_acquisitions();
  events_.clear();
  bus_->take_target_events(events_);
  for (const auto& e : events_) {
    rec_.on_target_event(e);
    // Shao 2020 revisits (marks.hpp).
    if (e.kind == static_cast<uint8_t>(core::TargetEventKind::RevisitDue)) frame_builder_.revisit(e.cell, true);
    if (e.kind == static_cast<uint8_t>(core::TargetEventKind::Revisited)) frame_builder_.revisit(e.cell, false);
  }
  healths_.clear();
  bus_->take_health(healths_);
  for (const auto& h : healths_) {
    const auto owner_before = rec_.region_owner(h.region);
    if (rec_.on_health(h)) {
      log_->warn("place agent {}{} is back at tick {}", h.region, h.replica > 0 ? fmt::format(" (standby {})", h.replica) : "",
                 h.tick);
    }
    const auto owner = rec_.region_owner(h.region);
    if (owner_before && owner && *owner < *owner_before) {
      log_->info("region {}: replica {} owns it again", h.region, *owner);
    }
    frame_builder_.heard_region(h.region, Clock::now());
  }
  tiles_.clear();
  bus_->take_tiles(tiles_);
  fields_.clear();
  bus_->take_fields(fields_);
  for (auto& f : fields_) {
    // A forged chunk must not enter the field nor the count of chunks the
    // last tick waits for (holds_last_fields).
    if (auto reason = core::check_tick_reachable(f.tick, ceiling, "field")) {
      note_refused(core::Refusal::TickFarAhead, *reason);
      continue;
    }
    const auto out_of_range = std::find_if(f.tiles.begin(), f.tiles.end(),
                                           [&](const auto& t) { return core::check_tile_range(t, layer_ranges_); });
    if (out_of_range != f.tiles.end()) {
      note_refused(core::Refusal::ValueOutOfRange, "a field chunk: " + *core::check_tile_range(*out_of_range, layer_ranges_));
      continue;
    }
    if (f.region < geo_.region_count()) {
      auto& [tick, chunks] = field_ticks_[f.region];
      if (f.tick > tick || chunks.empty()) {
        tick = f.tick;
        chunks.clear();
      }
      if (f.tick == tick) chunks.insert(f.chunk);
      field_chunks_[f.region] = f.chunks;
    }
    for (auto& t : f.tiles) tiles_.push_back(std::move(t));
  }
  for (auto& t : tiles_) {
    if (auto reason = core::check_tile(t, geo_, layers_)) {
      rec_.count_rejected_sample();
      if (rec_.samples_rejected() <= 3) log_->warn("dropped tile ({},{}): {}", t.tile.tx, t.tile.ty, *reason);
      continue;
    }
    // Forged values must not reach the final field (plausibility.hpp).
    if (auto reason = core::check_tick_reachable(t.tick, ceiling, "tile")) {
      note_refused(core::Refusal::TickFarAhead, *reason);
      continue;
    }
    if (auto reason = core::check_tile_range(t, layer_ranges_)) {
      note_refused(core::Refusal::ValueOutOfRange, *reason);
      continue;
    }
    auto& slot = tiles_latest_[{t.layer, {t.tile.tx, t.tile.ty}}];
    if (slot.values.empty() || t.tick >= slot.tick) slot = std::move(t);
  }
  std::vector<uint32_t> places_gone;
  bus_->take_departed_regions(places_gone);
  for (uint32_t id : places_gone) {
    const core::RegionId r = core::place_id_region(id);
    const uint16_t replica = core::place_id_replica(id);
    auto it = rec_.replica_health().find(id);
    const bool finished = it != rec_.replica_health().end() && it->second.finished;
    rec_.on_place_departed(id);
    if (finished) continue;
    if (cfg_.common.standby || scenario_.standby) conductor_.on_place_departed(id);
    const std::string who = replica > 0 ? fmt::format("standby {} of region {}", replica, r) : fmt::format("place agent {}", r);
    if (auto owner = rec_.region_owner(r)) {
      log_->warn("{} lost (liveliness); region {} is served by {}", who, r,
                 *owner == 0 ? std::string("its primary") : fmt::format("standby {}", *owner));
    } else {
      log_->warn("{} lost (liveliness); region {} has no live place agent: deposits into it are lost", who, r);
    }
  }
  dones_.clear();
  bus_->take_phase_done(dones_);
  for (const auto& d : dones_) {
    conductor_.on_phase_done(d);
    if (d.process >> 24U == core::kRoleUav) conductor_.heard_from(d.process & 0xFFFFFFU, Clock::now());
  }
  note_discovery();
}

void GroundApp::print_progress() {
  uint32_t flying = 0;
  for (const auto& [id, u] : rec_.uavs()) flying += (u.alive && !u.finished) ? 1 : 0;
  uint64_t applied = 0, rejected = 0;
  for (const auto& [r, h] : rec_.health()) {
    applied += h.deposits_applied;
    rejected += h.deposits_rejected;
  }
  rec_.sample_coverage();
  uint32_t standby_owned = 0;
  for (core::RegionId r = 0; r < geo_.region_count(); ++r) {
    const auto owner = rec_.region_owner(r);
    standby_owned += owner && *owner > 0 ? 1 : 0;
  }
  log_->info("tick {:5d} | uavs {}/{} flying | places {}/{}{} | coverage {:5.1f}% | targets {}/{} | deposits sent {} applied {} "
             "rejected {} unaccounted {}",
             rec_.max_tick(), flying, cfg_.expect_uavs, rec_.regions_alive(), geo_.region_count(),
             standby_owned > 0 ? fmt::format(" ({} on standby)", standby_owned) : std::string(),
             100.0 * rec_.coverage().coverage(), rec_.acquisitions().found(), world_.targets().size(),
             rec_.deposits_sent(), applied, rejected, rec_.deposits_lost());
}

void GroundApp::progress_if_due() {
  if (Clock::now() < next_progress_) return;
  print_progress();
  next_progress_ += std::chrono::milliseconds(static_cast<int64_t>(cfg_.progress_period_s * 1000));
}

bool GroundApp::run_phase(uint32_t tick, core::ClockPhase phase) {
  conducted_tick_ = std::max(conducted_tick_, tick);
  poll();
  resend_.begin_tick();
  const auto t0 = Clock::now();
  resend_.clock(conductor_.begin_phase(tick, phase, t0));
  for (;;) {
    poll();
    const auto st = conductor_.status(Clock::now());
    const char* name = phase == core::ClockPhase::Uav ? "uav" : phase == core::ClockPhase::Place ? "place" : "ready";
    if (st.complete) {
      log_->debug("lockstep tick {} {} phase: {} ms", tick, name,
                  std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0).count());
      return true;
    }
    if (st.timed_out && phase == core::ClockPhase::Ready) {
      log_->warn("starting tick 0 although {} process(es) did not report ready within {} s (not yet matched: their first "
                 "deposits may be lost)",
                 st.waiting, cfg_.start_timeout_s);
      return true;
    }
    if (st.timed_out || runtime::shutdown_requested()) {
      log_->error("lockstep tick {} {} phase: {} process(es) did not finish within {} s", tick,
                  phase == core::ClockPhase::Uav ? "uav" : "place", st.waiting, cfg_.phase_timeout_s);
      return false;
    }
    progress_if_due();
    service();
    if (resend_.resend_if_quiet()) log_->debug("lockstep tick {}: nothing new for 1 s; re-sent the clock", tick);
    wait_for_data(Clock::now() + std::chrono::milliseconds(20));
  }
}

void GroundApp::wait_for_data(Clock::time_point until) {
  using K = bus::TopicKind;
  bus_->wait({K::UavState, K::Field, K::Tile, K::Detection, K::TargetEvent, K::Health, K::Broadcast, K::PhaseDone}, until);
}

void GroundApp::drop_uav(uint32_t uav, uint32_t tick) {
  if (!conductor_.drop_uav(uav)) return;
  log_->warn("lockstep tick {}: uav {} was killed; it no longer takes part", tick, uav);
  rec_.on_uav_killed();
  rec_.on_uav_departed(uav);
}

void GroundApp::drop_region(core::RegionId r, uint32_t tick) {
  if (cfg_.standby) {
    log_->warn("lockstep tick {}: place agent {} was killed; its standby answers for region {}", tick, r, r);
    conductor_.on_place_departed(core::place_id(r, 0));
    rec_.on_place_killed(false);
    return;
  }
  if (conductor_.drop_region(r)) {
    rec_.on_place_killed(true);
    log_->warn("lockstep tick {}: place agent {} was killed without a standby; region {} is absent from now on (its field "
               "frozen, deposits into it lost, its UAVs on empty views)",
               tick, r, r);
  }
}

bool GroundApp::apply_faults(uint32_t tick) {
  if (cfg_.launcher_fd < 0) {
    log_->error("lockstep tick {} has faults (--fault-ticks) but there is no launcher to inject them (--launcher-fd)", tick);
    return false;
  }
  // The launcher kills and reaps the processes of this tick before it
  // answers. Meanwhile the clock keeps going out (re-sent), so nobody takes
  // the wait for the conductor's death.
  const console::LauncherLink link(cfg_.launcher_fd,
                                   std::chrono::milliseconds(static_cast<int64_t>(cfg_.faults_timeout_s * 1000)));
  auto answer = std::async(std::launch::async, [&] { return link.ask("faults " + std::to_string(tick)); });
  while (answer.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
    poll();
    progress_if_due();
    resend_.resend_if_quiet();
    wait_for_data(Clock::now() + std::chrono::milliseconds(20));
  }
  const auto a = answer.get();
  if (a.status != 200) {
    log_->error("lockstep tick {}: the launcher did not inject the faults of this tick: {}", tick, a.message);
    return false;
  }
  auto gone = core::parse_gone(a.message, cfg_.expect_uavs, geo_.region_count());
  if (!gone) {
    log_->error("lockstep tick {}: {}", tick, gone.error().message);
    return false;
  }
  log_->info("lockstep tick {}: the launcher reports {}", tick, a.message);
  for (uint32_t u : gone->uavs) drop_uav(u, tick);
  for (core::RegionId r : gone->regions) drop_region(r, tick);
  for (uint32_t p : gone->standbys) {
    log_->warn("lockstep tick {}: standby {} of region {} was killed", tick, core::place_id_replica(p), core::place_id_region(p));
    conductor_.on_place_departed(p);
  }
  return true;
}

bool GroundApp::holds_last_fields(uint32_t tick) const {
  for (core::RegionId r = 0; r < geo_.region_count(); ++r) {
    if (conductor_.absent(r)) continue;
    auto it = field_ticks_.find(r);
    auto n = field_chunks_.find(r);
    if (it == field_ticks_.end() || n == field_chunks_.end() || it->second.first != tick ||
        it->second.second.size() < n->second) {
      return false;
    }
  }
  return true;
}

bool GroundApp::conduct() {
  bus_->subscribe_phase_done();
  const uint32_t ticks = scenario_.ticks;
  log_->info("conducting {} lockstep ticks", ticks);
  // Tick 0 waits until every process matched what it deposits to.
  bool ok = run_phase(0, core::ClockPhase::Ready);
  for (uint32_t k = 0; k <= ticks && ok && !runtime::shutdown_requested(); ++k) {
    // Paused from the console: the next tick is not announced (the last clock
    // is, again, so the swarm knows the conductor lives).
    while (paused_ && !runtime::shutdown_requested()) {
      poll();
      service();
      resend_.resend_if_quiet();
      wait_for_data(Clock::now() + std::chrono::milliseconds(10));
    }
    if (std::find(cfg_.fault_ticks.begin(), cfg_.fault_ticks.end(), k) != cfg_.fault_ticks.end()) ok = apply_faults(k);
    ok = ok && run_phase(k, core::ClockPhase::Uav) && run_phase(k, core::ClockPhase::Place);
    progress_if_due();
    service();
  }
  // The final field is that of the last tick: wait (bounded) until every
  // present region's field of it is here, before the place agents are let go.
  const auto deadline = Clock::now() + std::chrono::milliseconds(static_cast<int64_t>(cfg_.phase_timeout_s * 1000));
  while (ok && !holds_last_fields(ticks) && !runtime::shutdown_requested()) {
    if (Clock::now() > deadline) {
      log_->error("the fields of the last tick {} did not all reach the ground station within {} s", ticks, cfg_.phase_timeout_s);
      ok = false;
      break;
    }
    poll();
    resend_.resend_if_quiet();
    wait_for_data(Clock::now() + std::chrono::milliseconds(20));
  }
  // Stop: re-sent like every clock (run() keeps the re-sender going), not
  // flushed - a killed process's reader would never acknowledge it.
  resend_.begin_tick();
  resend_.clock(core::LockstepConductor::stop(ticks));
  if (conductor_.deposits_lost() > 0) {
    log_->info("{} deposits were lost with the place agents killed at a tick", conductor_.deposits_lost());
  }
  return ok;
}

bool GroundApp::places_finished() const {
  // Every replica heard of every region reported its final health or is
  // gone (a killed primary whose standby finished counts as done).
  std::vector<bool> heard(geo_.region_count(), false);
  for (const auto& [id, h] : rec_.replica_health()) {
    const core::RegionId r = core::place_id_region(id);
    if (r >= heard.size()) continue;
    heard[r] = true;
    if (!h.finished && !rec_.place_departed(id)) return false;
  }
  for (core::RegionId r = 0; r < geo_.region_count(); ++r) {
    if (!heard[r] && !rec_.region_departed(r)) return false;
  }
  return true;
}

void GroundApp::note_full_state() {
  if (full_state_logged_) return;
  if (frame_builder_.uavs_heard() < cfg_.expect_uavs || frame_builder_.regions_heard() < geo_.region_count() ||
      field_ticks_.size() < geo_.region_count()) {
    return;
  }
  full_state_logged_ = true;
  log_->info(
      "attached: the whole swarm is shown (every uav of {}, every place agent of {}, every region's field) {:.2f} s "
      "after the monitor started",
      cfg_.expect_uavs, geo_.region_count(), static_cast<double>(unix_ms_now() - run_t0_unix_ms_) / 1000.0);
}

bool GroundApp::uavs_done() const {
  const auto& uavs = rec_.uavs();
  if (uavs.size() < cfg_.expect_uavs && !start_sent_) return false;
  if (uavs.empty()) return false;
  return std::all_of(uavs.begin(), uavs.end(), [](const auto& kv) { return kv.second.finished || !kv.second.alive; });
}

void GroundApp::end_run() {
  ended_ = true;
  core::CommandMsg end;
  end.kind = static_cast<uint8_t>(core::CommandKind::End);
  const auto a = publish_swarm_command(end);
  if (a.status == 200) {
    log_->info("every uav finished: {}", a.message);
  } else {
    log_->error("every uav finished, but the end of the run cannot be announced: {}", a.message);
  }
}

int GroundApp::finish() {
  // Final drain: wait (bounded) for every place agent's final health so the
  // deposit accounting is complete. After an End the place agents, maybe on
  // other hosts, finish their last tick and publish it: longer.
  const auto deadline = Clock::now() + std::chrono::seconds(ended_ ? 10 : 3);
  for (;;) {
    poll();
    if (places_finished() || Clock::now() > deadline) break;
    wait_for_data(std::min(deadline, Clock::now() + std::chrono::milliseconds(20)));
  }
  rec_.judge_pending_detections();
  note_acquisitions();
  print_progress();
  if (console_) {
    // The last frame holds the final state; a replay ends with it too.
    build_frame();
    console_->close();
    const auto final_json = console::frame_json(console_->state(), console_->console_info(), 0, 0);
    std::string error;
    if (!runtime::write_json(cfg_.out_dir, "console_final.json", final_json, error)) log_->error("{}", error);
    if (server_) server_->stop();
    if (recording_) {
      // The recording appears under its name only now, complete (recording.hpp).
      if (auto closed = recording_->close(); !closed) {
        log_->error("{}", closed.error().message);
      } else {
        log_->info("recorded {} console frames ({} bytes) in {}", frames_, closed.value(), recording_->path());
      }
    }
  }
  const auto field_value = [&](int layer, core::Cell c) {
    const core::TileCoord t = geo_.tile_of(c);
    auto it = tiles_latest_.find({layer, {t.tx, t.ty}});
    if (it == tiles_latest_.end()) return std::numeric_limits<float>::quiet_NaN();
    const core::Rect r = geo_.tile_rect(t);
    return it->second.values[static_cast<std::size_t>((c.y - r.y0) * r.w + (c.x - r.x0))];
  };
  rec_.set_field_summary(core::field_summary(scenario_, field_value));
  std::string error;
  const runtime::RunInfo info{bus_->vendor(),
                              cfg_.common.clock,
                              cfg_.expect_uavs,
                              discovery_s_,
                              conductor_.phase_times().uav_ms,
                              conductor_.phase_times().place_ms};
  if (!runtime::write_json(cfg_.out_dir, "metrics.json", runtime::metrics_json(rec_, info), error)) {
    log_->error("{}", error);
    return 5;
  }
  const std::string field_path = (std::filesystem::path(cfg_.out_dir) / "final_field.txt").string();
  const bool field_ok = runtime::write_field(field_path, geo_, core::policy_traits(scenario_).layers, field_value);
  if (!field_ok) log_->error("cannot write {}", field_path);
  log_->info("wrote {}/metrics.json and final_field.txt", cfg_.out_dir);
  return 0;
}

int GroundApp::run() {
  bus_->subscribe_ground();
  bus_->subscribe_broadcasts();
  log_->info("ground station on domain {} over {} ({} clock): expecting {} uavs and {} place agents",
             cfg_.common.domain, bus_->vendor(), cfg_.common.clock, cfg_.expect_uavs, geo_.region_count());
  next_progress_ = Clock::now();
  start_console();
  bool ok = true;
  if (cfg_.common.lockstep() && !cfg_.attach) ok = conduct();
  if (cfg_.until_done && cfg_.common.lockstep()) end_run();
  while (!runtime::shutdown_requested()) {
    if (cfg_.attach) {
      note_full_state();
      if (places_finished()) {
        log_->info("every place agent finished: the run is over");
        break;
      }
    }
    if (cfg_.until_done && !ended_ && uavs_done()) {
      end_run();
      break;
    }
    if (ended_) break;
    poll();
    progress_if_due();
    service();
    if (cfg_.common.lockstep()) resend_.resend_if_quiet();  // the stop
    wait_for_data(Clock::now() + std::chrono::milliseconds(20));
  }
  const int rc = finish();
  return rc != 0 ? rc : (ok ? 0 : 6);
}

}  // namespace pheromesh::groundstation
