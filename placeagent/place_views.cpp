// A place agent's views: the home UAVs it serves this tick, to every other
// place agent; the tiles of this region their UAVs' views need, to each of
// them; the tiles its own UAVs' views need, from each owner; and the views
// (core::ViewServer composes them and joins the tiles). Lockstep: exactly
// this tick's; realtime: the latest received.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>

#include "place_app.hpp"

namespace pheromesh::placeagent {

namespace {
// Realtime: a home UAV not heard for this many place ticks gets no more
// views (it died or finished); in lockstep every view is sent.
constexpr uint32_t kViewsAfterSilence = 20;
// Realtime: neighbour states at most this many ticks older than the UAV's
// own go into its view (UavCore keeps the same window).
constexpr uint32_t kNeighbourAge = 4;
}  // namespace

void PlaceApp::publish_served(uint32_t tick) {
  // The home UAVs that get a view this tick and where they are, to every
  // other place agent: each owner sends back the tiles their views need.
  // Lockstep: those that took part in this tick's UAV phase, of those the
  // place clock lists as this region's (every owner sends tiles for that
  // list), and nothing is sent: the clock told every place agent.
  served_.clear();
  served_states_.clear();
  const bool from_clock = demand_ && demand_->served != nullptr;
  listed_.clear();
  if (from_clock) {
    for (const auto& s : *demand_->served) {
      if (s.region == cfg_.region) listed_.push_back(s.uav);
    }
    std::sort(listed_.begin(), listed_.end());
  }
  for (uint32_t u : gateway_uavs_) {
    const core::UavStateMsg* st = views_.state(u);
    if (st == nullptr || st->finished) continue;
    if (demand_ ? st->tick != tick : tick - heard_at_[u] > kViewsAfterSilence) continue;
    // Its newest state was refused: it gets an empty view (send_views), not
    // one around a position it has left.
    if (const auto refused = intake_.refused_tick(u); refused && *refused > st->tick) continue;
    if (from_clock && !std::binary_search(listed_.begin(), listed_.end(), u)) {
      log_->warn("tick {}: uav {} is not among the UAVs the clock lists for this region; it gets no view", tick, u);
      continue;
    }
    served_.push_back(u);
    served_states_.push_back(*st);
  }
  if (from_clock) return;
  for (auto& f : core::make_field_chunks(cfg_.region, tick, {}, served_states_)) {
    f.replica = cfg_.replica;
    resend_.served(f);
  }
}

void PlaceApp::take_served(uint32_t tick) {
  // Which UAVs every other place agent serves and where they are: exactly
  // this tick's (lockstep: as the place clock lists them). Before the
  // deposits are applied: they are judged against these positions
  // (deposit_reach).
  if (demand_ && demand_->served != nullptr) {
    if (served_listed_ == tick) return;
    served_listed_ = tick;
    malformed_.clear();
    views_.update_served(*demand_->served, tick, present_others_, scenario_.uavs, malformed_);
    for (auto& why : malformed_) (void)audit_.admit(core::IntakeVerdict::drop("the place clock's " + why));
    return;
  }
  // Realtime: the chunks that came since the last tick.
  field_inbox_.clear();
  bus_->take_served(field_inbox_);
  const uint32_t ceiling = tick_ceiling();
  const auto now = std::chrono::steady_clock::now();
  for (const auto& f : field_inbox_) {
    if (f.region == cfg_.region || !audit_.admit(core::check_field_chunk(f, ceiling, rules_))) continue;
    // What only that place agent writes, judged by who wrote it; it
    // vouches for its process as a forwarder of deposits (judge_forwarded).
    if (audit_.admit(intake_.judge_served_chunk(f, now))) views_.update_served(f, tick);
  }
}

void PlaceApp::send_tiles(uint32_t tick) {
  take_served(tick);  // held since before the deposits were applied (step); realtime: what came since
  // To each of them the tiles of this region their UAVs' views need, and
  // nothing else (the tile join, core::ViewServer::tiles_for). Realtime: not
  // to a place agent not heard of lately (it died: its views are no one's).
  const uint32_t heard_since = demand_ || tick < tiles_stale_after_ ? 0 : tick - tiles_stale_after_;
  for (core::RegionId home : present_others_) {
    tiles_for_.clear();
    views_.tiles_for(home, heard_since, tile_margin(), tiles_out_, tiles_for_);
    if (tiles_for_.empty()) continue;
    for (auto& f : core::make_field_chunks(cfg_.region, tick, tiles_for_, {})) {
      f.replica = cfg_.replica;
      resend_.tiles_for(f, home);
    }
  }
}

std::vector<core::RegionId> PlaceApp::owners_for_views() const {
  // The other present regions whose tiles the served UAVs' views need: they
  // send them (send_tiles above, from the same served states).
  std::vector<core::RegionId> owners = views_.owners_for(served_, tile_margin(), cfg_.region);
  std::erase_if(owners, [&](core::RegionId r) { return is_absent(r); });
  return owners;
}

void PlaceApp::take_tiles(uint32_t tick) {
  // The tiles its served UAVs' views need from the other regions (lockstep:
  // of this tick, from exactly tile_owners_; realtime: what arrived).
  field_inbox_.clear();
  bus_->take_tiles_for_views(field_inbox_);
  const uint32_t ceiling = tick_ceiling();
  for (const auto& f : field_inbox_) {
    if (f.region == cfg_.region || !audit_.admit(core::check_field_chunk(f, ceiling, rules_))) continue;
    // Lockstep shows a tile of this tick only; realtime one that arrived lately.
    views_.update_tiles(f, demand_ ? f.tick : tick);
  }
}

void PlaceApp::send_field_and_tiles(uint32_t tick) {
  for (const auto& t : tiles_out_) views_.update_tile(t, tick);
  // This region's field (core::FieldToGround: lockstep all of it every tick,
  // realtime what changed at the console's rate) and its home UAVs' latest
  // states, to the ground station.
  if (to_ground_.due(tick, last_tick_)) {
    home_states_.clear();
    for (uint32_t u : gateway_uavs_) {
      if (const core::UavStateMsg* st = views_.state(u)) home_states_.push_back(*st);
    }
    ground_tiles_.clear();
    to_ground_.select(tiles_out_, last_tick_, ground_tiles_);
    for (auto& f : core::make_field_chunks(cfg_.region, tick, ground_tiles_, home_states_)) {
      f.replica = cfg_.replica;
      resend_.field(f);
    }
  }
  send_tiles(tick);
}

void PlaceApp::send_views(uint32_t tick) {
  // Lockstep: tiles of this tick only; realtime: tiles an owner sent lately
  // (a dead owner's region goes dark after that).
  const uint32_t min_tile_tick = demand_ ? tick : (tick > tiles_stale_after_ ? tick - tiles_stale_after_ : 0);
  // Lockstep: a home UAV's view carries the UAV clock this place clock
  // began, so that it wakes once for both (relay_uav_clock_after_views
  // relays it to those whose view did not).
  const core::ClockMsg* clock = clock_for_views(tick);
  clocked_views_.clear();
  const auto carry_clock = [&](uint32_t u) {
    view_.clock.reset();
    if (clock == nullptr || !std::binary_search(home_uavs_.begin(), home_uavs_.end(), u)) return;
    view_.clock = *clock;
    clocked_views_.push_back(u);
  };
  for (uint32_t u : served_) {
    if (views_.compose(u, tick, demand_ ? 0 : kNeighbourAge, min_tile_tick, view_)) {
      view_.deposit_ack = desk_.ack(u);
      view_.deposit_ack_from = desk_.ack_from(u);
      carry_clock(u);
      resend_.view(view_);
    }
  }
  // A UAV whose state was refused gets an empty view of this tick: no tile
  // and no neighbour around a position its gateway does not believe, and in
  // lockstep the answer it waits for (the simulator does the same).
  for (uint32_t u : refused_views_) {
    view_.uav = u;
    view_.tick = tick;
    view_.tiles.clear();
    view_.uavs.clear();
    view_.deposit_ack = desk_.ack(u);
    view_.deposit_ack_from = desk_.ack_from(u);
    carry_clock(u);
    resend_.view(view_);
  }
  refused_views_.clear();
  view_.clock.reset();
}

}  // namespace pheromesh::placeagent
