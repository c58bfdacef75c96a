// The relays of a place agent (docs/architecture.md, "Relays"): the lockstep
// tree (clocks down, its UAVs' reports up), its UAVs' detections and
// broadcasts up, the swarm's broadcasts and the ground station's commands
// down. Whether a sample goes on is core::PlaceIntake's judgement.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <vector>

#include "place_app.hpp"

namespace pheromesh::placeagent {

void PlaceApp::relay_uplinks() {
  relay_reports();
  // Detections and broadcasts of the UAVs it serves, up; the swarm's
  // broadcasts (its own UAVs' among them, as it relayed them to "b"), down.
  detections_up_.clear();
  bus_->take_uplink_detections(detections_up_);
  const auto now = std::chrono::steady_clock::now();
  // Only of a UAV this place agent can be the gateway of (as its states),
  // from the UAV's own process: the one that writes its states.
  for (const auto& d : detections_up_) {
    if (audit_.admit(intake_.judge_detection(d, now))) bus_->relay_detection(d);
  }
  // A broadcast goes on only if it is well formed and of a UAV of the swarm
  // (going up: from the UAV's own process).
  broadcasts_.clear();
  bus_->take_uplink_broadcasts(broadcasts_);
  for (const auto& b : broadcasts_) {
    if (audit_.admit(intake_.judge_broadcast(b, /*up=*/true, now))) bus_->relay_broadcast_up(b);
  }
  broadcasts_.clear();
  bus_->take_broadcasts(broadcasts_);
  for (const auto& b : broadcasts_) {
    if (audit_.admit(intake_.judge_broadcast(b, /*up=*/false, now))) bus_->relay_broadcast_down(b);
  }
  // The ground station's commands, as this place agent admitted them
  // (each UAV checks their signatures again).
  for (const auto& c : commands_->take()) bus_->relay_command(c);
}

void PlaceApp::relay_clock(const core::ClockMsg& c) {
  // A place clock that begins the next UAV phase: a UAV acts on its UAV
  // clock once it holds its view of this place tick, so the clock goes down
  // right after the views (relay_uav_clock_after_views): the UAV wakes once
  // for both, not for the clock and again for its view. Once this place
  // phase is done (a re-send), at once.
  if (auto uav = core::uav_clock_begun_by(c)) {
    const auto done = follower_.last_done();
    if (done && *done >= c.tick) {
      relay_one_clock(*uav);
    } else {
      uav_clock_after_views_ = std::move(uav);
    }
  }
  relay_one_clock(c);
}

const core::ClockMsg* PlaceApp::clock_for_views(uint32_t tick) {
  if (!uav_clock_after_views_ || uav_clock_after_views_->tick != tick + 1) return nullptr;
  if (!view_clock_to_) view_clock_to_ = uav_clocks_.relays(*uav_clock_after_views_);
  return view_clock_to_->home ? &*uav_clock_after_views_ : nullptr;
}

void PlaceApp::relay_uav_clock_after_views(uint32_t tick) {
  // The UAV clock of the tick after this place phase's, or an older one.
  if (!uav_clock_after_views_ || uav_clock_after_views_->tick > tick + 1) return;
  const core::ClockMsg& c = *uav_clock_after_views_;
  if (!view_clock_to_) {
    relay_one_clock(c);
  } else {
    // Decided when the views went (clock_for_views): the home UAVs whose
    // view carried it need it relayed no more.
    auto to = *view_clock_to_;
    std::sort(clocked_views_.begin(), clocked_views_.end());
    if (to.home && std::includes(clocked_views_.begin(), clocked_views_.end(), home_uavs_.begin(), home_uavs_.end())) {
      to.home = false;
      ++clocks_relayed_;
    }
    send_clock(c, to);
  }
  uav_clock_after_views_.reset();
  view_clock_to_.reset();
  clocked_views_.clear();
}

void PlaceApp::relay_one_clock(const core::ClockMsg& c) { send_clock(c, uav_clocks_.relays(c)); }

void PlaceApp::send_clock(const core::ClockMsg& c, core::UavClockRelay::To to) {
  if (!to.home && !to.backups) return;
  // A UAV needs no place phase's served UAVs (only the place agents do).
  const core::ClockMsg* out = &c;
  core::ClockMsg bare;
  if (!c.served.empty()) {
    bare = c;
    bare.served.clear();
    out = &bare;
  }
  if (to.home) bus_->relay_clock(*out, cfg_.region);
  if (to.backups) bus_->relay_clock_to_backups(*out, cfg_.region);
  clocks_relayed_ += (to.home ? 1 : 0) + (to.backups ? 1 : 0);
}

void PlaceApp::relay_reports() {
  // A report goes on as it came (the ground station checks it): the
  // conductor keys it by its UAV, and with standbys the reader takes the
  // owning replica's copy (exclusive ownership, bus/qos.hpp).
  // Only a report of a UAV it can be the gateway of, from the UAV's own
  // process (core::judge_uav_report), as its detections and broadcasts.
  reports_.clear();
  bus_->take_uav_reports(reports_);
  const auto now = std::chrono::steady_clock::now();
  for (const auto& m : reports_) {
    if (!audit_.admit(intake_.judge_report(m, now))) continue;
    bus_->publish_phase_done(m);
    ++reports_relayed_;
  }
}

void PlaceApp::relay_idle() {
  // Between phases: the states of the UAV phase under way go to the ground
  // station now (its conductor waits for them), and are this place agent's
  // for the place phase that follows. A UAV whose home the clock lists
  // absent from this tick on sends its state here already: adopt it first.
  note_absent();
  take_home_states(current_tick_, /*batch=*/true);
  relay_uplinks();
}

}  // namespace pheromesh::placeagent
