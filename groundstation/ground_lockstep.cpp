// The ground station as the lockstep conductor (docs/architecture.md, "Time"):
// publishes the clocks core::LockstepConductor returns, waits (bounded) for
// each phase, and asks the launcher for the faults of a tick.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <future>
#include <string>

#include "ground_app.hpp"

namespace pheromesh::groundstation {

using Clock = std::chrono::steady_clock;

namespace {

const char* phase_name(core::ClockPhase phase) {
  switch (phase) {
    case core::ClockPhase::Uav:
      return "uav";
    case core::ClockPhase::Place:
      return "place";
    default:
      return "ready";
  }
}

// "uav 3, 7; place 2", the first few of each.
std::string not_ready_list(const core::LockstepConductor::Status& st) {
  const auto ids = [](const char* role, const std::vector<uint32_t>& v) {
    if (v.empty()) return std::string();
    std::string s = role;
    for (std::size_t i = 0; i < v.size() && i < 10; ++i) s += (i == 0 ? " " : ", ") + std::to_string(v[i]);
    return v.size() > 10 ? s + fmt::format(" and {} more", v.size() - 10) : s;
  };
  const std::string u = ids("uav", st.uavs_not_ready), p = ids("place", st.regions_not_ready);
  return u.empty() ? p : p.empty() ? u : u + "; " + p;
}

}  // namespace

bool GroundApp::conduct() {
  bus_->subscribe_phase_done();
  const uint32_t ticks = scenario_.ticks;
  log_->info("conducting {} lockstep ticks", ticks);
  // Tick 0 waits until every process matched what it deposits to.
  bool ok = run_phase(0, core::ClockPhase::Ready);
  bool uav_phase_run = false;  // the UAV phase of k ran with the place phase of k-1
  for (uint32_t k = 0; k <= ticks && ok && !runtime::shutdown_requested(); ++k) {
    if (!uav_phase_run) {
      hold_while_paused();
      if (std::find(cfg_.fault_ticks.begin(), cfg_.fault_ticks.end(), k) != cfg_.fault_ticks.end()) {
        ok = apply_faults(k);
      }
      ok = ok && run_phase(k, core::ClockPhase::Uav);
    }
    uav_phase_run = fuses_after(k, ticks);
    ok = ok && run_phase(k, core::ClockPhase::Place, uav_phase_run);
    progress_if_due();
    service();
  }
  if (ok && runtime::shutdown_requested() && !interrupted_) {
    log_->warn("lockstep: interrupted between two phases; stopping");
    interrupted_ = true;
  }
  // Before the place agents are let go.
  ok = ok && await_last_fields(ticks);
  // Stop: re-sent like every clock (run() keeps the re-sender going), not
  // flushed - a killed process's reader would never acknowledge it.
  resend_.begin_tick();
  resend_.clock(core::LockstepConductor::stop(ticks));
  if (conductor_.deposits_lost() > 0) {
    log_->info("{} deposits were lost with the place agents killed at a tick", conductor_.deposits_lost());
  }
  return ok;
}

void GroundApp::hold_while_paused() {
  while (paused_ && !runtime::shutdown_requested()) {
    poll();
    service();
    resend_.resend_if_quiet();
    wait_for_data(Clock::now() + std::chrono::milliseconds(10));
  }
}

bool GroundApp::await_last_fields(uint32_t ticks) {
  const auto deadline = Clock::now() + millis(cfg_.phase_timeout_s);
  while (!book_.holds_last_fields(ticks, conductor_) && !runtime::shutdown_requested()) {
    if (Clock::now() > deadline) {
      log_->error("the fields of the last tick {} did not all reach the ground station within {} s", ticks,
                  cfg_.phase_timeout_s);
      return false;
    }
    poll();
    resend_.resend_if_quiet();
    wait_for_data(Clock::now() + std::chrono::milliseconds(20));
  }
  return true;
}

bool GroundApp::fuses_after(uint32_t tick, uint32_t ticks) const {
  // Not after the last tick, not before a tick with faults (the launcher
  // kills before its UAV phase), not while paused (the pause holds before a
  // UAV phase), and never with standbys (the conductor would not).
  const uint32_t next = tick + 1;
  return next <= ticks && !cfg_.standby && !paused_ &&
         std::find(cfg_.fault_ticks.begin(), cfg_.fault_ticks.end(), next) == cfg_.fault_ticks.end();
}

bool GroundApp::run_phase(uint32_t tick, core::ClockPhase phase, bool next_uav_phase) {
  book_.note_conducted(tick);
  poll();
  resend_.begin_tick();
  const auto t0 = Clock::now();
  resend_.clock(conductor_.begin_phase(tick, phase, t0, next_uav_phase));
  for (;;) {
    poll();
    const auto st = conductor_.status(Clock::now());
    // A fused place phase goes on as the next tick's UAV phase.
    if (conductor_.tick() != tick) book_.note_conducted(conductor_.tick());
    tick = conductor_.tick();
    phase = conductor_.phase();
    if (st.complete) {
      log_->debug("lockstep tick {} {} phase: {} ms", tick, phase_name(phase),
                  std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0).count());
      return true;
    }
    if (st.timed_out && phase == core::ClockPhase::Ready) {
      // Lockstep without them would neither be the run asked for nor equal
      // the simulator: refuse, and say who and what to do.
      log_->error(
          "lockstep: {} of {} processes did not report ready within {:.0f} s ({}); not starting a run that would "
          "differ from the one asked for. The host may not hold this many processes in one domain (pheromesh bench "
          "scale), or discovery needs longer (pheromesh run --start-timeout)",
          st.waiting, cfg_.expect_uavs + geo_.region_count(),
          start_timeout(cfg_, cfg_.expect_uavs + geo_.region_count() * (cfg_.standby ? 2 : 1)), not_ready_list(st));
      return false;
    }
    if (runtime::shutdown_requested()) {
      // Stopped (Ctrl-C, the launcher's stop): not a failure of the run's
      // processes, so not exit 6; the launcher reports the interruption.
      log_->warn("lockstep tick {} {} phase: interrupted while waiting for {} process(es); stopping", tick,
                 phase_name(phase), st.waiting);
      interrupted_ = true;
      return false;
    }
    if (st.timed_out) {
      log_->error("lockstep tick {} {} phase: {} process(es) did not finish within {} s ({})", tick,
                  phase == core::ClockPhase::Uav ? "uav" : "place", st.waiting, cfg_.phase_timeout_s,
                  not_ready_list(st));
      return false;
    }
    progress_if_due();
    service();
    if (resend_.resend_if_quiet()) log_->debug("lockstep tick {}: nothing new for 1 s; re-sent the clock", tick);
    wait_for_data(Clock::now() + std::chrono::milliseconds(20));
  }
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
    conductor_.on_place_killed(core::place_id(r, 0));
    rec_.on_place_killed(/*region_frozen=*/false);
    return;
  }
  if (conductor_.drop_region(r)) {
    rec_.on_place_killed(/*region_frozen=*/true);
    log_->warn(
        "lockstep tick {}: place agent {} was killed without a standby; region {} is absent from now on (its field "
        "frozen, deposits into it lost, its UAVs served by their backup gateway, region {})",
        tick, r, r, (r + 1) % geo_.region_count());
  }
}

console::ConsoleSource::Answer GroundApp::ask_faults(uint32_t tick) {
  // The launcher kills and reaps the processes of this tick before it
  // answers. Meanwhile the clock keeps going out (re-sent), so nobody takes
  // the wait for the conductor's death.
  const console::LauncherLink link(cfg_.launcher_fd, millis(cfg_.faults_timeout_s));
  auto answer = std::async(std::launch::async, [&] { return link.ask("faults " + std::to_string(tick)); });
  while (answer.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
    poll();
    progress_if_due();
    resend_.resend_if_quiet();
    wait_for_data(Clock::now() + std::chrono::milliseconds(20));
  }
  return answer.get();
}

void GroundApp::await_health_before_kills(uint32_t tick) {
  // A place agent publishes its health of a tick just before its PhaseDone,
  // without waiting for it to be delivered (place_app.cpp). Killed right
  // after, it could take its last records with it, and the counts of the
  // deposits it applied would be short of the simulator's by chance. So
  // before the launcher kills anyone at `tick`, every live place agent's
  // health of the tick before is here (the records are reliable: they come).
  if (tick == 0) return;
  const auto deadline = Clock::now() + millis(cfg_.phase_timeout_s);
  auto missing = intake_.places_without_health_of(tick - 1);
  while (!missing.empty() && !runtime::shutdown_requested()) {
    if (Clock::now() > deadline) {
      log_->warn(
          "lockstep tick {}: the health of tick {} of {} place agent(s) (first: region {}) did not arrive within {} s; "
          "if one of them is killed now, the deposits it applied last are counted lost",
          tick, tick - 1, missing.size(), core::place_id_region(missing.front()), cfg_.phase_timeout_s);
      return;
    }
    poll();
    resend_.resend_if_quiet();
    wait_for_data(Clock::now() + std::chrono::milliseconds(10));
    missing = intake_.places_without_health_of(tick - 1);
  }
}

bool GroundApp::apply_faults(uint32_t tick) {
  if (cfg_.launcher_fd < 0) {
    log_->error("lockstep tick {} has faults (--fault-ticks) but there is no launcher to inject them (--launcher-fd)",
                tick);
    return false;
  }
  await_health_before_kills(tick);
  const auto a = ask_faults(tick);
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
    log_->warn("lockstep tick {}: standby {} of region {} was killed", tick, core::place_id_replica(p),
               core::place_id_region(p));
    conductor_.on_place_killed(p);
  }
  return true;
}

}  // namespace pheromesh::groundstation
