// When a realtime UAV runs its next tick (issue 44): as its gateway's view
// arrives, in the thread that received it, rather than on a timer of its own
// (docs/architecture.md, "Answering in the receive thread"). The place agent
// ticks at the swarm's rate and sends each UAV one view a tick, so the views
// pace the UAV; a UAV that acts on a view as it arrives also acts on the
// newest field. What a timer of its own cost was a wake-up of its main
// thread per tick, besides the receive thread's wake-up for the view
// (measured: docs/benchmarks.md, "A tick paced by the view").
//
// Rules, with time passed in so that tests drive it by hand:
//  * A view that arrives at most half a period before the next tick is due
//    runs it (an earlier one is a copy or a burst: the tick waits).
//  * Without views (the gateway is dead or paused, views lost) the tick runs
//    half a period after it was due, and the ticks after it keep the period
//    from there: the UAV keeps the swarm's rate on its own.
//  * A tick that a view ran is the anchor of the next: the next is due one
//    period after it, so the UAV follows its place agent's clock.
//  * A tick that starts more than a period after the timer would have run
//    it is late (runtime::TickClock counts a wake-up more than a period
//    after its boundary), and the schedule restarts from it.
#pragma once

#include <chrono>
#include <cstdint>

namespace pheromesh::core {

class ViewPacing {
 public:
  using Clock = std::chrono::steady_clock;

  // `period` > 0; the first tick after `start` is due one period later.
  ViewPacing(std::chrono::nanoseconds period, Clock::time_point start);

  // A view arrived at `now`: whether it runs the next tick now.
  [[nodiscard]] bool view_runs_tick(Clock::time_point now) const { return now >= due_ - period_ / 2; }
  // When the next tick runs if no view runs it first.
  [[nodiscard]] Clock::time_point timer_at() const { return due_ + period_ / 2; }
  [[nodiscard]] bool timer_runs_tick(Clock::time_point now) const { return now >= timer_at(); }

  // The next tick ran at `now`, started by a view (`by_view`) or by the timer.
  void ran(Clock::time_point now, bool by_view);
  // Nothing ran for a while on purpose (a pause from the console): the next
  // tick is due one period after `now`, and the silence is not lateness.
  void restart(Clock::time_point now) { due_ = now + period_; }

  [[nodiscard]] Clock::time_point due() const { return due_; }
  [[nodiscard]] std::chrono::nanoseconds period() const { return period_; }
  [[nodiscard]] uint32_t late_ticks() const { return late_; }
  [[nodiscard]] uint64_t ticks_by_view() const { return by_view_; }
  [[nodiscard]] uint64_t ticks_by_timer() const { return by_timer_; }

 private:
  std::chrono::nanoseconds period_;
  Clock::time_point due_;
  uint32_t late_ = 0;
  uint64_t by_view_ = 0;
  uint64_t by_timer_ = 0;
};

// How often a realtime UAV that waits for the ground station's start wakes
// on its own: to announce itself again (its state, so that a ground station
// that joined late hears it) and so keep its state writer's liveliness
// asserted, four times a lease; the start, or a command, wakes it at once.
// At most once a second: before the start a UAV does nothing else, each
// wake-up is most of what it costs, and a swarm of thousands waits minutes
// for its last UAVs (docs/benchmarks.md, "Waiting for the start"). `lease` > 0.
[[nodiscard]] std::chrono::milliseconds start_wait_period(std::chrono::milliseconds lease);

}  // namespace pheromesh::core
