#include <gtest/gtest.h>

#include "pheromesh/core/faults.hpp"

namespace pheromesh::core {
namespace {

TEST(FaultSchedule, ParsesEveryActionWithTargetsTimesAndDurations) {
  auto s = parse_fault_schedule(
      "stop place:1 @10s for 5s; kill uav:3 @5s; partition uav:0-2,place:1 @12s for 2500ms; loss 30% @0s for 20s; "
      "restart uav:2 @7s for 1s; standby place:0 @8s");
  ASSERT_TRUE(s.ok()) << s.error().message;
  ASSERT_EQ(s->events.size(), 6U);
  // Sorted by time.
  EXPECT_EQ(s->events[0].action, FaultAction::Loss);
  EXPECT_DOUBLE_EQ(s->events[0].loss, 0.30);
  EXPECT_TRUE(s->events[0].targets.empty());
  EXPECT_DOUBLE_EQ(s->events[0].duration_s, 20.0);
  EXPECT_EQ(s->events[1].action, FaultAction::Kill);
  EXPECT_DOUBLE_EQ(*s->events[1].at_s, 5.0);
  EXPECT_EQ(s->events[1].targets, (std::vector<FaultTarget>{{"uav", 3}}));
  EXPECT_EQ(s->events[2].action, FaultAction::Restart);
  EXPECT_DOUBLE_EQ(s->events[2].duration_s, 1.0);
  EXPECT_EQ(s->events[3].action, FaultAction::Standby);
  EXPECT_EQ(s->events[4].action, FaultAction::Stop);
  EXPECT_DOUBLE_EQ(s->events[4].duration_s, 5.0);
  EXPECT_EQ(s->events[5].action, FaultAction::Partition);
  EXPECT_DOUBLE_EQ(s->events[5].duration_s, 2.5);
  EXPECT_EQ(s->events[5].targets,
            (std::vector<FaultTarget>{{"uav", 0}, {"uav", 1}, {"uav", 2}, {"place", 1}}));
  EXPECT_TRUE(s->has_network());
  EXPECT_FALSE(s->in_ticks());
}

TEST(FaultSchedule, TicksForLockstepAndTheSimulator) {
  auto s = parse_fault_schedule("kill uav:1 @40t; kill place:2 @12t; kill uav:1 @50t; stop uav:0 @3t for 2s");
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_TRUE(s->in_ticks());
  EXPECT_EQ(*s->events.front().at_tick, 3U);
  // The first kill of a UAV counts.
  EXPECT_EQ(s->uav_kills(), (std::vector<std::pair<uint32_t, uint32_t>>{{1, 40}}));
  EXPECT_EQ(s->place_kills(), (std::vector<std::pair<uint32_t, uint32_t>>{{2, 12}}));
  EXPECT_FALSE(check_fault_schedule(s.value(), 4, 4, true).has_value());
  const auto realtime = check_fault_schedule(s.value(), 4, 4, false);
  ASSERT_TRUE(realtime.has_value());
  EXPECT_NE(realtime->find("realtime run times faults in s or ms"), std::string::npos) << *realtime;
}

TEST(FaultSchedule, AcceptsTheOlderKillForm) {
  auto s = parse_fault_schedule("uav:3@5s,place:1@2500ms", "--kill");
  ASSERT_TRUE(s.ok()) << s.error().message;
  ASSERT_EQ(s->events.size(), 2U);
  EXPECT_EQ(s->events[0].targets.front().process_name(), "place-1");
  EXPECT_DOUBLE_EQ(*s->events[0].at_s, 2.5);
  EXPECT_EQ(s->events[1].targets.front().process_name(), "uav-3");
}

TEST(FaultSchedule, ErrorsNameTheSourceTheItemAndWhatIsWrong) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"explode uav:1 @5s", "unknown action 'explode'"},
      {"kill uav:1", "no time"},
      {"stop uav:1 for 3s", "no time"},
      {"kill uav:1 @5", "needs a unit"},
      {"stop uav:1 @5s", "stop needs 'for DURATION'"},
      {"stop uav:1 @5s for 3t", "wall time"},
      {"kill drone:1 @5s", "role must be uav, place or ground"},
      {"kill uav:4-2 @5s", "bad range"},
      {"loss 130% @1s for 2s", "loss share"},
      {"kill uav:1 @5s; kill uav:2 @4t", "mixes tick times"},
      {"standby uav:1 @4s", "standby starts place agents only"},
      {"kill uav:1 @5s extra", "unexpected 'extra'"},
  };
  for (const auto& [text, want] : cases) {
    auto s = parse_fault_schedule(text, "scen.textproto:7");
    ASSERT_FALSE(s.ok()) << text;
    EXPECT_NE(s.error().message.find("scen.textproto:7"), std::string::npos) << s.error().message;
    EXPECT_NE(s.error().message.find(want), std::string::npos) << text << " -> " << s.error().message;
  }
  auto s = parse_fault_schedule("kill uav:9 @1s");
  ASSERT_TRUE(s.ok());
  const auto err = check_fault_schedule(s.value(), 6, 4, false);
  ASSERT_TRUE(err.has_value());
  EXPECT_NE(err->find("uav-9 does not exist (this swarm has 6 UAVs: uav:0-5)"), std::string::npos) << *err;
}

}  // namespace
}  // namespace pheromesh::core
