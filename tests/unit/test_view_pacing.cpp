// When a realtime UAV runs its next tick (core/view_pacing.hpp): as its view
// arrives, or on its timer without one; time driven by hand. And the timer
// the main thread sleeps on (runtime::WakeTimer), moved from another thread.
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <thread>

#include "pheromesh/core/view_pacing.hpp"
#include "pheromesh/runtime/process.hpp"

namespace pheromesh::core {
namespace {

using namespace std::chrono_literals;
using TimePoint = ViewPacing::Clock::time_point;

TEST(ViewPacing, AViewHalfAPeriodBeforeTheTickIsDueRunsItAnEarlierOneWaits) {
  const TimePoint t0 = TimePoint{} + 10s;
  ViewPacing p(200ms, t0);
  EXPECT_EQ(p.due(), t0 + 200ms);
  EXPECT_FALSE(p.view_runs_tick(t0 + 99ms)) << "101 ms before due: a copy or a burst";
  EXPECT_TRUE(p.view_runs_tick(t0 + 100ms)) << "100 ms before due: runs";
  EXPECT_TRUE(p.view_runs_tick(t0 + 250ms)) << "after due: runs";
  EXPECT_EQ(p.timer_at(), t0 + 300ms) << "without a view: half a period after due";
  EXPECT_FALSE(p.timer_runs_tick(t0 + 299ms));
  EXPECT_TRUE(p.timer_runs_tick(t0 + 300ms));
}

TEST(ViewPacing, TicksRunByViewsFollowTheViewsAndTheNextIsDueOnePeriodAfterEach) {
  const TimePoint t0 = TimePoint{} + 10s;
  ViewPacing p(200ms, t0);
  // The place agent's views arrive every 200 ms, 30 ms after the UAV's own
  // schedule: the UAV follows them.
  TimePoint v = t0 + 230ms;
  for (int i = 0; i < 10; ++i, v += 200ms) {
    ASSERT_TRUE(p.view_runs_tick(v)) << i;
    p.ran(v, /*by_view=*/true);
    EXPECT_EQ(p.due(), v + 200ms);
    EXPECT_EQ(p.timer_at(), v + 300ms);
  }
  EXPECT_EQ(p.ticks_by_view(), 10U);
  EXPECT_EQ(p.ticks_by_timer(), 0U);
  EXPECT_EQ(p.late_ticks(), 0U);
  // A second copy of the last view 5 ms later runs nothing.
  EXPECT_FALSE(p.view_runs_tick(v - 200ms + 5ms));
}

TEST(ViewPacing, WithoutViewsTheTimerKeepsThePeriodAndAViewTakesOverAgain) {
  const TimePoint t0 = TimePoint{} + 10s;
  ViewPacing p(200ms, t0);
  // No views (the gateway is gone): ticks at 300, 500, 700, ... ms.
  for (int i = 0; i < 5; ++i) {
    const TimePoint at = t0 + 300ms + i * 200ms;
    EXPECT_EQ(p.timer_at(), at) << i;
    p.ran(at, /*by_view=*/false);
  }
  EXPECT_EQ(p.ticks_by_timer(), 5U);
  EXPECT_EQ(p.late_ticks(), 0U) << "half a period after due is not late";
  // Views again (a backup gateway): the next arrives 120 ms before the next
  // timer tick (at 1300 ms) and runs it.
  const TimePoint v = t0 + 1180ms;
  EXPECT_TRUE(p.view_runs_tick(v));
  p.ran(v, /*by_view=*/true);
  EXPECT_EQ(p.due(), v + 200ms);
}

TEST(ViewPacing, ATickMoreThanAPeriodAfterItsTimerIsLateAndTheScheduleRestartsFromIt) {
  const TimePoint t0 = TimePoint{} + 10s;
  ViewPacing p(200ms, t0);
  // Due at 200 ms, its timer at 300 ms: up to 500 ms is not late.
  p.ran(t0 + 500ms, /*by_view=*/true);
  EXPECT_EQ(p.late_ticks(), 0U);
  EXPECT_EQ(p.due(), t0 + 700ms);
  p.ran(t0 + 1001ms, /*by_view=*/false);  // due 700, timer 800: 201 ms after the timer
  EXPECT_EQ(p.late_ticks(), 1U);
  EXPECT_EQ(p.due(), t0 + 1201ms) << "no burst to catch up";
  p.restart(t0 + 5s);  // a pause
  EXPECT_EQ(p.due(), t0 + 5200ms);
  EXPECT_EQ(p.late_ticks(), 1U);
}

TEST(ViewPacing, RefusesAPeriodThatIsNotPositive) { EXPECT_THROW(ViewPacing(0ms, TimePoint{}), std::invalid_argument); }

}  // namespace
}  // namespace pheromesh::core

namespace pheromesh::runtime {
namespace {

using namespace std::chrono_literals;
using SteadyClock = std::chrono::steady_clock;

TEST(WakeTimer, TheLastDeadlineSetWinsAndAnotherThreadCanMoveItWhileItSleeps) {
  // As in every process (run_process): the shutdown handlers' wake-up
  // descriptor, without which a wait would also end after a slice.
  install_shutdown_handlers();
  WakeTimer timer;
  // The last deadline set wins, earlier or later than the one before.
  auto t0 = SteadyClock::now();
  timer.set(t0 + 300ms);
  timer.set(t0 + 60s);
  timer.set(t0 + 100ms);
  ASSERT_TRUE(timer.wait());
  EXPECT_GE(SteadyClock::now() - t0, 100ms);
  EXPECT_LT(SteadyClock::now() - t0, 30s);
  t0 = SteadyClock::now();
  timer.set(t0 + 50ms);
  timer.set(t0 + 250ms);
  ASSERT_TRUE(timer.wait());
  EXPECT_GE(SteadyClock::now() - t0, 250ms) << "a deadline moved later does not wake at the earlier one";
  // Moved by another thread while this one sleeps (on a deadline a minute
  // away): it wakes at the new deadline.
  t0 = SteadyClock::now();
  timer.set(t0 + 60s);
  std::atomic<int64_t> moved_to{0};
  std::thread mover([&] {
    std::this_thread::sleep_for(20ms);
    const auto at = SteadyClock::now() + 50ms;
    moved_to = at.time_since_epoch().count();
    timer.set(at);
  });
  ASSERT_TRUE(timer.wait());
  const auto woke = SteadyClock::now();
  mover.join();
  EXPECT_GE(woke.time_since_epoch().count(), moved_to.load());
  EXPECT_LT(woke - t0, 30s);
  // A deadline already past returns at once.
  timer.set(SteadyClock::now() - 1ms);
  const auto t1 = SteadyClock::now();
  ASSERT_TRUE(timer.wait());
  EXPECT_LT(SteadyClock::now() - t1, 5s);
}

TEST(WakeTimer, AShutdownRequestWakesItAtOnceAndItSaysSo) {
  install_shutdown_handlers();
  WakeTimer timer;
  const auto t0 = SteadyClock::now();
  timer.set(t0 + 60s);
  std::thread stopper([] {
    std::this_thread::sleep_for(20ms);
    request_shutdown();  // what SIGINT and SIGTERM do
  });
  EXPECT_FALSE(timer.wait());
  stopper.join();
  EXPECT_LT(SteadyClock::now() - t0, 30s);
}

}  // namespace
}  // namespace pheromesh::runtime

TEST(StartWaitPeriod, AWaitingUavWakesFourTimesALeaseAndAtMostOnceASecond) {
  using std::chrono::milliseconds;
  EXPECT_EQ(pheromesh::core::start_wait_period(milliseconds(1000)),
            milliseconds(250));  // pheromesh-uav's default lease
  EXPECT_EQ(pheromesh::core::start_wait_period(milliseconds(200)), milliseconds(50));
  EXPECT_EQ(pheromesh::core::start_wait_period(milliseconds(4000)), milliseconds(1000));
  EXPECT_EQ(pheromesh::core::start_wait_period(milliseconds(5000)),
            milliseconds(1000));  // a big swarm's (pheromesh run)
  EXPECT_EQ(pheromesh::core::start_wait_period(milliseconds(60000)), milliseconds(1000));
  EXPECT_EQ(pheromesh::core::start_wait_period(milliseconds(2)), milliseconds(1));
  EXPECT_THROW((void)pheromesh::core::start_wait_period(milliseconds(0)), std::invalid_argument);
}
