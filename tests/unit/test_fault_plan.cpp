// The launcher's fault bookkeeping (core/fault_plan.hpp): which events are due
// at a wall time or before a lockstep tick, when the lasting ones end, and
// what metrics.json records.
#include <gtest/gtest.h>

#include "pheromesh/core/fault_plan.hpp"

namespace pheromesh::core {
namespace {

FaultPlan plan_of(const std::string& text) {
  auto s = parse_fault_schedule(text);
  EXPECT_TRUE(s.ok()) << s.error().message;
  return FaultPlan(std::move(s).value());
}

std::vector<FaultAction> actions(const FaultPlan& p, const std::vector<std::size_t>& idx) {
  std::vector<FaultAction> out;
  for (auto i : idx) out.push_back(p.event(i).action);
  return out;
}

TEST(FaultPlan, RealtimeEventsAreHandedOutOnceWhenTheirTimeHasCome) {
  FaultPlan p = plan_of("kill uav:3 @5s; stop place:1 @10s for 5s; loss 30% @2s for 20s");
  EXPECT_TRUE(p.take_due_at(1.9).empty());
  EXPECT_EQ(actions(p, p.take_due_at(2.0)), std::vector<FaultAction>{FaultAction::Loss});
  EXPECT_TRUE(p.take_due_at(4.0).empty());
  // A late look hands out everything overdue, in schedule order, once.
  EXPECT_EQ(actions(p, p.take_due_at(11.0)), (std::vector<FaultAction>{FaultAction::Kill, FaultAction::Stop}));
  EXPECT_TRUE(p.take_due_at(100.0).empty());
  EXPECT_TRUE(p.all_taken());
}

TEST(FaultPlan, LockstepEventsAreDueBeforeTheirTickAndEarlierOnesAreNotForgotten) {
  FaultPlan p = plan_of("kill uav:1 @40t; stop uav:0 @3t for 2s; kill place:2 @12t; kill uav:2 @40t");
  EXPECT_EQ(p.fault_ticks(), (std::vector<uint32_t>{3, 12, 40}));
  EXPECT_TRUE(p.take_due_before_tick(2).empty());
  EXPECT_EQ(actions(p, p.take_due_before_tick(3)), std::vector<FaultAction>{FaultAction::Stop});
  // The conductor skipped asking before tick 12: asked before 20, tick 12's
  // kill is still handed out.
  const auto at20 = p.take_due_before_tick(20);
  ASSERT_EQ(at20.size(), 1U);
  EXPECT_EQ(p.event(at20[0]).targets.front().process_name(), "place-2");
  EXPECT_EQ(p.take_due_before_tick(40).size(), 2U);
  EXPECT_TRUE(p.take_due_before_tick(1000).empty());
  // Tick events never come due by wall time, nor second events by tick.
  FaultPlan q = plan_of("kill uav:1 @4t");
  EXPECT_TRUE(q.take_due_at(1e9).empty());
  FaultPlan r = plan_of("kill uav:1 @4s");
  EXPECT_TRUE(r.take_due_before_tick(1000000).empty());
}

TEST(FaultPlan, LastingEventsEndAfterTheirDurationFromWhenTheyBegan) {
  FaultPlan p = plan_of("stop uav:1 @1s for 5s; kill uav:2 @2s; restart uav:3 @3s for 1s");
  for (auto i : p.take_due_at(3.5)) p.begin(i, 3.5, {p.event(i).targets.front().process_name()});
  // Begun late (3.5 s): the stop ends 5 s after it began, not after 1 s + 5 s.
  EXPECT_TRUE(p.take_ends_at(4.4).empty());
  EXPECT_EQ(actions(p, p.take_ends_at(4.5)), std::vector<FaultAction>{FaultAction::Restart});
  EXPECT_TRUE(p.take_ends_at(8.4).empty());
  const auto stop_end = p.take_ends_at(8.5);
  ASSERT_EQ(actions(p, stop_end), std::vector<FaultAction>{FaultAction::Stop});
  p.end(stop_end[0], 8.51);
  EXPECT_TRUE(p.take_ends_at(100).empty());
  // The records: the kill was done when it began, the restart never ended.
  const auto& rec = p.records();
  ASSERT_EQ(rec.size(), 3U);
  EXPECT_EQ(rec[0].action, FaultAction::Stop);
  EXPECT_DOUBLE_EQ(rec[0].duration_s, 5.0);
  EXPECT_DOUBLE_EQ(*rec[0].done_at_s, 8.51);
  EXPECT_EQ(rec[1].action, FaultAction::Kill);
  EXPECT_DOUBLE_EQ(*rec[1].done_at_s, 3.5);
  EXPECT_EQ(rec[2].targets, std::vector<std::string>{"uav-3"});
  EXPECT_FALSE(rec[2].done_at_s.has_value());
}

TEST(FaultPlan, AtTheEndOfARunEveryOpenEventIsHandedOutToBeUndone) {
  FaultPlan p = plan_of("partition uav:0-1 @1s for 60s; loss 20% @2s for 60s; kill uav:3 @3s");
  for (auto i : p.take_due_at(3)) p.begin(i, 3, {});
  const auto open = p.take_all_ends();
  EXPECT_EQ(actions(p, open), (std::vector<FaultAction>{FaultAction::Partition, FaultAction::Loss}));
  for (auto i : open) p.end(i, 10, "cut short: the run ended");
  EXPECT_TRUE(p.take_all_ends().empty());
  EXPECT_EQ(p.records()[0].note, "cut short: the run ended");
  EXPECT_DOUBLE_EQ(*p.records()[1].done_at_s, 10.0);
}

TEST(FaultPlan, BeginningAnEventTwiceIsAProgrammingError) {
  FaultPlan p = plan_of("kill uav:1 @1s");
  p.begin(0, 1, {"uav-1"});
  EXPECT_THROW(p.begin(0, 2, {"uav-1"}), std::logic_error);
  FaultPlan q = plan_of("stop uav:1 @1s for 1s");
  EXPECT_THROW(q.end(0, 1), std::logic_error);
}

}  // namespace
}  // namespace pheromesh::core
