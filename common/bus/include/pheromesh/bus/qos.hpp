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
// "pheromesh_uav_state" but differ in reader QoS.
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
};
inline constexpr TopicKind kAllTopicKinds[] = {
    TopicKind::Tile,   TopicKind::Deposit,     TopicKind::UavState, TopicKind::UavHome,
    TopicKind::Detection, TopicKind::TargetEvent, TopicKind::Health,
    TopicKind::Halo,   TopicKind::Clock,       TopicKind::PhaseDone, TopicKind::Broadcast,
    TopicKind::Command, TopicKind::View,      TopicKind::Field};

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

  bool operator==(const QosSpec&) const = default;
};

// The QoS of `kind` for a writer or a reader, with the process's liveliness lease.
QosSpec topic_qos(TopicKind kind, Endpoint endpoint, std::chrono::milliseconds lease);

// The DDS topic name and type name of a kind (the same on every vendor).
const char* topic_name(TopicKind kind);
const char* type_name(TopicKind kind);
const char* to_string(TopicKind kind);
std::string to_string(const QosSpec& q);

}  // namespace pheromesh::bus
