#include "ground_app.hpp"

#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>

#include "pheromesh/core/policy.hpp"

namespace pheromesh::groundstation {

using Clock = std::chrono::steady_clock;

namespace {

// The flags completed from the scenario.
GroundConfig settle(GroundConfig cfg, const core::ScenarioConfig& s) {
  if (cfg.expect_uavs == 0) cfg.expect_uavs = s.uavs;
  // Place agents have standby replicas (--standby, common to every process, or run.standby).
  cfg.standby = cfg.common.standby || s.standby;
  return cfg;
}

core::LockstepConductor::Options conductor_options(const GroundConfig& cfg, uint32_t regions) {
  const uint32_t replicas = cfg.standby ? 2U : 1U;
  return {cfg.expect_uavs,
          regions,
          millis(cfg.phase_timeout_s),
          millis(cfg.departed_grace_s),
          replicas - 1,
          millis(start_timeout(cfg, cfg.expect_uavs + regions * replicas))};
}

}  // namespace

double start_timeout(const GroundConfig& cfg, uint32_t processes) {
  // A flat domain's discovery grows with the square of the processes: 117
  // Fast DDS processes on a 2-core host took 153 s (docs/dds.md).
  return cfg.start_timeout_s > 0 ? cfg.start_timeout_s : 60.0 + 1.0 * processes;
}

namespace {

// The run's launch ($PHEROMESH_RUN_T0_MS, milliseconds since the Unix epoch,
// set by pheromesh run and by attach) on this process's steady clock.
std::optional<Clock::time_point> launch_from_env(Clock::time_point now) {
  const char* t0 = std::getenv("PHEROMESH_RUN_T0_MS");
  if (t0 == nullptr) return std::nullopt;
  char* end = nullptr;
  const long long v = std::strtoll(t0, &end, 10);
  if (end == t0 || *end != '\0' || v <= 0) return std::nullopt;
  const auto unix_now = std::chrono::system_clock::now().time_since_epoch();
  return now - (std::chrono::duration_cast<std::chrono::milliseconds>(unix_now) - std::chrono::milliseconds(v));
}

core::RunBook::Options book_options(const GroundConfig& cfg, const core::ScenarioConfig& s, uint32_t regions) {
  using Role = core::RunBook::Role;
  const auto now = Clock::now();
  const Role role = cfg.attach ? Role::Monitor : cfg.common.lockstep() ? Role::Conductor : Role::Starter;
  return {role, cfg.expect_uavs, regions, s.tick_rate_hz, now, launch_from_env(now), runtime::launch_slack()};
}

}  // namespace

GroundApp::GroundApp(GroundConfig cfg, core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus)
    : cfg_(settle(std::move(cfg), scenario)),
      launcher_(cfg_.launcher_fd),
      scenario_(std::move(scenario)),
      geo_(scenario_.geometry()),
      world_(geo_, scenario_.obstacles, scenario_.targets),
      bus_(std::move(bus)),
      // Only conduct() (lockstep) publishes through it. The clock goes out at
      // least every half lease: the UAVs and place agents take a long
      // silence for the conductor's death (core::ConductorWatch).
      resend_(*bus_, /*enabled=*/true,
              std::min(std::chrono::milliseconds(1000), std::chrono::milliseconds(cfg_.common.lease_ms) / 2)),
      log_(spdlog::default_logger()),
      rec_(scenario_, world_),
      frame_builder_(geo_),
      conductor_(conductor_options(cfg_, geo_.region_count())),
      book_(book_options(cfg_, scenario_, geo_.region_count())),
      intake_(scenario_, {rec_, conductor_, book_, frame_builder_, world_},
              cfg_.standby ? console::GroundIntake::Standby::Hot : console::GroundIntake::Standby::None,
              std::chrono::milliseconds(cfg_.common.lease_ms),
              cfg_.common.lockstep() ? console::GroundIntake::Pace::Lockstep : console::GroundIntake::Pace::Realtime) {
  if (cfg_.tracks) rec_.keep_tracks();
}

void GroundApp::note_discovery(Clock::time_point now) {
  using StartNow = core::RunBook::StartNow;
  const auto d = book_.note_discovery(heard(), now);
  if (d.complete_s) {
    log_->info(
        "discovery complete: every UAV ({}) and place agent ({}) heard {:.1f} s after the launch, every place agent "
        "matched to every other",
        cfg_.expect_uavs, geo_.region_count(), *d.complete_s);
  }
  if (d.start == StartNow::No) return;
  if (d.start == StartNow::WithoutSomeAfterBound) {
    log_->warn(
        "starting the swarm without {} of {} UAVs and {} of {} place agents, not heard within {} s{}", d.uavs_missing,
        cfg_.expect_uavs, d.regions_missing, geo_.region_count(), book_.start_bound().count() / 1000,
        d.regions_unlinked == 0
            ? std::string()
            : fmt::format("; {} place agents heard have not matched every other region's, and deposits they forward "
                          "there are rejected until they do",
                          d.regions_unlinked));
  }
  core::CommandMsg start;
  start.kind = static_cast<uint8_t>(core::CommandKind::Start);
  const auto a = publish_swarm_command(start);
  if (a.status == 200) {
    log_->info("{}", a.message);
    // The launcher measures the steady flight from here (metrics.json "steady").
    if (launcher_.connected()) (void)launcher_.ask("started");
  } else {
    log_->warn("cannot start the swarm: {}", a.message);
  }
}

void GroundApp::poll() {
  // The ceiling of what a realtime tick may be is read after the take: a
  // take on a busy host can last seconds, and a `now` from before it judged
  // samples written meanwhile against an old ceiling (tick_far_ahead).
  take_samples();
  const auto now = Clock::now();
  log_notes(intake_.take(samples_, book_.tick_ceiling(now), now));
  note_discovery(now);
}

void GroundApp::take_samples() {
  samples_.clear();
  bus_->take_uav_states(samples_.states);
  bus_->take_broadcasts(samples_.broadcasts);
  bus_->take_departed_uavs(samples_.departed_uavs);
  bus_->take_detections(samples_.detections);
  bus_->take_target_events(samples_.target_events);
  bus_->take_health(samples_.healths);
  bus_->take_tiles(samples_.tiles);
  bus_->take_fields(samples_.fields);
  bus_->take_departed_regions(samples_.departed_places);
  bus_->take_phase_done(samples_.phase_dones);
}

void GroundApp::log_notes(const console::GroundIntake::Notes& notes) {
  for (const auto& n : notes) {
    if (mavlink_feed_) mavlink_feed_->note(n);
    log_->log(n.level == console::IntakeNote::Level::Warn ? spdlog::level::warn : spdlog::level::info, "{}", n.text);
  }
}

void GroundApp::print_progress() {
  uint32_t flying = 0;
  for (const auto& [id, u] : rec_.uavs()) flying += (u.alive && !u.finished) ? 1 : 0;
  uint64_t applied = 0, rejected = 0;
  for (const auto& [r, h] : rec_.health()) {
    applied += h.deposits_applied;
    rejected += h.deposits_rejected;
  }
  uint32_t standby_owned = 0;
  for (core::RegionId r = 0; r < geo_.region_count(); ++r) {
    const auto owner = rec_.region_owner(r);
    standby_owned += owner && *owner > 0 ? 1 : 0;
  }
  log_->info(
      "tick {:5d} | uavs {}/{} flying | places {}/{}{} | coverage {:5.1f}% | targets {}/{} | deposits sent {} applied "
      "{} "
      "rejected {} unaccounted {}",
      rec_.max_tick(), flying, cfg_.expect_uavs, rec_.regions_alive(), geo_.region_count(),
      standby_owned > 0 ? fmt::format(" ({} on standby)", standby_owned) : std::string(),
      100.0 * rec_.coverage().coverage(), rec_.acquisitions().found(), world_.targets().size(), rec_.deposits_sent(),
      applied, rejected, rec_.deposits_lost());
}

void GroundApp::progress_if_due() {
  if (Clock::now() < next_progress_) return;
  print_progress();
  next_progress_ += millis(cfg_.progress_period_s);
}

void GroundApp::wait_for_data(Clock::time_point until) {
  using K = bus::TopicKind;
  // The UAVs' states come relayed by their gateways (GroundState): a lockstep
  // UAV phase is complete when the last of them or of their reports is here.
  bus_->wait({K::UavState, K::GroundState, K::Field, K::Tile, K::Detection, K::TargetEvent, K::Health, K::Broadcast,
              K::PhaseDone},
             until);
}

core::RunBook::Heard GroundApp::heard() const { return {frame_builder_.uavs_heard(), frame_builder_.regions_heard()}; }

void GroundApp::note_full_state() {
  if (const auto shown_s = book_.note_full_state(heard(), Clock::now())) {
    log_->info(
        "attached: the whole swarm is shown (every uav of {}, every place agent of {}, every region's field) {:.2f} s "
        "after the monitor started",
        cfg_.expect_uavs, geo_.region_count(), *shown_s);
  }
}

bool GroundApp::end_if_over() {
  if (cfg_.attach && book_.places_finished(rec_)) {
    log_->info("every place agent finished: the run is over");
    return true;
  }
  if (cfg_.attach) {
    if (const auto never_heard = intake_.heard_places_over(Clock::now())) {
      log_->warn(
          "every place agent heard has finished and none other was heard for 5 s: the run is over; never heard "
          "region(s) {} (they ended before this monitor found them)",
          fmt::join(*never_heard, ", "));
      return true;
    }
  }
  if (cfg_.until_done && !ended_ && book_.uavs_done(rec_, conductor_, Clock::now())) end_run();
  return ended_;
}

int GroundApp::run() {
  bus_->subscribe_ground();
  bus_->subscribe_broadcasts();
  log_->info("ground station on domain {} over {} ({} clock): expecting {} uavs and {} place agents",
             cfg_.common.domain, bus_->vendor(), cfg_.common.clock, cfg_.expect_uavs, geo_.region_count());
  next_progress_ = Clock::now();
  start_console();
  start_mavlink();
  bool ok = true;
  if (cfg_.common.lockstep() && !cfg_.attach) ok = conduct();
  if (cfg_.until_done && cfg_.common.lockstep()) end_run();
  while (!runtime::shutdown_requested()) {
    if (cfg_.attach) note_full_state();
    if (end_if_over()) break;
    poll();
    progress_if_due();
    service();
    if (cfg_.common.lockstep()) resend_.resend_if_quiet();  // the stop
    wait_for_data(Clock::now() + std::chrono::milliseconds(20));
  }
  const int rc = finish();
  return rc != 0 ? rc : (ok || interrupted_ ? 0 : 6);
}

}  // namespace pheromesh::groundstation
