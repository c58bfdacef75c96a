// The shells' lockstep run loop and bounded wait (runtime/lockstep_loop.hpp,
// runtime/await.hpp) on the in-memory bus: a conductor played by the test
// drives a follower's loop in another thread, tick by tick, as the ground
// station drives a UAV.
#include <gtest/gtest.h>
#include <spdlog/sinks/null_sink.h>
#include <spdlog/spdlog.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <functional>
#include <mutex>
#include <numeric>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

#include "pheromesh/bus/memory.hpp"
#include "pheromesh/runtime/await.hpp"
#include "pheromesh/runtime/lockstep_loop.hpp"
#include "pheromesh/runtime/process.hpp"

namespace pheromesh::runtime {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

std::shared_ptr<spdlog::logger> quiet_logger() {
  return std::make_shared<spdlog::logger>("test", std::make_shared<spdlog::sinks::null_sink_mt>());
}

core::ClockMsg clock_of(uint32_t tick, core::ClockPhase phase) {
  core::ClockMsg c;
  c.tick = tick;
  c.phase = static_cast<uint8_t>(phase);
  return c;
}

// Waits (bounded) until `conductor` takes a PhaseDone of `tick`.
bool done_of(bus::Bus& conductor, uint32_t tick) {
  std::vector<core::PhaseDoneMsg> dones;
  const auto deadline = Clock::now() + 5s;
  while (Clock::now() < deadline) {
    conductor.take_phase_done(dones);
    for (const auto& d : dones) {
      if (d.tick == tick) return true;
    }
    conductor.wait({bus::TopicKind::PhaseDone}, Clock::now() + 50ms);
  }
  return false;
}

TEST(LockstepLoop, RunsEachUavPhaseTheConductorAnnouncesOnceAndEndsOnItsStop) {
  auto domain = bus::make_memory_domain();
  auto conductor = bus::make_memory_bus(domain);
  auto uav = bus::make_memory_bus(domain);
  conductor->subscribe_phase_done();
  uav->subscribe_clock();
  auto log = quiet_logger();
  bus::LatestResender resend(*uav, true);
  SampleAudit audit(log);
  core::LockstepFollower follower(core::ClockPhase::Uav, core::ConductorWatch(6s, 300s, Clock::now()));
  std::vector<uint32_t> ran;
  std::atomic<int> end{-1};
  std::thread t([&] {
    LockstepLoop loop{*uav,
                      follower,
                      resend,
                      audit,
                      *log,
                      1000,
                      [] {},
                      [&](const core::ClockMsg& c) {
                        ran.push_back(c.tick);
                        resend.phase_done({core::process_key(core::kRoleUav, 0), c.tick, c.phase, 0, {}});
                        return PhaseOutcome::Continue;
                      }};
    end = static_cast<int>(loop.run());
  });
  for (uint32_t k = 0; k < 3; ++k) {
    ASSERT_TRUE(conductor->publish_clock(clock_of(k, core::ClockPhase::Uav)));
    ASSERT_TRUE(done_of(*conductor, k)) << "tick " << k;
    // The place phase and a re-sent clock of the same tick are not UAV phases.
    ASSERT_TRUE(conductor->publish_clock(clock_of(k, core::ClockPhase::Place)));
    ASSERT_TRUE(conductor->publish_clock(clock_of(k, core::ClockPhase::Uav)));
  }
  ASSERT_TRUE(conductor->publish_clock(core::LockstepConductor::stop(3)));
  t.join();
  EXPECT_EQ(end.load(), static_cast<int>(LockstepEnd::Stopped));
  EXPECT_EQ(ran, (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(follower.last_done(), 2U);
}

// A UAV's loop whose phases may run in the thread that delivers its samples
// (LockstepLoop::ready). The in-memory bus delivers in the writer's thread:
// the test's, as the conductor. `ready` and `phase` see every clock.
struct ReceivingUav {
  std::shared_ptr<bus::MemoryDomain> domain = bus::make_memory_domain();
  std::unique_ptr<bus::Bus> conductor = bus::make_memory_bus(domain);
  std::unique_ptr<bus::Bus> uav = bus::make_memory_bus(domain);
  std::shared_ptr<spdlog::logger> log = quiet_logger();
  bus::LatestResender resend{*uav, true};
  SampleAudit audit{log};
  core::LockstepFollower follower{core::ClockPhase::Uav, core::ConductorWatch(6s, 300s, Clock::now())};
  std::thread::id loop_thread;
  std::atomic<int> end{-1};
  std::exception_ptr thrown;
  std::atomic<bool> started{false};
  std::thread t;

  ReceivingUav(std::function<bool(const core::ClockMsg&)> ready, std::function<void(const core::ClockMsg&)> phase) {
    conductor->subscribe_phase_done();
    uav->subscribe_clock();
    uav->offer_phase_done();  // no endpoint is created in a delivering thread
    t = std::thread([this, ready, phase] {
      loop_thread = std::this_thread::get_id();
      LockstepLoop loop{*uav,
                        follower,
                        resend,
                        audit,
                        *log,
                        1000,
                        [this] { started = true; },
                        [&](const core::ClockMsg& c) {
                          phase(c);
                          resend.phase_done({core::process_key(core::kRoleUav, 0), c.tick, c.phase, 0, {}});
                          return PhaseOutcome::Continue;
                        }};
      loop.ready = ready;
      loop.inputs = {bus::TopicKind::Clock};
      try {
        end = static_cast<int>(loop.run());
      } catch (...) {
        thrown = std::current_exception();
        end = 100;
      }
    });
    const auto deadline = Clock::now() + 5s;
    while (!started && Clock::now() < deadline) std::this_thread::sleep_for(1ms);
  }
  ~ReceivingUav() {
    if (t.joinable()) {
      conductor->publish_clock(core::LockstepConductor::stop(1000));
      t.join();
    }
  }
  ReceivingUav(const ReceivingUav&) = delete;
  ReceivingUav& operator=(const ReceivingUav&) = delete;
};

TEST(LockstepLoop, AReadyPhaseRunsInTheThreadThatDeliveredItsClockEachOnceInOrder) {
  std::mutex m;
  std::vector<uint32_t> ran;
  std::vector<std::thread::id> on;
  ReceivingUav u([](const core::ClockMsg&) { return true; },
                 [&](const core::ClockMsg& c) {
                   std::lock_guard<std::mutex> lock(m);
                   ran.push_back(c.tick);
                   on.push_back(std::this_thread::get_id());
                 });
  constexpr uint32_t kTicks = 20;
  for (uint32_t k = 0; k < kTicks; ++k) {
    ASSERT_TRUE(u.conductor->publish_clock(clock_of(k, core::ClockPhase::Uav)));
    ASSERT_TRUE(done_of(*u.conductor, k)) << "tick " << k;
    ASSERT_TRUE(u.conductor->publish_clock(clock_of(k, core::ClockPhase::Uav)));  // a re-send: not run again
  }
  ASSERT_TRUE(u.conductor->publish_clock(core::LockstepConductor::stop(kTicks)));
  u.t.join();
  EXPECT_EQ(u.end.load(), static_cast<int>(LockstepEnd::Stopped));
  std::vector<uint32_t> expected(kTicks);
  std::iota(expected.begin(), expected.end(), 0U);
  EXPECT_EQ(ran, expected);
  // The main thread runs a round when it starts and after each quiet
  // 250 ms; the clocks come faster, so (almost) all ran in the delivering
  // thread, the test's.
  const auto here = std::count(on.begin(), on.end(), std::this_thread::get_id());
  EXPECT_GE(here, static_cast<long>(kTicks) / 2) << "of " << kTicks << " phases";
  EXPECT_EQ(here + std::count(on.begin(), on.end(), u.loop_thread), static_cast<long>(kTicks));
}

TEST(LockstepLoop, APhaseThatIsNotReadyIsLeftToTheMainThreadOrToTheSampleThatMakesItReady) {
  std::mutex m;
  std::atomic<bool> view_here{false};
  std::vector<std::pair<uint32_t, bool>> ran;  // tick, in the loop's own thread
  std::thread::id loop_thread;
  ReceivingUav u([&](const core::ClockMsg& c) { return c.tick != 1 || view_here.load(); },
                 [&](const core::ClockMsg& c) {
                   std::lock_guard<std::mutex> lock(m);
                   // Never in the delivering thread while it is not ready.
                   if (c.tick == 1 && std::this_thread::get_id() != loop_thread) EXPECT_TRUE(view_here.load());
                   ran.emplace_back(c.tick, std::this_thread::get_id() == loop_thread);
                 });
  loop_thread = u.loop_thread;
  ASSERT_TRUE(u.conductor->publish_clock(clock_of(0, core::ClockPhase::Uav)));
  ASSERT_TRUE(done_of(*u.conductor, 0));
  // Tick 1 is not ready in the delivering thread: the main thread runs it
  // after its slice (a UAV's phase would wait there for its view).
  ASSERT_TRUE(u.conductor->publish_clock(clock_of(1, core::ClockPhase::Uav)));
  ASSERT_TRUE(done_of(*u.conductor, 1));
  {
    std::lock_guard<std::mutex> lock(m);
    ASSERT_EQ(ran.size(), 2U);
    EXPECT_TRUE(ran[1].second) << "tick 1 ran in the delivering thread while it was not ready";
  }
  view_here = true;
  ASSERT_TRUE(u.conductor->publish_clock(clock_of(2, core::ClockPhase::Uav)));
  ASSERT_TRUE(done_of(*u.conductor, 2));
  ASSERT_TRUE(u.conductor->publish_clock(core::LockstepConductor::stop(3)));
  u.t.join();
  EXPECT_EQ(u.end.load(), static_cast<int>(LockstepEnd::Stopped));
  ASSERT_EQ(ran.size(), 3U);
  EXPECT_EQ(ran[0].first, 0U);
  EXPECT_EQ(ran[1].first, 1U);
  EXPECT_EQ(ran[2].first, 2U);
}

TEST(LockstepLoop, WhatAPhaseThrowsInTheDeliveringThreadIsThrownByRunInItsOwn) {
  ReceivingUav u([](const core::ClockMsg&) { return true; },
                 [](const core::ClockMsg& c) {
                   if (c.tick == 1) throw std::runtime_error("phase 1 failed");
                 });
  ASSERT_TRUE(u.conductor->publish_clock(clock_of(0, core::ClockPhase::Uav)));
  ASSERT_TRUE(done_of(*u.conductor, 0));
  // The conductor's write returns: the exception does not cross the
  // delivering thread (a vendor's C frames).
  EXPECT_NO_THROW(u.conductor->publish_clock(clock_of(1, core::ClockPhase::Uav)));
  u.t.join();
  ASSERT_TRUE(u.thrown);
  try {
    std::rethrow_exception(u.thrown);
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "phase 1 failed");
  }
}

// A place agent's phase waits for samples several times: it runs as far as
// the samples held let it and says Pending; the sample that completes it
// runs it on in the thread that delivered it, and only then is it done.
TEST(LockstepLoop, APendingPhaseIsRunOnByTheSampleThatCompletesItAndIsDoneOnlyThen) {
  auto domain = bus::make_memory_domain();
  auto conductor = bus::make_memory_bus(domain);
  auto neighbour = bus::make_memory_bus(domain);
  auto place = bus::make_memory_bus(domain);
  conductor->subscribe_phase_done();
  place->subscribe_clock();
  place->subscribe_ground();  // stands in for a place agent's inputs: health samples
  place->offer_phase_done();
  auto log = quiet_logger();
  bus::LatestResender resend(*place, true);
  SampleAudit audit(log);
  core::LockstepFollower follower(core::ClockPhase::Place, core::ConductorWatch(6s, 300s, Clock::now()));
  std::mutex m;
  std::vector<uint32_t> held;  // ticks of the health samples the phases took
  std::vector<std::pair<uint32_t, std::thread::id>> finished;
  std::atomic<int> calls{0};
  std::atomic<bool> started{false};
  std::atomic<int> end{-1};
  std::thread::id loop_thread;
  std::thread t([&] {
    loop_thread = std::this_thread::get_id();
    LockstepLoop loop{*place,
                      follower,
                      resend,
                      audit,
                      *log,
                      1000,
                      [&] { started = true; },
                      [&](const core::ClockMsg& c) {
                        ++calls;
                        std::vector<core::HealthMsg> h;
                        place->take_health(h);
                        std::lock_guard<std::mutex> lock(m);
                        for (const auto& x : h) held.push_back(x.tick);
                        if (std::find(held.begin(), held.end(), c.tick) == held.end()) return PhaseOutcome::Pending;
                        finished.emplace_back(c.tick, std::this_thread::get_id());
                        resend.phase_done({core::process_key(core::kRolePlace, 0), c.tick, c.phase, 0, {}});
                        return PhaseOutcome::Continue;
                      }};
    loop.inputs = {bus::TopicKind::Clock, bus::TopicKind::Health};
    end = static_cast<int>(loop.run());
  });
  const auto deadline = Clock::now() + 5s;
  while (!started && Clock::now() < deadline) std::this_thread::sleep_for(1ms);
  for (uint32_t k = 0; k < 3; ++k) {
    ASSERT_TRUE(conductor->publish_clock(clock_of(k, core::ClockPhase::Place)));
    std::this_thread::sleep_for(100ms);
    {
      std::lock_guard<std::mutex> lock(m);
      EXPECT_EQ(finished.size(), k) << "tick " << k << " finished before its sample came";
    }
    std::vector<core::PhaseDoneMsg> early;
    conductor->take_phase_done(early);
    EXPECT_TRUE(std::none_of(early.begin(), early.end(), [&](const auto& d) { return d.tick == k; }))
        << "tick " << k << " reported done while pending";
    core::HealthMsg h;
    h.tick = k;
    ASSERT_TRUE(neighbour->publish_health(h));
    ASSERT_TRUE(done_of(*conductor, k)) << "tick " << k;
  }
  ASSERT_TRUE(conductor->publish_clock(core::LockstepConductor::stop(3)));
  t.join();
  EXPECT_EQ(end.load(), static_cast<int>(LockstepEnd::Stopped));
  EXPECT_EQ(follower.last_done(), 2U);
  std::lock_guard<std::mutex> lock(m);
  ASSERT_EQ(finished.size(), 3U);
  for (uint32_t k = 0; k < 3; ++k) {
    EXPECT_EQ(finished[k].first, k);
    // The health sample's writer, the test, delivered it (unless the main
    // thread's round happened to hold the loop then).
    EXPECT_TRUE(finished[k].second == std::this_thread::get_id() || finished[k].second == loop_thread);
  }
  EXPECT_GT(calls.load(), 3) << "a pending phase is run again";
  const auto here = std::count_if(finished.begin(), finished.end(),
                                  [](const auto& f) { return f.second == std::this_thread::get_id(); });
  EXPECT_GE(here, 2) << "of 3 phases, finished in the delivering thread";
}

TEST(LockstepFollower, APhaseGivenBackComesFirstAgain) {
  core::LockstepFollower f(core::ClockPhase::Uav, core::ConductorWatch(6s, 300s, Clock::now()));
  std::vector<core::ClockMsg> taken{clock_of(0, core::ClockPhase::Uav), clock_of(1, core::ClockPhase::Uav)};
  for (auto& c : taken) c.writer = 7;
  f.offer(taken, Clock::now());
  auto first = f.next_phase();
  ASSERT_TRUE(first);
  EXPECT_EQ(first->tick, 0U);
  f.put_back(*first);
  auto again = f.next_phase();
  ASSERT_TRUE(again);
  EXPECT_EQ(again->tick, 0U);
  f.done(0);
  auto next = f.next_phase();
  ASSERT_TRUE(next);
  EXPECT_EQ(next->tick, 1U);
}

// A place agent's loop whose conductor sent the clock of tick 0 and then fell
// silent (a watch of 300 ms); `phase` runs the one phase it announced.
LockstepEnd run_after_one_clock(const std::function<void()>& phase) {
  auto domain = bus::make_memory_domain();
  auto conductor = bus::make_memory_bus(domain);
  auto place = bus::make_memory_bus(domain);
  place->subscribe_clock();
  auto log = quiet_logger();
  bus::LatestResender resend(*place, true);
  SampleAudit audit(log);
  core::LockstepFollower follower(core::ClockPhase::Place, core::ConductorWatch(300ms, 300ms, Clock::now()));
  EXPECT_TRUE(conductor->publish_clock(clock_of(0, core::ClockPhase::Place)));
  LockstepLoop loop{*place,
                    follower,
                    resend,
                    audit,
                    *log,
                    50,
                    [] {},
                    [&](const core::ClockMsg&) {
                      phase();
                      return PhaseOutcome::Continue;
                    }};
  return loop.run();
}

TEST(LockstepLoop, AConductorThatFallsSilentEndsTheLoopAfterTheWatchsLimit) {
  uint32_t phases = 0;
  const auto t0 = Clock::now();
  EXPECT_EQ(run_after_one_clock([&] { ++phases; }), LockstepEnd::ConductorLost);
  EXPECT_EQ(phases, 1U);
  EXPECT_GE(Clock::now() - t0, 300ms) << "not before the limit";
}

// Measured in a mixed run whose conductor was SIGKILLed: a place agent's
// place phase waited 6 s for samples that never came; meanwhile every UAV
// ended (conductor gone) and the launcher sent SIGTERM. The place agent saw
// the stop first and ended as if stopped (exit 0), without naming the
// conductor. A child process: the stop request is process-wide.
TEST(LockstepLoop, AStopAskedForAfterTheConductorFellSilentEndsTheLoopAsConductorLost) {
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    _exit(static_cast<int>(run_after_one_clock([] {
      std::this_thread::sleep_for(400ms);  // a phase that waits past the watch's limit
      request_shutdown();                  // the launcher's SIGTERM
    })));
  }
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << status;
  EXPECT_EQ(WEXITSTATUS(status), static_cast<int>(LockstepEnd::ConductorLost));
}

TEST(AwaitSamples, TakesUntilTheAwaitedSampleArrivesAndGivesUpAtTheBound) {
  auto domain = bus::make_memory_domain();
  auto ground = bus::make_memory_bus(domain);
  auto place = bus::make_memory_bus(domain);
  ground->subscribe_ground();
  std::vector<core::HealthMsg> health;
  std::thread writer([&] {
    std::this_thread::sleep_for(50ms);
    core::HealthMsg h;
    h.region = 2;
    h.tick = 7;
    place->publish_health(h);
  });
  const auto r = await_samples(
      *ground, {bus::TopicKind::Health}, {2000ms, 20ms}, nullptr, [&] { ground->take_health(health); },
      [&] { return !health.empty(); });
  writer.join();
  EXPECT_EQ(r, Awaited::Done);
  ASSERT_EQ(health.size(), 1U);
  EXPECT_EQ(health[0].tick, 7U);
  const auto t0 = Clock::now();
  const auto none = await_samples(
      *ground, {bus::TopicKind::Health}, {100ms, 20ms}, nullptr, [&] { ground->take_health(health); },
      [&] { return health.size() > 1; });
  EXPECT_EQ(none, Awaited::TimedOut);
  EXPECT_GE(Clock::now() - t0, 100ms) << "not before its bound";
}

}  // namespace
}  // namespace pheromesh::runtime

namespace pheromesh::runtime {
namespace sample_audit_test {  // named: the unit tests build as one unity source

TEST(SampleAudit, RefusesSeveralSamplesAtOnceUnderOneReasonAndNoneForZero) {
  SampleAudit audit(std::make_shared<spdlog::logger>("audit", std::make_shared<spdlog::sinks::null_sink_mt>()));
  audit.refuse(core::Refusal::RefusedStateDeposit, "3 deposits of a refused state", 3);
  audit.refuse(core::Refusal::RefusedStateDeposit, "no deposit", 0);
  audit.refuse(core::Refusal::UnknownPlace, "a health of standby 1 of region 0");
  EXPECT_EQ(audit.refused()[core::Refusal::RefusedStateDeposit], 3U);
  EXPECT_EQ(audit.refused()[core::Refusal::UnknownPlace], 1U);
  EXPECT_EQ(audit.refused().total(), 4U);
}

}  // namespace sample_audit_test
}  // namespace pheromesh::runtime
