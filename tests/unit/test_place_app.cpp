// The place agent's app as a library (issue 43 D2): a lockstep PlaceApp on
// the in-memory bus, driven by a conductor and a UAV the test plays, gives
// its UAV the view of exactly the field core::PlaceCore computes from the
// same deposit, and counts it in its final health. No DDS. In a child
// process: the stop request that ends the app is process-wide.
#include <gtest/gtest.h>
#include <spdlog/spdlog.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <map>
#include <thread>
#include <tuple>
#include <vector>

#include "pheromesh/bus/memory.hpp"
#include "pheromesh/core/place_core.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/runtime/process.hpp"
#include "place_app.hpp"

namespace pheromesh::placeagent {
namespace place_app_test {  // named: the unit tests build as one unity source

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

// Polls `take` until `found` holds, for at most 5 s; waits on `kind` between.
template <typename Take, typename Found>
bool await(bus::Bus& b, bus::TopicKind kind, Take take, Found found) {
  const auto deadline = Clock::now() + 5s;
  while (Clock::now() < deadline) {
    take();
    if (found()) return true;
    b.wait({kind}, Clock::now() + 20ms);
  }
  return false;
}

bool done_of(bus::Bus& conductor, uint32_t tick, core::ClockPhase phase) {
  std::vector<core::PhaseDoneMsg> dones;
  return await(
      conductor, bus::TopicKind::PhaseDone, [&] { conductor.take_phase_done(dones); },
      [&] {
        for (const auto& d : dones) {
          if (d.tick == tick && d.phase == static_cast<uint8_t>(phase) &&
              d.process == core::process_key(core::kRolePlace, 0)) {
            return true;
          }
        }
        return false;
      });
}

core::ClockMsg clock_of(uint32_t tick, core::ClockPhase phase) {
  core::ClockMsg c;
  c.tick = tick;
  c.phase = static_cast<uint8_t>(phase);
  return c;
}

// The run, as an exit code: 0 if every step held, else the step that failed.
int fly_one_tick() {
  spdlog::set_level(spdlog::level::off);
  auto loaded = core::load_scenario(std::string(PHEROMESH_SOURCE_DIR) + "/scenarios/small-test.textproto");
  if (!loaded) return 10;
  core::ScenarioConfig s = loaded.value();
  s.regions_x = 1;  // one place agent: no neighbour to wait for
  s.regions_y = 1;
  auto domain = bus::make_memory_domain();
  auto conductor = bus::make_memory_bus(domain);
  conductor->subscribe_phase_done();
  conductor->subscribe_health();
  auto uav = bus::make_memory_bus(domain);
  uav->join_uav(0, 0);
  const std::vector<core::RegionId> gateways{0, 0};
  uav->join_clock_tree(gateways);
  PlaceConfig cfg;
  cfg.common.clock = "lockstep";
  std::atomic<int> rc{-1};
  std::thread place([&] {
    PlaceApp app(cfg, s, bus::make_memory_bus(domain));
    rc = app.run();
  });
  const auto stop = [&](int code) {
    runtime::request_shutdown();
    place.join();
    return code;
  };
  if (!done_of(*conductor, 0, core::ClockPhase::Ready)) return stop(11);

  // UAV phase 0: UAV 0 at its start cell marks it (a path visit), its
  // deposit carried by its state.
  conductor->publish_clock(clock_of(0, core::ClockPhase::Uav));
  const core::Cell start = core::uav_start(s, core::policy_traits(s), 0);
  core::DepositMsg d;
  d.uav = 0;
  d.seq = 1;
  d.tick = 0;
  d.region = 0;
  d.kind = static_cast<uint8_t>(core::DepositKind::PathVisit);
  d.cell = start;
  d.amount = 1.0F;
  core::UavStateMsg st;
  st.uav = 0;
  st.tick = 0;
  st.x = start.x + 0.5;
  st.y = start.y + 0.5;
  st.view = start;
  st.deposits_sent = 1;
  st.deposits = {d};
  uav->publish_uav_state(st);

  // Place phase 0: exactly that deposit and that state, and the UAV served
  // by region 0 (the conductor lists every UAV whose state it accepted).
  core::ClockMsg place_phase = clock_of(0, core::ClockPhase::Place);
  place_phase.deposits = {{0, 1}};
  place_phase.states = {{0, 1}};
  place_phase.served = {{0, 0, st.x, st.y, 0.0, 0.0, 0, 0, start}};
  // ... which begins UAV phase 1 (the conductor waits for no place report
  // before it): the place agent gives that UAV clock in the view of tick 0
  // (the UAV's bus hands it out as a clock and holds the view).
  place_phase.next_uav_phase = true;
  place_phase.broadcasts = 0;
  conductor->publish_clock(place_phase);
  std::vector<core::ClockMsg> clocks;
  const auto uav_clock_1 = [&] {
    return std::any_of(clocks.begin(), clocks.end(), [](const core::ClockMsg& c) {
      return c.tick == 1 && c.phase == static_cast<uint8_t>(core::ClockPhase::Uav);
    });
  };
  if (!await(
          *uav, bus::TopicKind::RelayedClock, [&] { uav->take_clock(clocks); }, uav_clock_1))
    return stop(20);
  std::vector<core::ViewMsg> views;
  uav->take_views(views);
  if (views.empty() || views.back().tick != 0) return stop(21);  // the view that carried it
  if (!done_of(*conductor, 0, core::ClockPhase::Place)) return stop(12);
  if (!await(
          *uav, bus::TopicKind::View, [&] { uav->take_views(views); },
          [&] { return !views.empty() && views.back().tick == 0; })) {
    return stop(13);
  }

  // The same deposit through the core alone.
  core::PlaceCore expected(s, 0);
  std::vector<core::DepositMsg> inbox{d};
  std::vector<core::TargetEventMsg> events;
  (void)expected.begin_tick(inbox, 0, events);
  expected.finish_tick();
  std::vector<core::TileMsg> tiles;
  expected.tiles(0, core::PlaceCore::TileSelection::All, tiles);
  std::map<std::tuple<int32_t, int32_t, int>, std::vector<float>> field;
  for (const auto& t : tiles) field[{t.tile.tx, t.tile.ty, t.layer}] = t.values;
  const core::ViewMsg& v = views.back();
  if (v.tiles.empty() || v.deposit_ack != 1) return stop(14);
  bool marked = false;
  for (const auto& t : v.tiles) {
    auto it = field.find({t.tile.tx, t.tile.ty, t.layer});
    if (it == field.end() || it->second != t.values) return stop(15);
    for (float x : t.values) marked = marked || x != 0.0F;
  }
  if (!marked) return stop(16);  // the view shows the deposit

  // The conductor's Stop, then the launcher's SIGTERM: whichever the app
  // takes first, it ends with its final health.
  conductor->publish_clock(clock_of(1, core::ClockPhase::Stop));
  const int code = stop(0);
  if (rc != 0) return 17;
  std::vector<core::HealthMsg> health;
  conductor->take_health(health);
  for (const auto& h : health) {
    if (h.finished) return h.deposits_applied == 1 && h.deposits_received == 1 ? code : 18;
  }
  return 19;
}

TEST(PlaceApp, ALockstepPlaceAgentOnTheInMemoryBusGivesItsUavTheCoresFieldOfItsDeposit) {
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) _exit(fly_one_tick());
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << status;
  EXPECT_EQ(WEXITSTATUS(status), 0) << "the step that failed (fly_one_tick)";
}

}  // namespace place_app_test
}  // namespace pheromesh::placeagent
