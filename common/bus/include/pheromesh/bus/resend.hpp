// Lockstep re-sending of latest-value samples.
//
// Every lockstep phase waits for exact samples of one tick: the fields and
// halos of the other regions, a UAV's view, the conductor's clock, every
// process's PhaseDone. Each travels on a reliable keep-last-1 topic, so one
// sample that the vendor accepts and acknowledges but never hands to the
// reader stalls the whole swarm until a 30 s bound (measured on Fast DDS 2.9:
// a region field acknowledged by the reader's RTPS layer, never returned by
// take_next_sample until the writer's next sample replaced it; docs/dds.md
// "Lockstep re-sending"). A process that has published its samples of the
// tick and then heard nothing new for a while writes them again: the copy is
// a new sample of the same instance and content, which the readers take like
// the first (each of these readers is idempotent per tick), so the run's
// numbers do not change. Broadcasts are not re-sent: they are counted, not
// replaced. Deposits a place agent forwards and a UAV's states (which carry
// its deposits) are re-sent too: lockstep place agents drop a deposit they
// have seen (by UAV and sequence number, core::DepositDesk) and take a UAV's
// state of a tick once. No lockstep writer waits for acknowledgements, so a deposit or
// state whose packet was lost comes again with the writer's next heartbeat
// only, which Cyclone sends ever more rarely while the writer writes nothing
// new (measured: a run under 30 % loss waited 30 s for one deposit); with
// standbys a deposit a replica missed (measured: a Fast DDS UAV's first
// deposit never reached a Cyclone standby that matched it late) would split
// the replicas.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/core/messages.hpp"

namespace pheromesh::bus {

class LatestResender {
 public:
  using Clock = std::chrono::steady_clock;
  // Where it reads the time: the steady clock, or a test's own.
  using Now = std::function<Clock::time_point()>;

  // Disabled (realtime: new samples follow every tick anyway), it only publishes.
  LatestResender(Bus& bus, bool enabled, std::chrono::milliseconds quiet = std::chrono::milliseconds(1000),
                 Now now = &Clock::now)
      : bus_(bus), enabled_(enabled), quiet_(quiet), now_(std::move(now)), last_(now_()) {}

  // A new tick: the samples remembered so far are no longer re-sent.
  void begin_tick() {
    fields_.clear();
    views_.clear();
    halos_.clear();
    clock_.reset();
    done_.reset();
    states_.clear();
    deposits_.clear();
  }
  // Re-send deposits too (lockstep processes whose readers drop copies: see above).
  void resend_deposits(bool on) { deposits_on_ = on; }
  bool deposits(const core::DepositBatchMsg& m, core::RegionId via) {
    const bool ok = bus_.publish_deposits(m, via);
    if (enabled_ && deposits_on_) {
      deposits_.emplace_back(m, via);
      last_ = now_();
    }
    return ok;
  }

  // Publish and remember (the result is that of the bus's publish).
  bool field(const core::FieldMsg& m) { return keep_field(m, FieldTo::Ground, 0, bus_.publish_field(m)); }
  bool served(const core::FieldMsg& m) { return keep_field(m, FieldTo::Places, 0, bus_.publish_served(m)); }
  bool tiles_for(const core::FieldMsg& m, core::RegionId home) {
    return keep_field(m, FieldTo::Home, home, bus_.publish_tiles_for(m, home));
  }
  bool view(const core::ViewMsg& m) { return remember(views_, m, bus_.publish_view(m)); }
  bool halo(const core::HaloMsg& m, core::RegionId to) {
    const bool ok = bus_.publish_halo(m, to);
    if (enabled_) {
      halos_.emplace_back(m, to);
      last_ = now_();
    }
    return ok;
  }
  bool clock(const core::ClockMsg& m) { return remember(clock_, m, bus_.publish_clock(m)); }
  bool phase_done(const core::PhaseDoneMsg& m) { return remember(done_, m, bus_.publish_phase_done(m)); }
  // Every state sample of the tick: each carries some of its deposits
  // (core::uplink_samples).
  bool uav_state(const core::UavStateMsg& m) { return remember(states_, m, bus_.publish_uav_state(m)); }

  // Call from every wait loop: when nothing was published or re-sent for the
  // quiet period, publishes every remembered sample again. True if it did.
  bool resend_if_quiet() {
    const auto now = now_();
    if (now - last_ < quiet_ ||
        (fields_.empty() && views_.empty() && halos_.empty() && !clock_ && !done_ && states_.empty() &&
         deposits_.empty())) {
      return false;
    }
    for (const auto& [m, via] : deposits_) bus_.publish_deposits(m, via);
    for (const auto& f : fields_) publish(f);
    for (const auto& m : views_) bus_.publish_view(m);
    for (const auto& [m, to] : halos_) bus_.publish_halo(m, to);
    if (clock_) bus_.publish_clock(*clock_);
    for (const auto& m : states_) bus_.publish_uav_state(m);
    if (done_) bus_.publish_phase_done(*done_);
    last_ = now;
    ++resends_;
    return true;
  }

  // How many times samples were re-sent.
  [[nodiscard]] uint64_t resends() const { return resends_; }

 private:
  // Where a field chunk went: the ground station (the whole field), every
  // other place agent (served states), or the place agent `home` (tiles for
  // its views).
  enum class FieldTo : uint8_t { Ground, Places, Home };
  struct Field {
    core::FieldMsg m;
    FieldTo to = FieldTo::Ground;
    core::RegionId home = 0;
  };
  bool keep_field(const core::FieldMsg& m, FieldTo to, core::RegionId home, bool ok) {
    if (!enabled_) return ok;
    fields_.push_back(Field{m, to, home});
    last_ = now_();
    return ok;
  }
  bool publish(const Field& f) {
    switch (f.to) {
      case FieldTo::Places:
        return bus_.publish_served(f.m);
      case FieldTo::Home:
        return bus_.publish_tiles_for(f.m, f.home);
      case FieldTo::Ground:
        break;
    }
    return bus_.publish_field(f.m);
  }

  template <typename M>
  bool remember(std::vector<M>& to, const M& m, bool ok) {
    if (!enabled_) return ok;
    to.push_back(m);
    last_ = now_();
    return ok;
  }
  template <typename M>
  bool remember(std::optional<M>& to, const M& m, bool ok) {
    if (!enabled_) return ok;
    to = m;
    last_ = now_();
    return ok;
  }

  Bus& bus_;
  bool enabled_;
  std::chrono::milliseconds quiet_;
  Now now_;
  Clock::time_point last_;
  std::vector<Field> fields_;
  std::vector<core::ViewMsg> views_;
  std::vector<std::pair<core::HaloMsg, core::RegionId>> halos_;
  std::optional<core::ClockMsg> clock_;
  std::optional<core::PhaseDoneMsg> done_;
  std::vector<core::UavStateMsg> states_;
  bool deposits_on_ = false;
  std::vector<std::pair<core::DepositBatchMsg, core::RegionId>> deposits_;
  uint64_t resends_ = 0;
};

}  // namespace pheromesh::bus
