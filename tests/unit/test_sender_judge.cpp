// core/sender_judge.hpp: only names the run has, only from their holder
// (issue 42 D4-D5). A forger on an open domain can write any id and copy
// every field; what it cannot copy is its process.
#include <gtest/gtest.h>

#include <chrono>

#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/place_vouch.hpp"
#include "pheromesh/core/plausibility.hpp"
#include "pheromesh/core/sender_judge.hpp"

namespace pheromesh::core {
namespace sender_judge_test {  // named: the unit tests build as one unity source

using namespace std::chrono_literals;
using Clock = PlaceVouch::Clock;
const Clock::time_point t0 = Clock::time_point{} + 100s;

// 4 UAVs over 4 regions, without standbys (one place agent per region).
const SwarmNames kPlain{4, 4, replicas_of(false)};
const SwarmNames kStandbys{4, 4, replicas_of(true)};

PhaseDoneMsg report(uint32_t role, uint32_t id, uint64_t participant) {
  PhaseDoneMsg m;
  m.process = process_key(role, id);
  m.tick = 7;
  m.phase = static_cast<uint8_t>(ClockPhase::Uav);
  m.participant = participant;
  return m;
}

TEST(SenderJudge, APlaceIdTheRunDoesNotHaveIsRefusedAsUnknownPlace) {
  EXPECT_TRUE(check_place_id(3, 0, kPlain, "a health").taken());
  const auto standby = check_place_id(0, 1, kPlain, "a health");
  ASSERT_FALSE(standby.taken()) << "a standby replica in a swarm without standbys";
  EXPECT_EQ(standby.refusal, Refusal::UnknownPlace);
  EXPECT_NE(standby.reason.find("no standbys"), std::string::npos) << standby.reason;
  EXPECT_EQ(check_place_id(4, 0, kPlain, "a health").refusal, Refusal::UnknownPlace) << "a region beyond the map's";
  EXPECT_TRUE(check_place_id(0, 1, kStandbys, "a health").taken());
  EXPECT_FALSE(check_place_id(0, 2, kStandbys, "a health").taken()) << "one standby per region";
}

TEST(SenderJudge, AHealthOfAnUnknownPlaceIdLatchesNothingSoItsProcessIsNoPlaceAgent) {
  PlaceVouch v(2s);
  const auto forged = judge_place_sample(v, 0, 1, 0xF, t0, kPlain, false, "a health");
  EXPECT_EQ(forged.refusal, Refusal::UnknownPlace);
  EXPECT_FALSE(v.vouched(0xF)) << "refused: its process relays nothing on that strength";
  // The real place agent takes its id; a second process is refused for it.
  EXPECT_TRUE(judge_place_sample(v, 0, 0, 0xA, t0, kPlain, false, "a health").taken());
  EXPECT_TRUE(v.vouched(0xA));
  const auto impostor = judge_place_sample(v, 0, 0, 0xF, t0 + 100ms, kPlain, false, "a served-UAVs chunk");
  EXPECT_EQ(impostor.refusal, Refusal::ForeignWriter);
  EXPECT_NE(impostor.reason.find("a served-UAVs chunk of place agent 0"), std::string::npos) << impostor.reason;
  EXPECT_FALSE(v.vouched(0xF));
}

TEST(SenderJudge, APlaceAgentsReportIsTakenOnlyFromTheProcessThatHoldsItsId) {
  PlaceVouch v(10s);
  const SwarmNames names = kPlain;
  // Before its health: nobody to compare with (its Ready may come first).
  EXPECT_TRUE(judge_report(report(kRolePlace, place_id(2, 0), 0xB), v, names).taken());
  ASSERT_TRUE(v.claim(place_id(2, 0), 0xB, t0));
  EXPECT_TRUE(judge_report(report(kRolePlace, place_id(2, 0), 0xB), v, names).taken());
  const auto forged = judge_report(report(kRolePlace, place_id(2, 0), 0xF), v, names);
  EXPECT_EQ(forged.refusal, Refusal::ForeignReport);
  EXPECT_EQ(judge_report(report(kRolePlace, place_id(2, 1), 0xF), v, names).refusal, Refusal::UnknownPlace);
  EXPECT_EQ(judge_report(report(kRolePlace, place_id(9, 0), 0xF), v, names).refusal, Refusal::UnknownPlace);
}

TEST(SenderJudge, AUavsReportIsTakenOnlyFromAProcessOfItsHomeOrItsBackup) {
  PlaceVouch v(10s);
  ASSERT_TRUE(v.claim(place_id(1, 0), 0xA1, t0));  // UAV 1's home
  ASSERT_TRUE(v.claim(place_id(2, 0), 0xA2, t0));  // its backup
  ASSERT_TRUE(v.claim(place_id(3, 0), 0xA3, t0));
  ASSERT_TRUE(v.claim(place_id(0, 0), 0xA0, t0));
  EXPECT_TRUE(judge_report(report(kRoleUav, 1, 0xA1), v, kPlain).taken()) << "relayed by its home";
  EXPECT_TRUE(judge_report(report(kRoleUav, 1, 0xA2), v, kPlain).taken()) << "relayed by its backup";
  const auto other = judge_report(report(kRoleUav, 1, 0xA3), v, kPlain);
  EXPECT_EQ(other.refusal, Refusal::ForeignReport) << "another place agent's process";
  EXPECT_EQ(judge_report(report(kRoleUav, 1, 0xF), v, kPlain).refusal, Refusal::ForeignReport) << "a forger's";
  EXPECT_EQ(judge_report(report(kRoleUav, 9, 0xA1), v, kPlain).refusal, Refusal::UnknownUav);
  EXPECT_EQ(judge_report(report(5, 1, 0xA1), v, kPlain).kind, IntakeVerdict::Kind::Drop) << "no role";
  // Unknown (a transport that cannot tell): taken.
  EXPECT_TRUE(judge_report(report(kRoleUav, 1, 0), v, kPlain).taken());
}

TEST(SenderJudge, AStandbyOfTheUavsHomeRelaysItsReportToo) {
  PlaceVouch v(10s);
  ASSERT_TRUE(v.claim(place_id(1, 0), 0xA1, t0));
  ASSERT_TRUE(v.claim(place_id(1, 1), 0xB1, t0));
  ASSERT_TRUE(v.claim(place_id(2, 0), 0xA2, t0));
  ASSERT_TRUE(v.claim(place_id(2, 1), 0xB2, t0));
  EXPECT_TRUE(judge_report(report(kRoleUav, 1, 0xB1), v, kStandbys).taken());
  EXPECT_TRUE(judge_report(report(kRoleUav, 1, 0xB2), v, kStandbys).taken());
  EXPECT_FALSE(judge_report(report(kRoleUav, 1, 0xF), v, kStandbys).taken());
}

TEST(SenderJudge, AGatewayRelaysAUavsReportOrDetectionOnlyIfItCanServeItAndItCameFromTheUavsProcess) {
  EXPECT_TRUE(judge_uav_report(report(kRoleUav, 1, 0xC), 1, kPlain, true).taken()) << "its home";
  EXPECT_TRUE(judge_uav_report(report(kRoleUav, 1, 0xC), 2, kPlain, true).taken()) << "its backup";
  EXPECT_EQ(judge_uav_report(report(kRoleUav, 1, 0xC), 3, kPlain, true).refusal, Refusal::ForeignReport);
  EXPECT_EQ(judge_uav_report(report(kRoleUav, 1, 0xF), 1, kPlain, false).refusal, Refusal::ForeignReport)
      << "a process other than the one its states come from";
  EXPECT_EQ(judge_uav_report(report(kRoleUav, 7, 0xC), 3, kPlain, true).refusal, Refusal::UnknownUav);
  EXPECT_EQ(judge_uav_report(report(kRolePlace, 1, 0xC), 1, kPlain, true).kind, IntakeVerdict::Kind::Drop);
  // Detections: the same rule with their own reasons.
  EXPECT_EQ(
      judge_uplink("a detection", 1, 3, kPlain, true, Refusal::ImplausibleDetection, Refusal::ForeignWriter).refusal,
      Refusal::ImplausibleDetection);
  EXPECT_EQ(
      judge_uplink("a detection", 1, 1, kPlain, false, Refusal::ImplausibleDetection, Refusal::ForeignWriter).refusal,
      Refusal::ForeignWriter);
  EXPECT_TRUE(
      judge_uplink("a detection", 1, 1, kPlain, true, Refusal::ImplausibleDetection, Refusal::ForeignWriter).taken());
}

TEST(SenderJudge, ALockstepForwardedDepositIsTakenOnlyInThePlacePhaseOfItsTickAndNotByTheUavsGateway) {
  DepositMsg d;
  d.uav = 0;
  d.seq = 12;
  d.tick = 40;
  EXPECT_TRUE(judge_lockstep_forward(d, 40, false, false).taken());
  const auto late = judge_lockstep_forward(d, 41, false, false);
  EXPECT_EQ(late.refusal, Refusal::UnannouncedDeposit) << "never applied a tick late";
  EXPECT_NE(late.reason.find("of tick 40 forwarded in the place phase of tick 41"), std::string::npos) << late.reason;
  EXPECT_EQ(judge_lockstep_forward(d, 39, false, false).refusal, Refusal::UnannouncedDeposit) << "nor early";
  EXPECT_EQ(judge_lockstep_forward(d, 40, true, false).refusal, Refusal::ForeignWriter)
      << "its gateway takes its deposits from its states";
  EXPECT_EQ(judge_lockstep_forward(d, 41, true, true).refusal, Refusal::ForeignWriter) << "whatever it says";
  EXPECT_TRUE(judge_lockstep_forward(d, 41, false, true).taken())
      << "refused by the place core for what it says (a UAV outside the swarm, a seq far ahead), and counted so";
}

}  // namespace sender_judge_test
}  // namespace pheromesh::core
