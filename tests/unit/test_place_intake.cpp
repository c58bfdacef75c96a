// core::PlaceIntake (issue 43 D1): a place agent's judgement of the samples
// it receives - its UAVs' states and their writers, what the UAVs send up,
// the deposits other place agents forward, the served-UAVs chunks and halo
// rings of the other place agents - with time passed in, no DDS. And the
// tile join of core::ViewServer (tiles_for, owners_for).
#include <gtest/gtest.h>

#include <chrono>
#include <vector>

#include "pheromesh/core/intake.hpp"
#include "pheromesh/core/place_intake.hpp"
#include "pheromesh/core/view_server.hpp"

namespace pheromesh::core {
namespace place_intake_test {  // named: the unit tests build as one unity source

using namespace std::chrono_literals;
using Clock = PlaceIntake::Clock;
const Clock::time_point t0 = Clock::time_point{} + 100s;

// 4 regions (2x2) of a 30x30 map, 8 UAVs: region 1 is the home of UAVs 1
// and 5 and the backup of UAVs 0 and 4.
struct Swarm {
  MapGeometry geo{30, 30, 6, 2, 2};
  std::vector<ValueRange> ranges{{0.0F, 1000.0F}};
  IntakeRules rules{geo, 1, ranges, 8};
  SwarmNames names{8, 4, 1};
  PlaceIntake::Setup setup(bool lockstep) const { return {1, names, lockstep, 1s, 2s}; }
};

UavStateMsg state_of(uint32_t uav, uint32_t tick, double x, double y, uint64_t writer) {
  UavStateMsg s;
  s.uav = uav;
  s.tick = tick;
  s.x = x;
  s.y = y;
  s.view = {static_cast<int32_t>(x), static_cast<int32_t>(y)};
  s.writer = writer;
  s.participant = writer >> 8U;
  return s;
}

DepositMsg deposit_of(uint32_t uav, uint32_t seq, uint32_t tick, uint64_t participant) {
  DepositMsg d;
  d.uav = uav;
  d.seq = seq;
  d.tick = tick;
  d.region = 1;
  d.participant = participant;
  return d;
}

PlaceIntake::StateCall judge(PlaceIntake& in, const Swarm& s, const UavStateMsg& st, Clock::time_point now,
                             const UavStateMsg* before = nullptr, bool adopted = false, std::size_t carried = 0) {
  return in.judge_state(st, carried, before, adopted, {st.view.x, st.view.y}, 1.5, 1000, s.rules, now);
}

TEST(PlaceIntake, AHomeUavsStateFromItsFirstWriterIsTakenAndAnotherWritersIsRefusedWithItsDeposits) {
  Swarm s;
  PlaceIntake in(s.setup(false));
  const UavStateMsg first = state_of(1, 0, 10, 2, 0xA01);
  const auto a = judge(in, s, first, t0);
  EXPECT_TRUE(a.verdict.taken());
  EXPECT_TRUE(a.accept);
  EXPECT_FALSE(a.adopt);
  EXPECT_EQ(a.carried, CarriedDeposits::Judge);
  in.accept_state(first, t0);
  const auto b = judge(in, s, state_of(1, 1, 10, 3, 0xF01), t0 + 100ms, &first, false, 2);
  EXPECT_EQ(b.verdict.kind, IntakeVerdict::Kind::Refuse);
  EXPECT_EQ(b.verdict.refusal, Refusal::ForeignWriter);
  EXPECT_NE(b.verdict.reason.find("and the 2 deposits it carried"), std::string::npos) << b.verdict.reason;
  EXPECT_FALSE(b.carried) << "a forger's deposits go with its refused state";
  EXPECT_FALSE(b.accept);
}

TEST(PlaceIntake, AWriterSilentForTheTakeoverTimeGivesItsUavUpAndOneHeardInTheSameTakeDoesNot) {
  Swarm s;
  PlaceIntake in(s.setup(false));
  const UavStateMsg first = state_of(1, 0, 10, 2, 0xA01);
  ASSERT_TRUE(judge(in, s, first, t0).accept);
  in.accept_state(first, t0);
  // The holder's own sample queued in the same take keeps it alive.
  const std::vector<UavStateMsg> take{state_of(1, 20, 10, 3, 0xF01), state_of(1, 20, 10, 3, 0xA01)};
  in.heard_states(take, t0 + 1500ms);
  EXPECT_FALSE(judge(in, s, take[0], t0 + 1500ms, &first).accept);
  // Silent for longer than the takeover time (1 s): a restarted UAV is a new writer.
  EXPECT_TRUE(judge(in, s, take[0], t0 + 2600ms, &first).accept);
}

TEST(PlaceIntake, AStateAtAPlaceAgentThatIsNeitherItsHomeNorItsBackupIsRefusedAsImplausible) {
  Swarm s;
  PlaceIntake in(s.setup(false));
  const auto c = judge(in, s, state_of(2, 0, 10, 2, 0xA02), t0, nullptr, false, 1);
  EXPECT_EQ(c.verdict.refusal, Refusal::ImplausibleState);
  EXPECT_NE(c.verdict.reason.find("neither its home nor its backup, and the 1 deposit it carried"), std::string::npos)
      << c.verdict.reason;
  EXPECT_FALSE(c.carried);
  EXPECT_FALSE(c.adopt);
}

TEST(PlaceIntake, ABackupIsAdoptedByItsFirstStateRealtimeAndOnlyByTheClockInLockstep) {
  Swarm s;
  PlaceIntake realtime(s.setup(false));
  const auto r = judge(realtime, s, state_of(4, 0, 10, 2, 0xA04), t0);
  EXPECT_TRUE(r.adopt);
  EXPECT_TRUE(r.accept);
  PlaceIntake lockstep(s.setup(true));
  const auto waiting = judge(lockstep, s, state_of(4, 0, 10, 2, 0xA04), t0, nullptr, /*adopted=*/false);
  EXPECT_FALSE(waiting.adopt);
  EXPECT_FALSE(waiting.accept) << "its state counts from the tick its home is absent";
  EXPECT_TRUE(waiting.verdict.taken()) << "and nothing is counted";
  EXPECT_EQ(waiting.carried, CarriedDeposits::Judge) << "its deposits go on as any";
  EXPECT_TRUE(judge(lockstep, s, state_of(4, 0, 10, 2, 0xA04), t0, nullptr, /*adopted=*/true).accept);
}

TEST(PlaceIntake, AStateThatSaysItDepartedOrWasRefusedIsDroppedAndItsDepositsGoOn) {
  Swarm s;
  PlaceIntake in(s.setup(false));
  UavStateMsg st = state_of(1, 0, 10, 2, 0xA01);
  st.departed = true;
  const auto c = judge(in, s, st, t0);
  EXPECT_EQ(c.verdict.kind, IntakeVerdict::Kind::Drop);
  EXPECT_EQ(c.verdict.reason, "a state of uav 1 that says it departed (only a place agent says so)");
  EXPECT_EQ(c.carried, CarriedDeposits::Judge);
  EXPECT_FALSE(c.accept);
}

TEST(PlaceIntake, AStateFurtherThanMaxStepIsAnsweredCountedOnceAndItsDepositsRejected) {
  Swarm s;
  PlaceIntake in(s.setup(true));
  const UavStateMsg first = state_of(1, 0, 10, 2, 0xA01);
  ASSERT_TRUE(judge(in, s, first, t0).accept);
  in.accept_state(first, t0);
  const UavStateMsg leap = state_of(1, 1, 17, 2, 0xA01);
  const auto a = in.judge_state(leap, 3, &first, false, {10, 2}, 1.5, 1000, s.rules, t0 + 1s);
  EXPECT_TRUE(a.answer);
  EXPECT_FALSE(a.accept);
  EXPECT_EQ(a.verdict.refusal, Refusal::ImplausibleState);
  EXPECT_EQ(a.carried, CarriedDeposits::Reject);
  EXPECT_EQ(in.refused_tick(1), 1U);
  const auto copy = in.judge_state(leap, 3, &first, false, {10, 2}, 1.5, 1000, s.rules, t0 + 2s);
  EXPECT_TRUE(copy.answer) << "answered again";
  EXPECT_TRUE(copy.verdict.taken()) << "not counted again";
  EXPECT_EQ(copy.carried, CarriedDeposits::Reject);
}

TEST(PlaceIntake, AStateOfAUavOutsideTheSwarmIsRefusedWithItsDepositsRefused) {
  Swarm s;
  PlaceIntake in(s.setup(false));
  const auto c = judge(in, s, state_of(41, 0, 10, 2, 0xA29), t0);
  EXPECT_EQ(c.verdict.refusal, Refusal::UnknownUav);
  EXPECT_EQ(c.carried, CarriedDeposits::Refuse);
}

TEST(PlaceIntake, WhatAUavSendsUpIsRelayedOnlyFromItsOwnProcessWhileItsWriterIsHeard) {
  Swarm s;
  PlaceIntake in(s.setup(false));
  const UavStateMsg st = state_of(1, 0, 10, 2, 0xA01);  // process 0xA
  in.accept_state(st, t0);
  DetectionMsg d;
  d.uav = 1;
  d.participant = 0xB;
  EXPECT_EQ(in.judge_detection(d, t0 + 100ms).refusal, Refusal::ForeignWriter);
  d.participant = 0xA;
  EXPECT_TRUE(in.judge_detection(d, t0 + 100ms).taken());
  d.participant = 0xB;
  EXPECT_TRUE(in.judge_detection(d, t0 + 1500ms).taken()) << "its writer silent past the takeover time";
  d.uav = 2;  // neither home nor backup here
  EXPECT_EQ(in.judge_detection(d, t0).refusal, Refusal::ImplausibleDetection);

  BroadcastMsg b;
  b.uav = 1;
  b.participant = 0xB;
  EXPECT_EQ(in.judge_broadcast(b, /*up=*/true, t0 + 100ms).refusal, Refusal::ForeignWriter);
  EXPECT_TRUE(in.judge_broadcast(b, /*up=*/false, t0 + 100ms).taken()) << "the swarm's, down: any process";
  b.uav = 8;
  EXPECT_EQ(in.judge_broadcast(b, false, t0).refusal, Refusal::UnknownUav);
  b.uav = 1;
  b.kind = 200;
  EXPECT_EQ(in.judge_broadcast(b, false, t0).kind, IntakeVerdict::Kind::Drop);

  in.departed(1);
  d.uav = 1;
  EXPECT_TRUE(in.judge_detection(d, t0 + 100ms).taken()) << "departed: no process latched";
}

PlaceIntake::Forwarded forwarded_at(uint32_t tick, Clock::time_point now, bool last = false) {
  PlaceIntake::Forwarded f;
  f.tick = tick;
  f.now = now;
  f.last = last;
  f.refused_anyway = [](const DepositMsg& d) { return d.seq > 1000; };
  f.is_copy = [](const DepositMsg& d) { return d.seq == 7; };
  f.gateway_of = [](uint32_t uav) { return uav == 1 || uav == 5; };
  return f;
}

FieldMsg served_chunk(RegionId region, uint64_t participant) {
  FieldMsg f;
  f.region = region;
  f.participant = participant;
  return f;
}

TEST(PlaceIntake, RealtimeAForwardedDepositWaitsForItsProcessToBeHeardAsAPlaceAgent) {
  Swarm s;
  PlaceIntake in(s.setup(false));
  std::vector<IntakeVerdict> refusals;
  // Forwarded by process 0xC before it was heard as a place agent: parked.
  std::vector<DepositMsg> taken{deposit_of(1, 1, 0, 0), deposit_of(2, 1, 0, 0xC), deposit_of(3, 2000, 0, 0xC)};
  in.judge_forwarded(taken, 1, forwarded_at(0, t0), refusals);
  ASSERT_EQ(taken.size(), 2U) << "the carried one and the one refused anyway stay";
  EXPECT_EQ(taken[1].uav, 3U);
  EXPECT_TRUE(refusals.empty());
  // 0xC writes region 2's served UAVs: it is a place agent now.
  ASSERT_TRUE(in.judge_served_chunk(served_chunk(2, 0xC), t0 + 100ms).taken());
  taken = {deposit_of(3, 1, 0, 0xC)};
  in.judge_forwarded(taken, 0, forwarded_at(0, t0 + 200ms), refusals);
  ASSERT_EQ(taken.size(), 2U);
  EXPECT_EQ(taken[0].uav, 2U) << "the parked one first";
  EXPECT_EQ(taken[1].uav, 3U);
  EXPECT_TRUE(refusals.empty());
  // A forger's served chunk for a held id latches nothing.
  EXPECT_EQ(in.judge_served_chunk(served_chunk(2, 0xF), t0 + 300ms).refusal, Refusal::ForeignWriter);
  EXPECT_EQ(in.judge_served_chunk(served_chunk(9, 0xF), t0 + 300ms).refusal, Refusal::UnknownPlace);
}

TEST(PlaceIntake, RealtimeAForwardedDepositOfAProcessNeverHeardIsRefusedAfterTheParkingTimeOrAtTheDrain) {
  Swarm s;
  PlaceIntake in(s.setup(false));  // park for 2 s + 2 s
  std::vector<IntakeVerdict> refusals;
  std::vector<DepositMsg> taken{deposit_of(2, 1, 0, 0xF)};
  in.judge_forwarded(taken, 0, forwarded_at(0, t0), refusals);
  EXPECT_TRUE(taken.empty());
  taken = {deposit_of(2, 2, 0, 0xF)};
  in.judge_forwarded(taken, 0, forwarded_at(0, t0 + 3s), refusals);
  EXPECT_TRUE(refusals.empty()) << "3 s: still waits";
  taken = {deposit_of(2, 3, 0, 0xF)};
  in.judge_forwarded(taken, 0, forwarded_at(0, t0 + 4100ms), refusals);
  ASSERT_EQ(refusals.size(), 1U) << "the first, parked 4.1 s";
  EXPECT_EQ(refusals[0].refusal, Refusal::ForeignWriter);
  EXPECT_EQ(refusals[0].reason,
            "a deposit of uav 2 (seq 1) forwarded by a process that is no place agent's: its process was never heard "
            "as a place agent");
  taken.clear();
  in.judge_forwarded(taken, 0, forwarded_at(0, t0 + 4200ms, /*last=*/true), refusals);
  EXPECT_EQ(refusals.size(), 3U) << "the drain refuses what still waits";
  EXPECT_TRUE(taken.empty());
}

TEST(PlaceIntake, LockstepAForwardedDepositIsTakenOnlyOfThisTickAndNotByTheUavsGateway) {
  Swarm s;
  PlaceIntake in(s.setup(true));
  std::vector<IntakeVerdict> refusals;
  std::vector<DepositMsg> taken{
      deposit_of(5, 1, 3, 0),      // carried by its state (before `first`)
      deposit_of(2, 1, 3, 0xF),    // this tick's: taken (no vouching in lockstep)
      deposit_of(5, 2, 3, 0xC),    // forwarded to its own gateway: refused
      deposit_of(2, 2, 2, 0xC),    // of another tick: refused
      deposit_of(2, 7, 2, 0xC),    // a copy: the desk drops it
      deposit_of(2, 2000, 2, 0xC)  // refused anyway: the place core counts it
  };
  in.judge_forwarded(taken, 1, forwarded_at(3, t0), refusals);
  ASSERT_EQ(taken.size(), 4U);
  EXPECT_EQ(taken[1].seq, 1U);
  EXPECT_EQ(taken[2].seq, 7U);
  EXPECT_EQ(taken[3].seq, 2000U);
  ASSERT_EQ(refusals.size(), 2U);
  EXPECT_EQ(refusals[0].refusal, Refusal::ForeignWriter);
  EXPECT_EQ(refusals[1].refusal, Refusal::UnannouncedDeposit);
}

TEST(PlaceIntake, ALockstepHaloRingIsTakenOnlyOfThisTickAndOfAPresentNeighbour) {
  HaloMsg h;
  h.region = 3;
  h.tick = 5;
  EXPECT_TRUE(judge_halo(h, 5, true, false, 6)->taken());
  EXPECT_FALSE(judge_halo(h, 6, true, false, 7)) << "a late re-send: no news";
  EXPECT_FALSE(judge_halo(h, 5, true, /*region_absent=*/true, 6));
  EXPECT_EQ(judge_halo(h, 4, true, false, 5)->refusal, Refusal::TickFarAhead);
  EXPECT_TRUE(judge_halo(h, 9, false, false, 100)->taken()) << "realtime: whatever arrived";
  EXPECT_EQ(judge_halo(h, 9, false, false, 4)->refusal, Refusal::TickFarAhead) << "beyond what the run reached";
}

TEST(ViewServerTileJoin, AnOwnerSendsAHomeExactlyItsTilesThatTheHomesServedUavsViewsNeed) {
  const MapGeometry geo{24, 12, 6, 2, 1};  // regions 0 (x 0..11) and 1 (x 12..23), tiles of 6 cells
  ViewServer views(geo, 1, 2.0);
  // Region 0 serves UAV 0 at (11, 5): its view needs tiles (1..2, 0..1).
  FieldMsg served;
  served.region = 0;
  served.tick = 4;
  served.uavs.push_back(state_of(0, 4, 11, 5, 0));
  views.update_served(served, 4);
  std::vector<TileMsg> own;  // region 1's tiles: x 2..3, y 0..1, two layers each
  for (int32_t ty = 0; ty < 2; ++ty) {
    for (int32_t tx = 2; tx < 4; ++tx) {
      for (uint8_t layer = 0; layer < 2; ++layer) {
        TileMsg t;
        t.tile = {tx, ty};
        t.layer = layer;
        own.push_back(t);
      }
    }
  }
  std::vector<TileMsg> out;
  views.tiles_for(0, 0, 0, own, out);
  ASSERT_EQ(out.size(), 4U) << "tiles (2,0) and (2,1), both layers";
  EXPECT_EQ(out[0].tile.tx, 2);
  EXPECT_EQ(out[0].tile.ty, 0);
  EXPECT_EQ(out[1].layer, 1);
  EXPECT_EQ(out[2].tile.ty, 1);
  out.clear();
  views.tiles_for(0, /*heard_since=*/5, 0, own, out);
  EXPECT_TRUE(out.empty()) << "a home not heard since: nobody's views";
  views.tiles_for(1, 0, 0, own, out);
  EXPECT_TRUE(out.empty()) << "a region that serves nobody";

  views.update_state(state_of(7, 4, 11, 5, 0));
  views.update_state(state_of(6, 4, 2, 5, 0));
  EXPECT_EQ(views.owners_for(std::vector<uint32_t>{7}, 0, 0), std::vector<RegionId>{1});
  EXPECT_EQ(views.owners_for(std::vector<uint32_t>{7}, 0, 1), std::vector<RegionId>{0});
  EXPECT_TRUE(views.owners_for(std::vector<uint32_t>{6}, 0, 0).empty()) << "its own region is no owner to wait for";
  EXPECT_EQ(views.owners_for(std::vector<uint32_t>{6}, /*margin=*/10, 0), std::vector<RegionId>{1})
      << "widened by a margin, its view reaches region 1";
}

}  // namespace place_intake_test
}  // namespace pheromesh::core
