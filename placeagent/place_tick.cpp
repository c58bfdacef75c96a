// One tick of a place agent: its inputs (place_inputs.cpp), the deposits
// applied, the exchange of border rings with its neighbours, the field's
// update, and its field and its home UAVs' views (place_views.cpp). In
// lockstep every input is waited for exactly as the clock announced it, in
// stages that never wait themselves (advance_step: the lockstep loop runs
// them again as samples arrive, in the thread that received them); in
// realtime the latest received is used.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>

#include "pheromesh/runtime/await.hpp"
#include "place_app.hpp"

namespace pheromesh::placeagent {

PlaceApp::StageEnd PlaceApp::stage_end(bool held) const {
  // Realtime takes what arrived and goes on; lockstep waits for exactly what
  // the clock announced, bounded as every lockstep wait (runtime::AwaitBounds):
  // past the bound, or asked to stop, the phase goes on without it.
  if (held || !demand_) return StageEnd::Held;
  if (runtime::shutdown_requested() || std::chrono::steady_clock::now() > stage_deadline_) return StageEnd::Late;
  return StageEnd::Wait;
}

void PlaceApp::next_stage(Stage s) {
  stage_ = s;
  stage_deadline_ = std::chrono::steady_clock::now() + runtime::AwaitBounds{}.bound;
}

void PlaceApp::take_rings(uint32_t tick) {
  // Neighbour rings. Realtime: whatever arrived (a neighbour that sent
  // nothing new leaves its last ring in the halo, counted as missing).
  // Lockstep: exactly the rings of this tick; an absent neighbour's last ring
  // stays in the halo (frozen).
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
      fresh_rings_.insert(h.region);
    }
  }
}

void PlaceApp::apply_inputs(uint32_t tick) {
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
  const auto& neighbours = core_.neighbours();
  for (core::RegionId n : neighbours) {
    if (!is_absent(n)) resend_.halo(core::trim_halo(full, geo_, n), n);
  }
  fresh_rings_.clear();
  rings_awaited_ = static_cast<std::size_t>(
      std::count_if(neighbours.begin(), neighbours.end(), [&](core::RegionId n) { return !is_absent(n); }));
}

void PlaceApp::update_field(uint32_t tick) {
  halos_missing_ += rings_awaited_ - std::min(fresh_rings_.size(), rings_awaited_);
  core_.finish_tick();
  tiles_out_.clear();
  core_.tiles(tick, core::PlaceCore::TileSelection::All, tiles_out_);
  send_field_and_tiles(tick);
  // Lockstep waits for exactly these owners' tiles; realtime takes what arrived.
  tile_owners_.clear();
  if (demand_) tile_owners_ = owners_for_views();
}

void PlaceApp::begin_step(uint32_t tick, std::optional<TickDemand> demand) {
  current_tick_ = tick;
  demand_ = demand;
  next_stage(Stage::Inputs);
  resend_.begin_tick();
  inbox_.clear();
}

bool PlaceApp::advance_step() {
  // Each stage takes what the bus holds, and ends when it holds what the
  // stage needs (lockstep: exactly as the clock announced) or its bound
  // passed; until then the step returns false and is advanced again when
  // more samples may have come (runtime::LockstepLoop). Nothing here waits.
  const uint32_t tick = current_tick_;
  for (;;) {
    switch (stage_) {
      case Stage::Inputs: {
        take_home_states(tick);  // first: the states carry their UAVs' deposits
        take_deposits();
        const StageEnd e = stage_end(inputs_held(tick));
        if (e == StageEnd::Wait) return false;
        if (e == StageEnd::Late) log_inputs_late(tick);
        apply_inputs(tick);
        next_stage(Stage::Rings);
        break;
      }
      case Stage::Rings: {
        take_rings(tick);
        const StageEnd e = stage_end(fresh_rings_.size() >= rings_awaited_);
        if (e == StageEnd::Wait) return false;
        if (e == StageEnd::Late) {
          log_->error("tick {}: rings of {} of {} neighbours did not arrive", tick,
                      rings_awaited_ - std::min(rings_awaited_, fresh_rings_.size()), rings_awaited_);
        }
        update_field(tick);
        next_stage(Stage::Tiles);
        break;
      }
      case Stage::Tiles: {
        take_tiles(tick);
        const StageEnd e = stage_end(views_.holds_tiles(tick, tile_owners_));
        if (e == StageEnd::Wait) return false;
        if (e == StageEnd::Late) {
          log_->error("tick {}: the tiles of some regions did not arrive ({}); views go without them", tick,
                      views_.missing_tiles(tick, tile_owners_));
        }
        send_views(tick);
        relay_uav_clock_after_views(tick);  // lockstep: the UAV phase this place clock began
        next_stage(Stage::Done);
        return true;
      }
      case Stage::Done:
        return true;
    }
  }
}

void PlaceApp::step(uint32_t tick) {
  // Realtime: no stage waits (stage_end), so one advance is the whole tick.
  begin_step(tick, std::nullopt);
  const bool whole = advance_step();
  if (!whole) log_->error("tick {}: a realtime step waited for samples", tick);
}

}  // namespace pheromesh::placeagent
