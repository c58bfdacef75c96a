#include "pheromesh/bus/qos.hpp"

#include <stdexcept>
#include <string>

namespace pheromesh::bus {

namespace {

// The QoS of every topic, as one table (docs/dds.md, "QoS"). Every endpoint
// is reliable and transient-local, also where late joiners do not matter: a
// writer may match a reader before the reader has matched the writer, and a
// sample written in that window reaches a volatile reader or not depending on
// the vendor (a Cyclone reader drops what a Fast DDS writer sent before the
// match; measured: deposits, detections and ground UAV states went missing
// across vendors). A transient-local reader asks for the writer's history once
// it matches, so nothing written is lost.
//
// Only the writers the ground station and the home place agents watch for
// departures (`watched`: UAV state, place-agent health) have a finite lease,
// manual-by-topic. Any finite automatic lease makes every participant assert
// its liveliness to every other one periodically (Cyclone's and Fast DDS's
// participant-message / WLP writers), traffic that grows as N² with the swarm
// whether or not anything is published (measured: issue 12, docs/dds.md
// "Scale"). Manual-by-topic on writer and reader: Fast DDS 2.9 keeps every
// remote writer that an automatic reader watches alive as long as any Fast DDS
// participant sends its automatic liveliness message (WLPListener asserts them
// all), so a killed Fast DDS process was never reported (measured); with a
// manual-by-topic reader the lease is tracked per writer on both vendors.
constexpr int32_t kKeepAll = 0;
struct QosRow {
  TopicKind kind;
  int32_t writer_depth;  // keep-last depth of its writers' history; kKeepAll: keep-all
  int32_t reader_depth;  // likewise, of its readers
  bool watched;          // manual-by-topic liveliness with the process's lease
};
constexpr QosRow kQosTable[] = {
    // Place-agent health: every record, not only the latest. A lockstep place
    // agent publishes one per place phase, and the ground station's
    // series.csv counts the deposits applied by each tick from them
    // (docs/outputs.md). With a depth of 1 a record still unacknowledged when
    // the next tick's was written was replaced (measured: tick 0's, now and
    // then). The ground station tells a lost place agent by its liveliness.
    {TopicKind::Health, 64, 64, true},
    // Latest value per key, also for late joiners.
    {TopicKind::Tile, 1, 1, false},
    {TopicKind::PhaseDone, 1, 1, false},
    {TopicKind::Scenario, 1, 1, false},
    {TopicKind::Halo, 1, 1, false},
    // A late joiner gets the latest clock. A reader keeps every clock sample
    // until it is taken: every writer's sample of the one instance would
    // otherwise replace the one before, and a forged clock (a Stop) written
    // between two of the conductor's - a few ms apart in lockstep - would
    // vanish uncounted instead of being refused (core::LockstepFollower,
    // plausibility.hpp).
    {TopicKind::Clock, 1, 16, false},
    {TopicKind::RelayedClock, 1, 16, false},
    // A UAV's uplink to its gateway (its state and its deposits): every sample
    // matters, a keep-all reader (UavHome), a writer history of 64 ticks. The
    // gateway tells a lost UAV by this writer's liveliness.
    {TopicKind::UavState, 64, kKeepAll, true},
    // The states (and departures) of the UAVs a place agent serves, relayed to
    // the ground station, which records every one: a RegionField of states
    // only per place agent and take (Bus::relay_states), keyed by region,
    // without the liveliness (a departure is a state here,
    // UavStateMsg::departed). Every batch matters: keep-all reader.
    {TopicKind::GroundState, 64, kKeepAll, false},
    // The gateway place agent reads every state of each UAV it serves: each
    // carries the deposits the UAV made since the one before
    // (UavStateMsg::deposits), so none may replace another before it is taken
    // (the UAV's writer keeps the last 64). Reader only; the writer is the
    // UAV's UavState writer, whose liveliness it must accept.
    {TopicKind::UavHome, kKeepAll, kKeepAll, true},
    // The latest view of a UAV, the latest field chunk of a region: a newer
    // one replaces an older one. Lockstep never has two in flight (each is
    // acknowledged before the phase that produced it reports done).
    {TopicKind::View, 1, 1, false},
    {TopicKind::Field, 1, 1, false},
    {TopicKind::PlaceField, 1, 1, false},
    // Every broadcast matters; a few ticks of them for late joiners.
    {TopicKind::Broadcast, 8, kKeepAll, false},
    // Few and all of them matter, also to a process that starts late (a
    // restarted UAV must see every pop-up obstacle so far): a deep history.
    {TopicKind::Command, 256, kKeepAll, false},
    // Every sample matters (pheromone accounting): deep writer history,
    // keep-all readers.
    {TopicKind::Deposit, 4096, kKeepAll, false},
    {TopicKind::Detection, 4096, kKeepAll, false},
    {TopicKind::TargetEvent, 4096, kKeepAll, false},
};

const QosRow& qos_row(TopicKind kind) {
  for (const QosRow& r : kQosTable) {
    if (r.kind == kind) return r;
  }
  throw std::logic_error("no QoS row for topic kind " + std::to_string(static_cast<int>(kind)));
}

}  // namespace

QosSpec topic_qos(TopicKind kind, Endpoint endpoint, std::chrono::milliseconds lease) {
  const QosRow& row = qos_row(kind);
  QosSpec q;
  q.reliability = QosSpec::Reliability::Reliable;
  q.durability = QosSpec::Durability::TransientLocal;
  q.liveliness = row.watched ? QosSpec::Liveliness::ManualByTopic : QosSpec::Liveliness::Automatic;
  q.liveliness_lease = row.watched ? lease : QosSpec::kInfiniteLease;
  const int32_t depth = endpoint == Endpoint::Reader ? row.reader_depth : row.writer_depth;
  q.history = depth == kKeepAll ? QosSpec::History::KeepAll : QosSpec::History::KeepLast;
  q.depth = depth;
  return q;
}

bool replicated(TopicKind kind) {
  switch (kind) {
    case TopicKind::Field:
    case TopicKind::PlaceField:
    case TopicKind::View:
    case TopicKind::Halo:
    case TopicKind::TargetEvent:
    case TopicKind::PhaseDone:
    // What place agents relay between the UAVs they serve and the rest of
    // the swarm (docs/architecture.md, "Relays"): one copy per region.
    case TopicKind::GroundState:
    case TopicKind::Detection:
    case TopicKind::Broadcast:
    case TopicKind::Command:
      return true;
    default:
      return false;
  }
}

QosSpec endpoint_qos(TopicKind kind, Endpoint endpoint, std::chrono::milliseconds lease, const Replication& r,
                     Pacing pacing) {
  QosSpec q = topic_qos(kind, endpoint, lease);
  if (pacing == Pacing::Realtime && (kind == TopicKind::View || kind == TopicKind::PlaceField)) {
    // A realtime view is superseded by the next tick's, and the deposit
    // receipts it carries are cumulative (core/receipts.hpp): a lost one
    // costs nothing the next does not bring. Best effort drops the
    // acknowledgement each view asked for, one datagram per UAV tick and a
    // wake-up of the sending place agent (measured: docs/benchmarks.md,
    // "Where a UAV tick goes"); volatile, as late joiners need no history
    // of something replaced each tick. The same for what place agents send
    // each other each tick (the UAVs they serve, the tiles for views): a
    // view uses tiles an owner sent lately, and a deposit is judged against
    // the newest state of its UAV held, whatever its tick
    // (check_deposit_reach). The field to the ground station stays reliable.
    q.reliability = QosSpec::Reliability::BestEffort;
    q.durability = QosSpec::Durability::Volatile;
  }
  if (!r.exclusive || !replicated(kind)) return q;
  q.ownership = QosSpec::Ownership::Exclusive;
  if (endpoint == Endpoint::Writer && r.strength > 0) {
    q.ownership_strength = r.strength;
    // Ownership passes to the next replica when this writer is not alive:
    // a finite lease, asserted while the process polls its bus (a stopped
    // or hung replica loses ownership too, and takes it back when it runs
    // again). The participant's lease (1 h, deploy/dds) would be far too slow.
    q.liveliness = QosSpec::Liveliness::ManualByTopic;
    q.liveliness_lease = lease;
  }
  return q;
}

const char* topic_name(TopicKind kind) {
  switch (kind) {
    case TopicKind::Tile: return "pheromesh_tile";
    case TopicKind::Deposit: return "pheromesh_deposit";
    case TopicKind::UavState:
    case TopicKind::UavHome: return "pheromesh_uav_state";
    case TopicKind::Detection: return "pheromesh_detection";
    case TopicKind::TargetEvent: return "pheromesh_target_event";
    case TopicKind::Health: return "pheromesh_place_health";
    case TopicKind::Halo: return "pheromesh_halo";
    case TopicKind::Clock: return "pheromesh_clock";
    case TopicKind::PhaseDone: return "pheromesh_phase_done";
    case TopicKind::Broadcast: return "pheromesh_broadcast";
    case TopicKind::Command: return "pheromesh_command";
    case TopicKind::View: return "pheromesh_view";
    case TopicKind::Field: return "pheromesh_region_field";
    case TopicKind::Scenario: return "pheromesh_run_scenario";
    case TopicKind::RelayedClock: return "pheromesh_clock_relay";
    case TopicKind::GroundState:
      return "pheromesh_uav_state_ground";
    case TopicKind::PlaceField:
      return "pheromesh_place_field";
  }
  throw std::logic_error("unknown topic kind");
}

const char* type_name(TopicKind kind) {
  switch (kind) {
    case TopicKind::Tile: return "pheromesh::msg::TileState";
    case TopicKind::Deposit:
      return "pheromesh::msg::DepositBatch";
    case TopicKind::UavState:
    case TopicKind::UavHome: return "pheromesh::msg::UavState";
    case TopicKind::Detection: return "pheromesh::msg::Detection";
    case TopicKind::TargetEvent: return "pheromesh::msg::TargetEvent";
    case TopicKind::Health: return "pheromesh::msg::PlaceHealth";
    case TopicKind::Halo: return "pheromesh::msg::Halo";
    case TopicKind::Clock:
    case TopicKind::RelayedClock: return "pheromesh::msg::ClockCommand";
    case TopicKind::PhaseDone: return "pheromesh::msg::PhaseDone";
    case TopicKind::Broadcast: return "pheromesh::msg::Broadcast";
    case TopicKind::Command: return "pheromesh::msg::Command";
    case TopicKind::View: return "pheromesh::msg::View";
    case TopicKind::Field:
    case TopicKind::GroundState:
    case TopicKind::PlaceField:
      return "pheromesh::msg::RegionField";
    case TopicKind::Scenario:
      return "pheromesh::msg::RunScenario";
  }
  throw std::logic_error("unknown topic kind");
}

const char* to_string(TopicKind kind) {
  switch (kind) {
    case TopicKind::Tile: return "tile";
    case TopicKind::Deposit: return "deposit";
    case TopicKind::UavState: return "uav-state";
    case TopicKind::UavHome: return "uav-home";
    case TopicKind::Detection: return "detection";
    case TopicKind::TargetEvent: return "target-event";
    case TopicKind::Health: return "health";
    case TopicKind::Halo: return "halo";
    case TopicKind::Clock: return "clock";
    case TopicKind::PhaseDone: return "phase-done";
    case TopicKind::Broadcast: return "broadcast";
    case TopicKind::Command: return "command";
    case TopicKind::View: return "view";
    case TopicKind::Field: return "field";
    case TopicKind::Scenario: return "scenario";
    case TopicKind::RelayedClock: return "relayed-clock";
    case TopicKind::GroundState:
      return "ground-state";
    case TopicKind::PlaceField:
      return "place-field";
  }
  return "?";
}

std::string to_string(const QosSpec& q) {
  std::string s = q.reliability == QosSpec::Reliability::Reliable ? "reliable" : "best-effort";
  s += "(" + std::to_string(q.max_blocking.count()) + "ms)";
  s += q.durability == QosSpec::Durability::TransientLocal ? " transient-local" : " volatile";
  s += q.history == QosSpec::History::KeepAll ? " keep-all" : " keep-last(" + std::to_string(q.depth) + ")";
  s += q.liveliness == QosSpec::Liveliness::ManualByTopic ? " manual-by-topic" : " automatic";
  s += q.liveliness_lease == QosSpec::kInfiniteLease ? std::string(" lease infinite")
                                                     : " lease " + std::to_string(q.liveliness_lease.count()) + "ms";
  if (q.ownership == QosSpec::Ownership::Exclusive) s += " exclusive(" + std::to_string(q.ownership_strength) + ")";
  return s;
}

}  // namespace pheromesh::bus
