// The QoS of every pheromesh topic, described once and without a vendor:
// each vendor's bus translates this description (cyclone_bus.cpp,
// fastdds_bus.cpp) and can read its translation back (effective_qos), which
// the bus tests compare with this table.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace pheromesh::bus {

// One entry per kind of endpoint pheromesh creates. UavState (the UAV's
// writer and the ground station's reader) and UavHome (the home place
// agent's reader of the same writer) share the DDS topic
// "pheromesh_uav_state" but differ in reader QoS. RelayedClock carries the
// clock's type on a topic of its own ("pheromesh_clock_relay": a place
// agent to the UAVs it serves, the lockstep tree), so that permissions name
// who may write the conductor's clock by topic alone (Fast DDS 2.9 does not
// check a writer's partitions against them). GroundState carries the region
// field's type on a topic of its own ("pheromesh_uav_state_ground": the
// states a place agent relays to the ground station, with the departures of
// the UAVs it serves, batched), replicated like the other topics place
// agents write. PlaceField is the same type on "pheromesh_place_field":
// what place agents send each other each tick (the UAVs each serves, the
// tiles for another's views), best effort in realtime (endpoint_qos) while
// the field to the ground station stays reliable.
enum class TopicKind : uint8_t {
  Tile,
  Deposit,
  UavState,
  UavHome,
  Detection,
  TargetEvent,
  Health,
  Halo,
  Clock,
  PhaseDone,
  Broadcast,
  Command,
  View,
  Field,
  Scenario,
  RelayedClock,
  GroundState,
  PlaceField,  // place agents among themselves: served UAVs, tiles for views (a RegionField)
};
inline constexpr TopicKind kAllTopicKinds[] = {
    TopicKind::Tile,         TopicKind::Deposit,     TopicKind::UavState,  TopicKind::UavHome, TopicKind::Detection,
    TopicKind::TargetEvent,  TopicKind::Health,      TopicKind::Halo,      TopicKind::Clock,   TopicKind::PhaseDone,
    TopicKind::Broadcast,    TopicKind::Command,     TopicKind::View,      TopicKind::Field,   TopicKind::Scenario,
    TopicKind::RelayedClock, TopicKind::GroundState, TopicKind::PlaceField};

enum class Endpoint : uint8_t { Writer, Reader };

struct QosSpec {
  enum class Reliability : uint8_t { BestEffort, Reliable };
  enum class Durability : uint8_t { Volatile, TransientLocal };
  enum class History : uint8_t { KeepLast, KeepAll };
  enum class Liveliness : uint8_t { Automatic, ManualByTopic };

  Reliability reliability = Reliability::Reliable;
  std::chrono::milliseconds max_blocking{100};  // a reliable writer blocks at most this long when its history is full
  Durability durability = Durability::Volatile;
  History history = History::KeepLast;
  int32_t depth = 1;                            // KeepLast only
  // ManualByTopic writers are kept alive by their writes and by the bus while
  // the process keeps polling it (Bus::take_*), so a hung process is lost too.
  Liveliness liveliness = Liveliness::Automatic;
  std::chrono::milliseconds liveliness_lease{1000};  // kInfiniteLease: no liveliness traffic at all
  static constexpr std::chrono::milliseconds kInfiniteLease = std::chrono::milliseconds::max();
  // Exclusive: a reader takes each instance from its strongest live writer
  // only (hot-standby place agents, docs/faults.md).
  enum class Ownership : uint8_t { Shared, Exclusive };
  Ownership ownership = Ownership::Shared;
  int32_t ownership_strength = 0;  // writers only

  bool operator==(const QosSpec&) const = default;
};

// The QoS of `kind` for a writer or a reader, with the process's liveliness lease.
QosSpec topic_qos(TopicKind kind, Endpoint endpoint, std::chrono::milliseconds lease);

// A swarm with hot-standby place agents (`pheromesh run --standby`): every
// process of it uses exclusive ownership on the topics a place agent
// publishes for others to use (fields, views, halos, target events, phase
// reports), so that each reader takes them from one replica of a region only.
// A place replica writes them with strength `strength` (> 0; the primary
// strongest) and a manual-by-topic lease, so that its death or a stop hands
// ownership to the next replica within a lease. Every other writer of these
// topics (a UAV's phase reports) has strength 0.
struct Replication {
  bool exclusive = false;
  int32_t strength = 0;  // > 0: this process is a place replica
};
// Kinds whose readers take each instance from one owner in a replicated swarm.
bool replicated(TopicKind kind);
// The swarm's clock, as far as the QoS goes: in a realtime swarm a UAV's
// view is replaced by the next one every tick, and goes best effort
// (endpoint_qos); lockstep waits for every one of them.
enum class Pacing : uint8_t { Lockstep, Realtime };
// topic_qos with the swarm's replication and pacing applied.
QosSpec endpoint_qos(TopicKind kind, Endpoint endpoint, std::chrono::milliseconds lease, const Replication& r,
                     Pacing pacing = Pacing::Lockstep);

// The DDS topic name and type name of a kind (the same on every vendor).
const char* topic_name(TopicKind kind);
const char* type_name(TopicKind kind);
const char* to_string(TopicKind kind);
std::string to_string(const QosSpec& q);

}  // namespace pheromesh::bus
