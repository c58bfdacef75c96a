// One tick of a place agent: its inputs (place_inputs.cpp), the deposits
// applied, the exchange of border rings with its neighbours, the field's
// update, and its field and its home UAVs' views (place_views.cpp). In
// lockstep every input is waited for exactly as the clock announced it; in
// realtime the latest received is used.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <set>

#include "pheromesh/runtime/await.hpp"
#include "place_app.hpp"

namespace pheromesh::placeagent {

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
    keep_tree();  // the lockstep tree goes on while this phase waits
    halo_inbox_.clear();
    bus_->take_halos(halo_inbox_);
    const uint32_t ceiling = tick_ceiling();
    for (const auto& h : halo_inbox_) {
      // Lockstep: only this tick's, of a present neighbour (core::judge_halo).
      const auto v = core::judge_halo(h, tick, demand_.has_value(), is_absent(h.region), ceiling);
      if (!v || !audit_.admit(*v)) continue;
      const auto whole = core::expand_halo(h, geo_, cfg_.region);
      if (!whole || !core_.accept_halo(*whole)) {
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

void PlaceApp::step(uint32_t tick, std::optional<TickDemand> demand) {
  current_tick_ = tick;
  demand_ = demand;
  resend_.begin_tick();
  take_inputs(tick);
  publish_served(tick);
  events_.clear();
  rejections_.clear();
  take_served(tick);
  // Each deposit where its UAV can have put it, judged against the UAV's
  // last accepted state this place agent knows (its own home UAVs' and every
  // other region's served UAVs'; the simulator judges the same way).
  const core::PlaceCore::DepositReach reach = [&](const core::DepositMsg& d) {
    return core::check_deposit_reach(d, views_.state(d.uav), core::uav_start(scenario_, traits_, d.uav),
                                     traits_.max_step, traits_.deposit_reach);
  };
  const core::HaloRing ring = core_.begin_tick(inbox_, tick, events_, &rejections_, &reach);
  for (const auto& r : rejections_) {
    if (core_.ledger().rejected() <= 20) log_->warn("rejected deposit from {}", r);
  }
  for (const auto& e : events_) {
    bus_->publish_target_event(e);
    log_->info("target at ({},{}) {} at tick {}", e.cell.x, e.cell.y,
               core::to_string(static_cast<core::TargetEventKind>(e.kind)), tick);
  }
  // To each neighbour only the cells of the ring its diffusion reads. With
  // shared ownership each replica writes an instance of its own (keyed by
  // replica): two writers of one keep-last-1 instance let a reader's history
  // replace or drop one replica's ring by the other's (on Fast DDS 2.9 by
  // source timestamp, DataReaderHistory::received_change_keep_last), and a
  // standby then waited 30 s for a ring (docs/faults.md). The receiver takes
  // the ring of the tick from whichever replica's instance has it.
  const uint16_t halo_key = replicated_ && cfg_.common.shared_ownership ? cfg_.replica : 0;
  const core::HaloMsg full{cfg_.region, tick, ring.target, ring.obstacle, halo_key};
  for (core::RegionId n : core_.neighbours()) {
    if (!is_absent(n)) resend_.halo(core::trim_halo(full, geo_, n), n);
  }
  exchange_halos(tick);
  core_.finish_tick();
  tiles_out_.clear();
  core_.tiles(tick, core::PlaceCore::TileSelection::All, tiles_out_);
  serve_views(tick);
  relay_uav_clock_after_views(tick);  // lockstep: the UAV phase this place clock began
}

}  // namespace pheromesh::placeagent
