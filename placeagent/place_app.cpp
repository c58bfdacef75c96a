#include "place_app.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace pheromesh::placeagent {

using Clock = std::chrono::steady_clock;

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
      views_(geo_, static_cast<int>(traits_.layers.size()), traits_.view_radius, traits_.reads_neighbours),
      rules_{geo_, core_.layer_count(), traits_.layer_ranges, scenario_.uavs},
      desk_(cfg_.region, geo_.region_count(), scenario_.uavs,
            cfg_.common.standby || scenario_.standby || cfg_.common.lockstep()),
      intake_({cfg_.region,
               {scenario_.uavs, geo_.region_count(), core::replicas_of(cfg_.common.standby || scenario_.standby)},
               cfg_.common.lockstep(),
               std::chrono::milliseconds(cfg_.common.lease_ms) * (cfg_.common.lockstep() ? 6 : 1),
               // A place agent writes its served UAVs every tick: silent for a lease, it is dead.
               std::max<core::PlaceVouch::Clock::duration>(std::chrono::seconds(1),
                                                           std::chrono::milliseconds(cfg_.common.lease_ms))}) {
  for (uint32_t u = 0; u < scenario_.uavs; ++u) {
    if (core::home_region(u, geo_.region_count()) == cfg_.region) {
      home_uavs_.push_back(u);
    } else if (core::backup_region(u, geo_.region_count()) == cfg_.region) {
      backed_up_.push_back(u);
    }
  }
  gateway_uavs_ = home_uavs_;
  for (core::RegionId r = 0; r < geo_.region_count(); ++r) {
    if (r != cfg_.region) other_regions_.push_back(r);
  }
  replicated_ = cfg_.common.standby || scenario_.standby;
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
    for (uint32_t u : backed_up_) {
      if (core::home_region(u, geo_.region_count()) == r) adopt(u, views_.state(u));
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

}  // namespace pheromesh::placeagent
