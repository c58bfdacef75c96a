// One tick of a UAV: what it receives (its view and the broadcasts, checked
// by core/intake.hpp), the lockstep wait for exactly the view and the
// broadcasts of the tick before, and the step itself: decide, move,
// deposit through its home place agent, publish its state.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>

#include "pheromesh/runtime/await.hpp"
#include "pheromesh/runtime/lockstep_loop.hpp"
#include "uav_app.hpp"

namespace pheromesh::agent {

void UavApp::receive() {
  view_inbox_.clear();
  bus_->take_views(view_inbox_);
  samples_received_ += view_inbox_.size();
  const core::IntakeRules rules{geo_, layers_, layer_ranges_, scenario_.uavs};
  const uint32_t ceiling = tick_ceiling();
  for (const auto& v : view_inbox_) {
    if (!audit_.admit(core::check_view(v, cfg_.id, ceiling, rules))) continue;
    home_watch_.heard(std::chrono::steady_clock::now());
    receipts_.confirmed(v.deposit_ack_from, v.deposit_ack);
    if (view_tick_ && v.tick <= *view_tick_) continue;  // an older view, or a copy re-sent
    view_tick_ = v.tick;
    core_.begin_view();
    tile_samples_received_ += v.tiles.size();
    for (const auto& t : v.tiles) {
      if (audit_.admit(core::check_view_tile(t, rules))) core_.receive_tile(t);
    }
    for (const auto& st : v.uavs) {
      if (audit_.admit(core::check_neighbour(st, rules))) core_.receive_neighbour(st);
    }
  }
  broadcast_inbox_.clear();
  bus_->take_broadcasts(broadcast_inbox_);
  samples_received_ += broadcast_inbox_.size();
  for (const auto& b : broadcast_inbox_) {
    if (audit_.admit(core::check_broadcast_from(b, rules))) core_.receive_broadcast(b);
  }
}

void UavApp::wait_for_tick(uint32_t tick, const core::ClockMsg& announced) {
  // The view of place tick `tick` comes from the UAV's gateway then (its
  // home, else its backup); with neither alive, none comes (core/faults.hpp).
  const bool blind = !gateway_at(tick);
  const auto view = [&] { return blind || (view_tick_ && *view_tick_ >= tick); };
  const auto broadcasts = [&] { return core_.holds_tick(tick, {}, announced.broadcasts); };
  // The last PhaseDone goes out again after a quiet second: the conductor
  // takes it as a sign of life while this UAV waits.
  const auto r = runtime::await_samples(
      *bus_, {bus::TopicKind::View, bus::TopicKind::Broadcast}, {}, &resend_, [&] { receive(); },
      [&] { return !runtime::take_clock(*bus_, follower_, audit_) || (view() && broadcasts()); });
  if (r == runtime::Awaited::Done) return;  // or the conductor is gone: run_lockstep says so and ends
  log_->error("tick {}: {}{} did not arrive; deciding without", tick, view() ? "" : "the view of the neighbourhood",
              broadcasts() ? "" : (view() ? "the announced broadcasts" : " and the announced broadcasts"));
}

bool UavApp::ready_for(const core::ClockMsg& c) {
  if (gateway_at(c.tick) != gateway_) return false;
  if (c.tick == 0) return true;
  receive();
  // As wait_for_tick waits for the view and the broadcasts of tick - 1.
  const uint32_t tick = c.tick - 1;
  const bool view = !gateway_at(tick) || (view_tick_ && *view_tick_ >= tick);
  return view && core_.holds_tick(tick, {}, c.broadcasts);
}

void UavApp::step(uint32_t tick, StepKind kind) {
  const bool finished = kind == StepKind::Finish;
  written_.clear();
  broadcast_written_ = false;
  uplink_.clear();
  if (!finished) {
    core_.step(tick, out_);
    // The deposits go up in this tick's state (UavStateMsg::deposits): one
    // sample to the gateway, not one per deposit.
    // A deposit written while no place agent of its gateway is matched
    // would be lost silently; it is counted undeliverable instead of sent.
    const bool reachable = gateway_ && bus_->matched_state_readers() > 0;
    for (const auto& d : out_.deposits) {
      if (!gateway_) {
        // Lockstep, home and backup killed without a standby
        // (core/faults.hpp): the deposit is made and lost on the way; the
        // conductor counts it lost.
        ++deposits_sent_;
        ++written_[d.region];
      } else if (reachable) {
        uplink_.push_back(d);
      } else {
        ++deposits_undeliverable_;
      }
    }
    for (const auto& d : out_.detections) bus_->publish_detection(d);
    if (out_.broadcast) broadcast_written_ = bus_->publish_broadcast(*out_.broadcast);
  }
  core::UavStateMsg s = core_.last_state();
  if (!finished) {
    log_->debug("tick {} at ({:.9g}, {:.9g}) v ({:.9g}, {:.9g}) role {}: saw {} neighbours, {} broadcasts, {} tiles",
                tick, s.x, s.y, s.vx, s.vy, s.role, core_.last_view_neighbours(), core_.last_view_broadcasts(),
                core_.neighbourhood().size());
  }
  s.tile_samples_received = tile_samples_received_;
  s.ticks_late = ticks_late_;
  s.tick_gap_max_ms = gaps_.max_gap_ms();
  s.tick_gaps_over_2 = gaps_.gaps_over_2();
  s.samples_received = samples_received_;
  s.finished = finished;
  s.deposits_unconfirmed = receipts_.unconfirmed() + deposits_undeliverable_;
  s.view = core_.cell();  // the home place agent composes the next view around it
  s.refused = audit_.refused().n;
  if (cfg_.common.lockstep() && !finished) {
    // Its answer for the UAV phase, which its gateway reports for it once
    // it holds the whole uplink (core::UplinkReports).
    s.tick_deposits = static_cast<uint32_t>(uplink_.size());
    s.broadcasts = broadcast_written_ ? 1 : 0;
  }
  // deposits_sent counts the deposits this state carries (a place agent
  // holds every deposit of the tick once it holds the tick's last sample).
  s.deposits_sent = deposits_sent_ + uplink_.size();
  for (const auto& sample : core::uplink_samples(s, uplink_)) {
    // Lockstep: re-sent after a quiet spell. A sample whose write failed
    // leaves its deposits undeliverable.
    if (resend_.uav_state(sample)) {
      for (const auto& d : sample.deposits) {
        ++deposits_sent_;
        ++written_[d.region];
        receipts_.sent(d.seq);
      }
    } else {
      deposits_undeliverable_ += sample.deposits.size();
    }
  }
}

void UavApp::wait_for_receipts(std::chrono::milliseconds bound) {
  (void)runtime::await_samples(
      *bus_, {bus::TopicKind::View}, {bound, std::chrono::milliseconds(50)}, nullptr, [&] { receive(); },
      [&] { return receipts_.pending() == 0; });
}

}  // namespace pheromesh::agent
