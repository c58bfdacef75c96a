// Lockstep: when a place agent's relays of its gateway UAVs' states and
// reports go to the ground station (core/relay_batch.hpp).
#include "pheromesh/core/relay_batch.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <vector>

namespace pheromesh::core {
namespace {

using std::chrono::milliseconds;
const RelayBatch::Clock::time_point kBatchStart{};

// Both UAVs reported tick 4; the batch of tick 5 goes with the second report.
RelayBatch batch_after_tick_4() {
  RelayBatch b(milliseconds(200));
  b.add_report(1, 4, kBatchStart);
  b.add_report(2, 4, kBatchStart);
  b.sent();
  return b;
}

TEST(RelayBatch, ThePhasesReportsGoTogetherOnceEveryGatewayUavThatReportedThePhaseBeforeHasReportedThisOne) {
  const std::vector<uint32_t> gateway{1, 2};
  RelayBatch b = batch_after_tick_4();
  EXPECT_TRUE(b.due(gateway, kBatchStart)) << "nothing held: states alone go at once";
  b.add_report(1, 5, kBatchStart + milliseconds(3));
  EXPECT_FALSE(b.due(gateway, kBatchStart + milliseconds(4))) << "UAV 2 reported tick 4, not yet 5";
  b.add_report(2, 5, kBatchStart + milliseconds(9));
  EXPECT_TRUE(b.due(gateway, kBatchStart + milliseconds(9)));
  b.sent();
  EXPECT_TRUE(b.due(gateway, kBatchStart + milliseconds(10)));
  // A report of an older phase than the newest held goes at once (the
  // conductor may still wait for it), and moves no UAV back.
  b.add_report(1, 6, kBatchStart + milliseconds(20));
  EXPECT_FALSE(b.due(gateway, kBatchStart + milliseconds(20)));
  b.add_report(1, 5, kBatchStart + milliseconds(21));
  EXPECT_TRUE(b.due(gateway, kBatchStart + milliseconds(21)));
  b.sent();
  b.add_report(2, 7, kBatchStart + milliseconds(30));
  EXPECT_FALSE(b.due(gateway, kBatchStart + milliseconds(30))) << "UAV 1 reported tick 6, not 5";
  b.add_report(1, 7, kBatchStart + milliseconds(31));
  EXPECT_TRUE(b.due(gateway, kBatchStart + milliseconds(31)));
}

TEST(RelayBatch, AUavThatNeverReportedOrStoppedTwoPhasesAgoIsNotWaitedFor) {
  // UAV 3 is listed but never reported (not started, or homed here but
  // flying from its backup): not waited for.
  const std::vector<uint32_t> gateway{1, 2, 3};
  RelayBatch b = batch_after_tick_4();
  b.add_report(1, 5, kBatchStart);
  b.add_report(2, 5, kBatchStart);
  EXPECT_TRUE(b.due(gateway, kBatchStart));
  b.sent();
  // UAV 2 stops after tick 5: tick 6 waits for it the bound, 200 ms from
  // the first report held, not a millisecond less.
  b.add_report(1, 6, kBatchStart + milliseconds(100));
  EXPECT_FALSE(b.due(gateway, kBatchStart + milliseconds(299)));
  EXPECT_TRUE(b.due(gateway, kBatchStart + milliseconds(300)));
  b.sent();
  // Tick 7: UAV 2's newest report is of tick 5, two phases back: not waited for.
  b.add_report(1, 7, kBatchStart + milliseconds(400));
  EXPECT_TRUE(b.due(gateway, kBatchStart + milliseconds(400)));
}

TEST(RelayBatch, ADepartureGoesAtOnce) {
  const std::vector<uint32_t> gateway{1, 2};
  RelayBatch b = batch_after_tick_4();
  b.add_report(1, 5, kBatchStart);
  EXPECT_FALSE(b.due(gateway, kBatchStart));
  b.add_departure();
  EXPECT_TRUE(b.due(gateway, kBatchStart));
  b.sent();
  // Sent: the departure is not held any more.
  b.add_report(2, 5, kBatchStart + milliseconds(1));
  b.sent();
  b.add_report(1, 6, kBatchStart + milliseconds(2));
  EXPECT_FALSE(b.due(gateway, kBatchStart + milliseconds(2))) << "UAV 2's newest is tick 5: waited for in tick 6";
}

}  // namespace
}  // namespace pheromesh::core
