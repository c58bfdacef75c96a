// A UAV's lockstep report, made by its gateway from the UAV's state
// (core/uplink_reports.hpp).
#include "pheromesh/core/uplink_reports.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace pheromesh::core {
namespace {

UavStateMsg state(uint32_t uav, uint32_t tick, uint32_t tick_deposits, uint8_t broadcasts = 0) {
  UavStateMsg s;
  s.uav = uav;
  s.tick = tick;
  s.tick_deposits = tick_deposits;
  s.broadcasts = broadcasts;
  return s;
}

DepositMsg deposit(uint32_t uav, uint32_t seq, uint32_t tick, RegionId region) {
  DepositMsg d;
  d.uav = uav;
  d.seq = seq;
  d.tick = tick;
  d.region = region;
  return d;
}

TEST(UplinkReports, AStateWithItsWholeUplinkIsReportedWithItsDepositsPerRegionAndItsBroadcast) {
  UplinkReports r;
  const std::vector<DepositMsg> carried{deposit(3, 10, 7, 2), deposit(3, 11, 7, 0), deposit(3, 12, 7, 2)};
  const auto done = r.on_state(state(3, 7, 3, 1), carried);
  ASSERT_TRUE(done.has_value());
  EXPECT_EQ(done->process, process_key(kRoleUav, 3));
  EXPECT_EQ(done->tick, 7U);
  EXPECT_EQ(done->phase, static_cast<uint8_t>(ClockPhase::Uav));
  EXPECT_EQ(done->broadcasts, 1U);
  ASSERT_EQ(done->deposits.size(), 2U);
  EXPECT_EQ(done->deposits[0].region, 0U);
  EXPECT_EQ(done->deposits[0].count, 1U);
  EXPECT_EQ(done->deposits[1].region, 2U);
  EXPECT_EQ(done->deposits[1].count, 2U);
  // A state of a tick without deposits is its own whole uplink.
  const auto quiet = r.on_state(state(3, 8, 0), {});
  ASSERT_TRUE(quiet.has_value());
  EXPECT_EQ(quiet->tick, 8U);
  EXPECT_TRUE(quiet->deposits.empty());
  EXPECT_EQ(quiet->broadcasts, 0U);
}

TEST(UplinkReports, AnUplinkOfSeveralSamplesIsReportedOnceItsLastDepositIsHereAndACopyCountsOnce) {
  // 70 deposits: 64 in the first sample, 6 in the second (uplink_samples).
  UplinkReports r;
  std::vector<DepositMsg> first, second;
  for (uint32_t i = 0; i < 64; ++i) first.push_back(deposit(5, 100 + i, 2, i % 2));
  for (uint32_t i = 64; i < 70; ++i) second.push_back(deposit(5, 100 + i, 2, 1));
  EXPECT_FALSE(r.on_state(state(5, 2, 70), first).has_value()) << "6 deposits are still on the way";
  EXPECT_FALSE(r.on_state(state(5, 2, 70), first).has_value()) << "a copy of the first sample adds nothing";
  const auto done = r.on_state(state(5, 2, 70), second);
  ASSERT_TRUE(done.has_value());
  ASSERT_EQ(done->deposits.size(), 2U);
  EXPECT_EQ(done->deposits[0].count, 32U);
  EXPECT_EQ(done->deposits[1].count, 38U);
  // The UAV re-sends its state while it waits: its report goes again.
  const auto again = r.on_state(state(5, 2, 70), second);
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(again->deposits[1].count, 38U) << "the copy counts nothing twice";
}

TEST(UplinkReports, AnOlderStateIsNotReportedAndADepositOfAnotherUavCountsForNone) {
  UplinkReports r;
  ASSERT_TRUE(r.on_state(state(1, 4, 0), {}).has_value());
  EXPECT_FALSE(r.on_state(state(1, 3, 0), {}).has_value()) << "tick 3 is over";
  const std::vector<DepositMsg> stray{deposit(2, 1, 5, 0)};
  EXPECT_FALSE(r.on_state(state(1, 5, 1), stray).has_value()) << "uav 2's deposit is no part of uav 1's uplink";
  const std::vector<DepositMsg> own{deposit(1, 9, 5, 0)};
  EXPECT_TRUE(r.on_state(state(1, 5, 1), own).has_value());
}

TEST(UplinkReports, ARefusedStateIsReportedAtOnceWithItsBroadcastAndNoDeposit) {
  UavStateMsg s = state(4, 6, 12, 1);
  const PhaseDoneMsg done = UplinkReports::on_refused(s);
  EXPECT_EQ(done.process, process_key(kRoleUav, 4));
  EXPECT_EQ(done.tick, 6U);
  EXPECT_EQ(done.broadcasts, 1U);
  EXPECT_TRUE(done.deposits.empty()) << "its gateway rejects the deposits it carried; none is announced";
}

}  // namespace
}  // namespace pheromesh::core
