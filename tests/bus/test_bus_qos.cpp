// The neutral QoS description means the same on both vendors: each vendor's
// translation, read back from the vendor's own QoS object, gives the table.
#include <gtest/gtest.h>

#include "cyclone_bus.hpp"
#include "fastdds_bus.hpp"
#include "pheromesh/bus/qos.hpp"

using namespace pheromesh::bus;  // NOLINT

TEST(Qos, EveryEndpointMeansTheSameOnCycloneAndFastDds) {
  for (const auto lease : {std::chrono::milliseconds(1000), std::chrono::milliseconds(250)}) {
    for (const TopicKind k : kAllTopicKinds) {
      for (const Endpoint e : {Endpoint::Writer, Endpoint::Reader}) {
        const QosSpec want = topic_qos(k, e, lease);
        EXPECT_EQ(cyclone_effective_qos(k, e, lease), want) << to_string(k) << " cyclone: " << to_string(cyclone_effective_qos(k, e, lease));
        EXPECT_EQ(fastdds_effective_qos(k, e, lease), want) << to_string(k) << " fastdds: " << to_string(fastdds_effective_qos(k, e, lease));
      }
    }
  }
}

TEST(Qos, ReplicatedSwarmsMeanTheSameOnCycloneAndFastDds) {
  const auto lease = std::chrono::milliseconds(800);
  for (const Replication r : {Replication{true, 0}, Replication{true, 999}}) {
    for (const TopicKind k : kAllTopicKinds) {
      for (const Endpoint e : {Endpoint::Writer, Endpoint::Reader}) {
        const QosSpec want = endpoint_qos(k, e, lease, r);
        EXPECT_EQ(cyclone_effective_qos(k, e, lease, r), want)
            << to_string(k) << " cyclone: " << to_string(cyclone_effective_qos(k, e, lease, r));
        EXPECT_EQ(fastdds_effective_qos(k, e, lease, r), want)
            << to_string(k) << " fastdds: " << to_string(fastdds_effective_qos(k, e, lease, r));
      }
    }
  }
}

TEST(Qos, ARealtimeSwarmsViewsAndPlaceFieldsAreBestEffortAndVolatileOnBothVendorsAndNothingElseChanges) {
  const auto lease = std::chrono::milliseconds(1000);
  for (const Replication r : {Replication{}, Replication{true, 999}}) {
    for (const TopicKind k : kAllTopicKinds) {
      for (const Endpoint e : {Endpoint::Writer, Endpoint::Reader}) {
        const QosSpec lockstep = endpoint_qos(k, e, lease, r);
        const QosSpec realtime = endpoint_qos(k, e, lease, r, Pacing::Realtime);
        if (k == TopicKind::View || k == TopicKind::PlaceField) {
          EXPECT_EQ(realtime.reliability, QosSpec::Reliability::BestEffort);
          EXPECT_EQ(realtime.durability, QosSpec::Durability::Volatile);
          EXPECT_EQ(lockstep.reliability, QosSpec::Reliability::Reliable) << "lockstep waits for every one";
          QosSpec rest = realtime;
          rest.reliability = lockstep.reliability;
          rest.durability = lockstep.durability;
          EXPECT_EQ(rest, lockstep) << "only reliability and durability differ";
        } else {
          EXPECT_EQ(realtime, lockstep) << to_string(k);
        }
        EXPECT_EQ(cyclone_effective_qos(k, e, lease, r, Pacing::Realtime), realtime) << to_string(k);
        EXPECT_EQ(fastdds_effective_qos(k, e, lease, r, Pacing::Realtime), realtime) << to_string(k);
      }
    }
  }
}

TEST(Qos, APlaceReplicasOutputIsExclusiveWithAStrengthAndALease) {
  using std::chrono::milliseconds;
  const auto lease = milliseconds(800);
  const Replication replica{true, 999};
  for (const TopicKind k : {TopicKind::Field, TopicKind::PlaceField, TopicKind::View, TopicKind::Halo,
                            TopicKind::TargetEvent, TopicKind::PhaseDone}) {
    const QosSpec w = endpoint_qos(k, Endpoint::Writer, lease, replica);
    EXPECT_EQ(w.ownership, QosSpec::Ownership::Exclusive) << to_string(k);
    EXPECT_EQ(w.ownership_strength, 999) << to_string(k);
    // Ownership moves on within a lease of the replica's death or stop.
    EXPECT_EQ(w.liveliness, QosSpec::Liveliness::ManualByTopic) << to_string(k);
    EXPECT_EQ(w.liveliness_lease, lease) << to_string(k);
    EXPECT_EQ(endpoint_qos(k, Endpoint::Reader, lease, Replication{true, 0}).ownership, QosSpec::Ownership::Exclusive);
    // A UAV's writer of the same topic: exclusive (or it would not match), strength 0, no lease traffic.
    const QosSpec uav = endpoint_qos(k, Endpoint::Writer, lease, Replication{true, 0});
    EXPECT_EQ(uav.ownership_strength, 0);
    EXPECT_EQ(uav.liveliness_lease, topic_qos(k, Endpoint::Writer, lease).liveliness_lease);
    // Not replicated: today's QoS.
    EXPECT_EQ(endpoint_qos(k, Endpoint::Writer, lease, Replication{}), topic_qos(k, Endpoint::Writer, lease));
  }
  // Deposits, states and health stay shared: every replica receives every
  // deposit, and the ground station hears each replica's health.
  for (const TopicKind k : {TopicKind::Deposit, TopicKind::UavState, TopicKind::Health, TopicKind::Clock}) {
    EXPECT_EQ(endpoint_qos(k, Endpoint::Writer, lease, replica).ownership, QosSpec::Ownership::Shared) << to_string(k);
  }
}

TEST(Qos, TheTableSaysWhatThePheromoneAccountingNeeds) {
  using std::chrono::milliseconds;
  const auto lease = milliseconds(1000);
  // Every deposit reaches the place agent: reliable, keep-all reader, deep writer history.
  const QosSpec dr = topic_qos(TopicKind::Deposit, Endpoint::Reader, lease);
  EXPECT_EQ(dr.reliability, QosSpec::Reliability::Reliable);
  EXPECT_EQ(dr.history, QosSpec::History::KeepAll);
  EXPECT_EQ(topic_qos(TopicKind::Deposit, Endpoint::Writer, lease).depth, 4096);
  // Late joiners get the latest tile and the clock; a clock reader keeps
  // every sample until taken (a forged one is refused, not overwritten).
  EXPECT_EQ(topic_qos(TopicKind::Clock, Endpoint::Writer, lease).depth, 1);
  EXPECT_EQ(topic_qos(TopicKind::Clock, Endpoint::Reader, lease).depth, 16);
  // Every place-agent health record reaches the ground station (series.csv).
  EXPECT_EQ(topic_qos(TopicKind::Health, Endpoint::Writer, lease).depth, 64);
  EXPECT_EQ(topic_qos(TopicKind::Health, Endpoint::Reader, lease).depth, 64);
  for (const TopicKind k : {TopicKind::Tile, TopicKind::View, TopicKind::Field}) {
    const QosSpec q = topic_qos(k, Endpoint::Reader, lease);
    EXPECT_EQ(q.durability, QosSpec::Durability::TransientLocal) << to_string(k);
    EXPECT_EQ(q.history, QosSpec::History::KeepLast) << to_string(k);
    EXPECT_EQ(q.depth, 1) << to_string(k);
  }
  // A UAV's states carry its deposits: its gateway keeps every one until taken.
  const QosSpec home = topic_qos(TopicKind::UavHome, Endpoint::Reader, lease);
  EXPECT_EQ(home.reliability, QosSpec::Reliability::Reliable);
  EXPECT_EQ(home.durability, QosSpec::Durability::TransientLocal);
  EXPECT_EQ(home.history, QosSpec::History::KeepAll);
  EXPECT_EQ(topic_qos(TopicKind::UavState, Endpoint::Writer, lease).depth, 64);
  // The home place agent reads the UAV's one state writer: the same topic,
  // a liveliness the writer offers.
  EXPECT_EQ(topic_qos(TopicKind::UavHome, Endpoint::Reader, lease).liveliness,
            topic_qos(TopicKind::UavState, Endpoint::Writer, lease).liveliness);
  // The lease is the process's.
  EXPECT_EQ(topic_qos(TopicKind::UavState, Endpoint::Writer, milliseconds(300)).liveliness_lease, milliseconds(300));
  EXPECT_EQ(std::string(topic_name(TopicKind::UavHome)), topic_name(TopicKind::UavState));
  EXPECT_EQ(to_string(topic_qos(TopicKind::Broadcast, Endpoint::Reader, lease)),
            "reliable(100ms) transient-local keep-all automatic lease infinite");
  // The writers the ground station watches for departures, and its readers,
  // are manual-by-topic (kept alive per writer; see qos.cpp).
  for (const TopicKind k : {TopicKind::UavState, TopicKind::Health}) {
    EXPECT_EQ(topic_qos(k, Endpoint::Writer, lease).liveliness, QosSpec::Liveliness::ManualByTopic) << to_string(k);
    EXPECT_EQ(topic_qos(k, Endpoint::Reader, lease).liveliness, QosSpec::Liveliness::ManualByTopic) << to_string(k);
  }
}
