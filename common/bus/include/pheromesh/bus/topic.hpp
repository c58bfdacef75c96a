// What the bus knows of each message type M, vendor-neutral: its topic
// (TopicKind: the DDS topic and type name and the QoS, from the table in
// qos.cpp), its instance key (the IDL @key fields), its routing rule (the
// partition a sample goes to, when the message itself says it), and the IDL
// bounds every transport checks before writing. Each vendor adds one
// conversion per message type (Convert<M> in cyclone_samples.hpp and
// fastdds_samples.hpp); Writer<M> and Reader<M> (typed.hpp) do the rest.
//
// Adding a topic:
//   1. the IDL struct (idl/pheromesh.idl) and the core message
//      (core/messages.hpp): what travels;
//   2. a TopicKind with its names and its QoS row (qos.hpp, qos.cpp): how;
//   3. a Topic<M> specialisation below, and M in `Messages`;
//   4. one Convert<M> per vendor (cyclone_samples.hpp, fastdds_samples.hpp),
//      with the bound checks of received samples.
// Then any process can use Writer<M> / Reader<M>. Who writes and reads it is
// wiring: the role methods of Bus (bus.cpp) or the shell itself, and the
// security grants (security.cpp).
#pragma once

#include <algorithm>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "pheromesh/bus/qos.hpp"
#include "pheromesh/bus/routing.hpp"
#include "pheromesh/core/messages.hpp"

namespace pheromesh::bus {

// A sample that would break an IDL bound: which sequence, how long it is.
struct Oversize {
  const char* what;
  std::size_t n;
};
using BoundCheck = std::optional<Oversize>;

namespace detail {
inline BoundCheck over(const char* what, std::size_t n, std::size_t bound) {
  if (n > bound) return Oversize{what, n};
  return std::nullopt;
}
// Nested tiles of a view or field: each within a tile's bound.
inline BoundCheck tiles_over(const char* what, const std::vector<core::TileMsg>& tiles) {
  const bool fits =
      std::all_of(tiles.begin(), tiles.end(), [](const auto& t) { return t.values.size() <= core::kMaxTileCells; });
  if (fits) return std::nullopt;
  return Oversize{what, core::kMaxTileCells + 1};
}
inline uint64_t pack(uint64_t high, uint64_t low) { return high << 32U | (low & 0xFFFFFFFFU); }
}  // namespace detail

template <typename M>
struct Topic;  // one specialisation per message type

template <>
struct Topic<core::TileMsg> {
  static constexpr TopicKind kind = TopicKind::Tile;
  static uint64_t key(const core::TileMsg& m) {
    return detail::pack(
        m.layer, (static_cast<uint64_t>(static_cast<uint16_t>(m.tile.tx)) << 16U) | static_cast<uint16_t>(m.tile.ty));
  }
  static std::string partition(const core::TileMsg& m) { return routing::tile_partition(m.tile); }
  static BoundCheck oversize(const core::TileMsg& m) {
    return detail::over("tile values", m.values.size(), core::kMaxTileCells);
  }
};

// Routed by the writer: a place agent forwards a batch to the owner's
// "r.<owner>" (Bus::publish_deposits' `via`).
template <>
struct Topic<core::DepositBatchMsg> {
  static constexpr TopicKind kind = TopicKind::Deposit;
  static uint64_t key(const core::DepositBatchMsg& m) { return m.forwarder; }
  static BoundCheck oversize(const core::DepositBatchMsg& m) {
    return detail::over("forwarded deposits", m.deposits.size(), core::kMaxForwardDeposits);
  }
};

// Routed by the writer: "s.<gateway>" of the UAV (Bus::join_uav,
// move_uplink). The departure of a UAV is reported by this key. It carries
// the UAV's deposits (core::uplink_samples splits a tick's deposits over the
// bound); nested in a view or a field, a state goes without them.
template <>
struct Topic<core::UavStateMsg> {
  static constexpr TopicKind kind = TopicKind::UavState;
  static uint64_t key(const core::UavStateMsg& m) { return m.uav; }
  static BoundCheck oversize(const core::UavStateMsg& m) {
    return detail::over("uplink deposits", m.deposits.size(), core::kMaxUplinkDeposits);
  }
};

template <>
struct Topic<core::ViewMsg> {
  static constexpr TopicKind kind = TopicKind::View;
  static uint64_t key(const core::ViewMsg& m) { return m.uav; }
  static std::string partition(const core::ViewMsg& m) { return routing::view_partition(m.uav); }
  static BoundCheck oversize(const core::ViewMsg& m) {
    if (auto o = detail::over("view tiles", m.tiles.size(), core::kMaxViewTiles)) return o;
    if (auto o = detail::over("view states", m.uavs.size(), core::kMaxViewUavs)) return o;
    return detail::tiles_over("view tile values", m.tiles);
  }
};

template <>
struct Topic<core::FieldMsg> {
  static constexpr TopicKind kind = TopicKind::Field;
  static uint64_t key(const core::FieldMsg& m) { return detail::pack(m.region, m.chunk); }
  static std::string partition(const core::FieldMsg& /*m*/) { return routing::kFieldPartition; }
  static BoundCheck oversize(const core::FieldMsg& m) {
    if (auto o = detail::over("field tiles", m.tiles.size(), core::kMaxFieldTiles)) return o;
    if (auto o = detail::over("field states", m.uavs.size(), core::kMaxFieldUavs)) return o;
    if (auto o = detail::over("field reports", m.reports.size(), core::kMaxFieldUavs)) return o;
    for (const auto& r : m.reports) {
      if (auto o = detail::over("field report deposits", r.deposits.size(), core::kMaxRegionCounts)) return o;
    }
    return detail::tiles_over("field tile values", m.tiles);
  }
};

template <>
struct Topic<core::DetectionMsg> {
  static constexpr TopicKind kind = TopicKind::Detection;
  static uint64_t key(const core::DetectionMsg& m) { return m.uav; }
  static std::string partition(const core::DetectionMsg& /*m*/) { return routing::kGroundPartition; }
  static BoundCheck oversize(const core::DetectionMsg& /*m*/) { return std::nullopt; }
};

template <>
struct Topic<core::TargetEventMsg> {
  static constexpr TopicKind kind = TopicKind::TargetEvent;
  static uint64_t key(const core::TargetEventMsg& m) { return m.region; }
  static std::string partition(const core::TargetEventMsg& /*m*/) { return routing::kGroundPartition; }
  static BoundCheck oversize(const core::TargetEventMsg& /*m*/) { return std::nullopt; }
};

// The departure of a place replica is reported by this key: core::place_id.
template <>
struct Topic<core::HealthMsg> {
  static constexpr TopicKind kind = TopicKind::Health;
  static uint64_t key(const core::HealthMsg& m) { return core::place_id(m.region, m.replica); }
  static std::string partition(const core::HealthMsg& /*m*/) { return routing::kGroundPartition; }
  static BoundCheck oversize(const core::HealthMsg& /*m*/) { return std::nullopt; }
};

template <>
struct Topic<core::HaloMsg> {
  static constexpr TopicKind kind = TopicKind::Halo;
  static uint64_t key(const core::HaloMsg& m) { return m.region; }
  static BoundCheck oversize(const core::HaloMsg& m) {
    if (auto o = detail::over("halo target ring", m.target.size(), core::kMaxRingCells)) return o;
    return detail::over("halo obstacle ring", m.obstacle.size(), core::kMaxRingCells);
  }
};

template <>
struct Topic<core::BroadcastMsg> {
  static constexpr TopicKind kind = TopicKind::Broadcast;
  static uint64_t key(const core::BroadcastMsg& m) { return m.uav; }
  static std::string partition(const core::BroadcastMsg& /*m*/) { return routing::kBroadcastPartition; }
  static BoundCheck oversize(const core::BroadcastMsg& m) {
    return detail::over("broadcast values", m.values.size(), core::kMaxBroadcastValues);
  }
};

// A received clock carries its writer's identity (ClockMsg::writer, stamped
// by Reader<M> from the transport's SampleInfo).
template <>
struct Topic<core::ClockMsg> {
  static constexpr TopicKind kind = TopicKind::Clock;
  static uint64_t key(const core::ClockMsg& /*m*/) { return 0; }  // one conductor
  static std::string partition(const core::ClockMsg& /*m*/) { return routing::kClockPartition; }
  static BoundCheck oversize(const core::ClockMsg& m) {
    if (auto o = detail::over("clock occupancy", m.occupancy.size(), core::kMaxOccupancy)) return o;
    if (auto o = detail::over("clock deposit counts", m.deposits.size(), core::kMaxRegionCounts)) return o;
    if (auto o = detail::over("clock absent regions", m.absent.size(), core::kMaxRegionCounts)) return o;
    if (auto o = detail::over("clock state counts", m.states.size(), core::kMaxRegionCounts)) return o;
    return detail::over("clock served UAVs", m.served.size(), core::kMaxClockServed);
  }
};

template <>
struct Topic<core::PhaseDoneMsg> {
  static constexpr TopicKind kind = TopicKind::PhaseDone;
  static uint64_t key(const core::PhaseDoneMsg& m) { return m.process; }
  static std::string partition(const core::PhaseDoneMsg& /*m*/) { return routing::kClockPartition; }
  static BoundCheck oversize(const core::PhaseDoneMsg& m) {
    return detail::over("phase deposit counts", m.deposits.size(), core::kMaxRegionCounts);
  }
};

template <>
struct Topic<core::CommandMsg> {
  static constexpr TopicKind kind = TopicKind::Command;
  static uint64_t key(const core::CommandMsg& m) { return m.issuer; }
  static std::string partition(const core::CommandMsg& /*m*/) { return routing::kCommandPartition; }
  static BoundCheck oversize(const core::CommandMsg& /*m*/) { return std::nullopt; }
};

template <>
struct Topic<core::ScenarioMsg> {
  static constexpr TopicKind kind = TopicKind::Scenario;
  static uint64_t key(const core::ScenarioMsg& m) { return m.publisher; }
  static std::string partition(const core::ScenarioMsg& /*m*/) { return routing::kGroundPartition; }
  static BoundCheck oversize(const core::ScenarioMsg& m) {
    return detail::over("scenario bytes", m.text.size(), core::kMaxScenarioBytes);
  }
};

// Every message type the bus carries, one per DDS topic. Each transport
// builds its table of conversions from this list, so a type without its
// Convert<M> does not compile.
template <typename... M>
struct MessageList {};
using Messages =
    MessageList<core::TileMsg, core::DepositBatchMsg, core::UavStateMsg, core::ViewMsg, core::FieldMsg,
                core::DetectionMsg, core::TargetEventMsg, core::HealthMsg, core::HaloMsg, core::BroadcastMsg,
                core::ClockMsg, core::PhaseDoneMsg, core::CommandMsg, core::ScenarioMsg>;

// Routed by the message itself (Topic<M>::partition), or by the writer.
template <typename M>
concept RoutedByMessage = requires(const M& m) {
  { Topic<M>::partition(m) } -> std::convertible_to<std::string>;
};

// The DDS topic a kind's endpoints use: UavHome readers read UavState.
constexpr TopicKind topic_of(TopicKind k) { return k == TopicKind::UavHome ? TopicKind::UavState : k; }
// The kind whose message type a kind's endpoints carry (Topic<M>::kind):
// also a relayed clock is a ClockMsg, the states relayed to the ground a
// FieldMsg (of states only: one sample per place agent and take).
constexpr TopicKind message_kind(TopicKind k) {
  if (k == TopicKind::RelayedClock) return TopicKind::Clock;
  if (k == TopicKind::GroundState || k == TopicKind::PlaceField) return TopicKind::Field;
  return topic_of(k);
}
inline constexpr std::size_t kTopicKindCount = static_cast<std::size_t>(TopicKind::PlaceField) + 1;
constexpr std::size_t index_of(TopicKind k) { return static_cast<std::size_t>(k); }

}  // namespace pheromesh::bus
