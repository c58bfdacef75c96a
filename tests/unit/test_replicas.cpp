// The ground station's view of replicated place agents (RunRecorder):
// which replica serves a region, lost and resumed replicas, and the deposit
// accounting that counts what no place agent received.
#include <gtest/gtest.h>

#include "pheromesh/core/receipts.hpp"
#include "pheromesh/core/run_metrics.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/world.hpp"

namespace pheromesh::core {
namespace {

struct Rig {
  ScenarioConfig s;
  MapGeometry geo;
  World world;
  RunRecorder rec;
  Rig() : s(make()), geo(s.geometry()), world(geo, s.obstacles, s.targets), rec(s, world) {}
  static ScenarioConfig make() {
    ScenarioConfig c;
    c.width = 20;
    c.height = 20;
    c.tile_size = 10;
    c.regions_x = 2;
    c.regions_y = 1;
    c.uavs = 2;
    c.start_area = {0, 0, 20, 20};
    return c;
  }
  static HealthMsg health(RegionId r, uint16_t replica, uint64_t received) {
    HealthMsg h;
    h.region = r;
    h.replica = replica;
    h.deposits_received = received;
    h.deposits_applied = received;
    return h;
  }
  bool sent(uint32_t uav, uint64_t n, uint64_t unconfirmed = 0, uint32_t tick = 0, bool finished = false) {
    UavStateMsg st;
    st.uav = uav;
    st.tick = tick;
    st.finished = finished;
    // At its start cell: the recorder refuses a state the UAV cannot have flown to.
    st.x = start_cell(s, uav).x;
    st.y = start_cell(s, uav).y;
    st.deposits_sent = n;
    st.deposits_unconfirmed = unconfirmed;
    return rec.on_uav_state(st);
  }
};

TEST(Replicas, TheLowestLiveReplicaServesTheRegionAndAStandbyTakesOver) {
  Rig rig;
  rig.rec.on_health(Rig::health(0, 0, 10));
  rig.rec.on_health(Rig::health(0, 1, 10));
  rig.rec.on_health(Rig::health(1, 0, 5));
  EXPECT_EQ(rig.rec.region_owner(0), std::optional<uint16_t>(0));
  EXPECT_EQ(rig.rec.replicas_alive(0), 2U);
  EXPECT_EQ(rig.rec.regions_alive(), 2U);
  rig.rec.on_place_departed(place_id(0, 0));
  EXPECT_EQ(rig.rec.region_owner(0), std::optional<uint16_t>(1)) << "the standby serves region 0";
  EXPECT_FALSE(rig.rec.region_departed(0));
  EXPECT_EQ(rig.rec.regions_alive(), 2U) << "places N/M counts regions with a live replica";
  rig.rec.on_place_departed(place_id(1, 0));
  EXPECT_TRUE(rig.rec.region_departed(1));
  EXPECT_EQ(rig.rec.regions_alive(), 1U);
  EXPECT_FALSE(rig.rec.region_owner(1).has_value());
}

TEST(Replicas, APlaceAgentStartedAgainKeepsWhatItsDeadLifeCounted) {
  // A restarted place agent counts from 0. Its new life's records used to
  // replace the dead life's: the run's applied deposits fell 109,140 ->
  // 86,823 at the restart and the soak reported the difference "lost"
  // (issue 28).
  Rig rig;
  HealthMsg h = Rig::health(0, 0, 100);
  h.deposits_rejected = 4;
  h.refused[0] = 2;
  h.tick_gap_max_ms = 900;
  rig.rec.on_health(h);
  HealthMsg second = Rig::health(0, 0, 3);  // the new life's first record
  second.life = 2;
  rig.rec.on_health(second);
  EXPECT_EQ(rig.rec.health().at(0).deposits_received, 103U);
  EXPECT_EQ(rig.rec.health().at(0).deposits_applied, 103U);
  EXPECT_EQ(rig.rec.health().at(0).deposits_rejected, 4U);
  EXPECT_EQ(rig.rec.health().at(0).refused[0], 2U);
  EXPECT_EQ(rig.rec.health().at(0).tick_gap_max_ms, 900U);
  second.deposits_received = second.deposits_applied = 50;  // the new life goes on
  rig.rec.on_health(second);
  EXPECT_EQ(rig.rec.health().at(0).deposits_applied, 150U);
  rig.rec.on_health(Rig::health(0, 0, 100));  // a late record of the dead life changes nothing
  EXPECT_EQ(rig.rec.health().at(0).deposits_applied, 150U);
  EXPECT_EQ(rig.rec.replica_health().at(place_id(0, 0)).deposits_applied, 150U);
  HealthMsg third = Rig::health(0, 0, 1);
  third.life = 3;
  rig.rec.on_health(third);
  EXPECT_EQ(rig.rec.health().at(0).deposits_applied, 151U);
  // Guard: records of one life, even out of order, bank nothing.
  Rig calm;
  calm.rec.on_health(Rig::health(1, 0, 12));
  calm.rec.on_health(Rig::health(1, 0, 10));
  EXPECT_EQ(calm.rec.health().at(1).deposits_applied, 10U) << "the latest record; 22 would bank a life that never ended";
}

TEST(Replicas, AReplicaHeardAgainAfterItWasLostIsAliveAndOwnsAgain) {
  Rig rig;
  rig.rec.on_health(Rig::health(0, 0, 3));
  rig.rec.on_health(Rig::health(0, 1, 3));
  rig.rec.on_place_departed(place_id(0, 0));  // SIGSTOP: its lease ran out
  EXPECT_TRUE(rig.rec.place_departed(place_id(0, 0)));
  EXPECT_FALSE(rig.rec.on_health(Rig::health(0, 1, 4))) << "the standby was never lost";
  EXPECT_TRUE(rig.rec.on_health(Rig::health(0, 0, 4))) << "SIGCONT: the primary is back";
  EXPECT_FALSE(rig.rec.place_departed(place_id(0, 0)));
  EXPECT_EQ(rig.rec.region_owner(0), std::optional<uint16_t>(0));
}

TEST(Replicas, TheRegionsCountsAreTheReplicaThatReceivedMost) {
  Rig rig;
  // The primary died after 40 deposits; its standby received all 100.
  rig.rec.on_health(Rig::health(0, 0, 40));
  rig.rec.on_health(Rig::health(0, 1, 100));
  EXPECT_EQ(rig.rec.health().at(0).deposits_received, 100U);
  EXPECT_EQ(rig.rec.health().at(0).replica, 1U);
  // A later health of the same replica replaces its own earlier one.
  rig.rec.on_health(Rig::health(0, 1, 101));
  EXPECT_EQ(rig.rec.health().at(0).deposits_received, 101U);
}

TEST(Replicas, DepositsNoPlaceAgentCountedAreLostAndTheUavsOwnCountIsKept) {
  Rig rig;
  rig.sent(0, 70, 0);
  rig.sent(1, 50, 12);  // 12 never confirmed by its home
  rig.rec.on_health(Rig::health(0, 0, 60));
  rig.rec.on_health(Rig::health(1, 0, 48));
  EXPECT_EQ(rig.rec.deposits_sent(), 120U);
  EXPECT_EQ(rig.rec.deposits_lost(), 12U) << "120 sent, 108 received";
  EXPECT_EQ(rig.rec.deposits_unconfirmed_by_uavs(), 12U);
  rig.rec.on_health(Rig::health(1, 0, 60));
  EXPECT_EQ(rig.rec.deposits_lost(), 0U) << "balanced";
}

// Both replicas of a home relay its UAVs' states, and so does a backup: the
// copies of two writers arrive in any order. An older one after a newer one
// once lowered a UAV's deposits_sent by 52 (applied 3165 > sent 3113, CI).
TEST(Replicas, AnOlderStateArrivingLateKeepsTheUavsNewerCountButARestartStartsANewLife) {
  Rig rig;
  EXPECT_TRUE(rig.sent(0, 10, 0, /*tick=*/5));
  EXPECT_TRUE(rig.sent(0, 12, 0, 6));
  EXPECT_TRUE(rig.sent(0, 11, 0, 5)) << "a copy of tick 5 from the other replica: heard, not refused";
  EXPECT_TRUE(rig.sent(0, 10, 0, 6)) << "same tick, fewer deposits: an older copy too";
  EXPECT_EQ(rig.rec.deposits_sent(), 12U);
  EXPECT_EQ(rig.rec.uavs().at(0).last.tick, 6U);
  EXPECT_EQ(rig.rec.states_stale(), 2U);
  // Lost, then heard from tick 0 with a count from 0: the next process
  // (realtime ticks start again), whose deposits add to the earlier life's.
  rig.rec.on_uav_departed(0);
  EXPECT_TRUE(rig.sent(0, 3, 0, 0));
  EXPECT_EQ(rig.rec.deposits_sent(), 15U);
  EXPECT_EQ(rig.rec.states_stale(), 2U);
  // A finished UAV flies no more: after its departure an older copy is one.
  EXPECT_TRUE(rig.sent(1, 20, 0, 8, /*finished=*/true));
  rig.rec.on_uav_departed(1);
  EXPECT_TRUE(rig.sent(1, 19, 0, 7));
  EXPECT_EQ(rig.rec.deposits_sent(), 35U) << "uav 0: 12 + 3, uav 1: 20";
  EXPECT_EQ(rig.rec.states_stale(), 3U);
}

}  // namespace
}  // namespace pheromesh::core

namespace pheromesh::core {
namespace {

TEST(DepositReceipts, ADepositStaysUnconfirmedUntilTheHomeAcknowledgesItsSeq) {
  DepositReceipts r;
  for (uint32_t seq : {1U, 2U, 5U, 9U}) r.sent(seq);
  EXPECT_EQ(r.unconfirmed(), 4U);
  r.confirmed(0, 0);  // a view before any deposit arrived
  EXPECT_EQ(r.unconfirmed(), 4U);
  r.confirmed(1, 5);
  EXPECT_EQ(r.unconfirmed(), 1U) << "1, 2 and 5 confirmed";
  r.confirmed(1, 3);  // an older view arriving late changes nothing
  EXPECT_EQ(r.unconfirmed(), 1U);
  r.sent((1U << 24U) + 1);  // a restarted life's numbering
  r.confirmed(1, 9);
  EXPECT_EQ(r.unconfirmed(), 1U);
  r.confirmed(1, (1U << 24U) + 1);
  EXPECT_EQ(r.unconfirmed(), 0U);
}

TEST(DepositReceipts, WhatADeadHomeNeverConfirmedStaysUnconfirmedWhenTheBackupConfirmsLaterOnes) {
  DepositReceipts r;
  for (uint32_t seq : {1U, 2U, 3U}) r.sent(seq);
  r.confirmed(1, 1);
  r.abandon();  // the home died with 2 and 3; the UAV moves to its backup
  EXPECT_EQ(r.unconfirmed(), 2U);
  EXPECT_EQ(r.pending(), 0U) << "nothing left for the backup to confirm";
  r.sent(4);
  r.confirmed(4, 4);  // the backup's cumulative ack covers 4 only
  EXPECT_EQ(r.unconfirmed(), 2U);
  EXPECT_EQ(r.pending(), 0U);
}

TEST(DepositReceipts, DepositsSentWhileTheHomeWasDeadStayUnconfirmedWhenItsNewLifeConfirmsLaterOnes) {
  // The home place agent dies after it received 1 and 2 and starts again
  // (pheromesh run --faults "restart place:R ..."): its new life reads no
  // history, so 3 and 4, written while it was dead, never reach it. The
  // first it receives is 5: its views say "from 5 up to 6".
  DepositReceipts r;
  for (uint32_t seq : {1U, 2U}) r.sent(seq);
  r.confirmed(1, 2);
  for (uint32_t seq : {3U, 4U, 5U, 6U}) r.sent(seq);
  r.confirmed(5, 6);
  EXPECT_EQ(r.unconfirmed(), 2U) << "3 and 4 never arrived; a cumulative ack of 6 alone would have confirmed them";
  EXPECT_EQ(r.pending(), 0U);
  r.sent(7);
  r.confirmed(5, 7);
  EXPECT_EQ(r.unconfirmed(), 2U);
}

TEST(HomeAcks, ThePlaceAgentConfirmsFromTheFirstDepositItReceivedOfEachUav) {
  HomeAcks a;
  EXPECT_EQ(a.ack_from(3), 0U) << "nothing received: confirms nothing";
  EXPECT_EQ(a.ack(3), 0U);
  a.received(3, 40, 10);  // a new life: the first it got of uav 3
  a.received(3, 41, 10);
  a.received(3, 42, 11);
  EXPECT_EQ(a.ack_from(3), 40U);
  EXPECT_EQ(a.ack(3), 42U);
  a.received(3, 39, 11);  // older, late: not a new start
  EXPECT_EQ(a.ack_from(3), 40U);
  EXPECT_EQ(a.ack(3), 42U);
}

}  // namespace
}  // namespace pheromesh::core
