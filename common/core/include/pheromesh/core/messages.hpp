// Vendor-neutral messages carried by the bus. They mirror idl/pheromesh.idl;
// the bus implementations convert between these and the generated types.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "pheromesh/core/grid.hpp"

namespace pheromesh::core {

inline constexpr std::size_t kMaxTileCells = 1024;  // 32 x 32, idl bound
inline constexpr std::size_t kMaxRingCells = 4096;  // idl bound
inline constexpr std::size_t kRefusalCount = 14;    // core::Refusal (plausibility.hpp), idl REFUSAL_REASONS

struct TileMsg {
  uint8_t layer = 0;
  TileCoord tile{};
  uint32_t tick = 0;
  RegionId region = 0;
  uint16_t width = 0, height = 0;  // [cell]
  std::vector<float> values;       // row-major, width*height
  // Not on the wire: the writer's process (bus::SampleInfo::participant),
  // as the receiving bus names it; 0 if unknown or written by this process.
  uint64_t participant = 0;
};

// What a deposit asks its place agent to do (idl/pheromesh.idl, Deposit).
enum class DepositKind : uint8_t {
  PathVisit = 0,     // Shao 2020 eq. (5), Shao 2020 eq. (6), Shao 2020 eq. (7): path pheromone falls around the UAV
  TargetMark = 1,    // Shao: a target sensed here
  ObstacleMark = 2,  // Shao: an obstacle sensed here
  LayerAdd = 3,      // add `amount` to `layer` at the cell (capped by the layer)
  Ellipse = 4,       // Ravankar 2016 eq. (14): spread over the error ellipse `spread`
  Observation = 5,   // Liu 2022 eq. (4), Liu 2022 eq. (5): the cell was looked at; amount 1 = detection
  PointSet = 6,      // Duan 2009: this UAV's point pheromone at the cell is `amount`
  PointClear = 7,    // Duan 2009: forget this UAV's point pheromone in the region
};
inline constexpr uint8_t kDepositKindCount = 8;

struct DepositMsg {
  uint32_t uav = 0;
  uint32_t seq = 0;   // per UAV, strictly increasing
  uint32_t tick = 0;  // UAV tick
  RegionId region = 0;
  uint8_t kind = 0;   // DepositKind
  uint8_t layer = 0;  // LayerAdd only
  Cell cell{};
  float amount = 0.0F;
  std::array<float, 3> spread{};  // Ellipse only: Σ_xy entries xx, xy, yy [m²]
  // Not on the wire: the writer's process (bus::SampleInfo::participant),
  // as the receiving bus names it; 0 if unknown or written by this process.
  uint64_t participant = 0;
};

// The deposits one place agent forwards to the owner of one region in one
// take (idl DepositBatch): one sample per destination and take, not one per
// deposit (issue 44: the per-deposit samples were 3 of the 12.7 RTPS
// submessages of a UAV tick at 500 UAVs). The receiver takes each deposit
// as if it had come alone.
struct DepositBatchMsg {
  RegionId forwarder = 0;  // the forwarding place agent's region (the key)
  uint32_t tick = 0;       // the forwarder's place tick
  std::vector<DepositMsg> deposits;
  // Not on the wire: the writer's process (bus::SampleInfo::participant).
  uint64_t participant = 0;
};
inline constexpr std::size_t kMaxForwardDeposits = 256;  // idl MAX_FORWARD_DEPOSITS

// The batches that carry `deposits` (all for one destination) from
// `forwarder` at place tick `tick`: kMaxForwardDeposits each, in order,
// none when there are none.
std::vector<DepositBatchMsg> deposit_batches(RegionId forwarder, uint32_t tick, std::span<const DepositMsg> deposits);

enum class Role : uint8_t { Searcher = 0, Leader = 1, Follower = 2 };

struct UavStateMsg {
  uint32_t uav = 0;
  uint32_t tick = 0;
  double x = 0, y = 0;    // [cell]
  double vx = 0, vy = 0;  // [cell/tick]
  uint8_t heading = 0;
  uint8_t role = 0;
  uint64_t deposits_sent = 0;
  uint64_t tile_samples_received = 0;
  uint64_t samples_received = 0;  // DDS samples the UAV took (views, broadcasts, commands)
  uint32_t ticks_late = 0;        // realtime ticks that started more than one tick period late
  Cell view{};                    // the cell whose neighbourhood the UAV reads next (its home place agent composes it)
  bool finished = false;          // last state of a UAV that ended its run
  uint32_t tick_gap_max_ms = 0;   // [ms] realtime: longest gap between two tick starts (core/tick_gaps.hpp)
  uint32_t tick_gaps_over_2 = 0;  // realtime: gaps between tick starts longer than two periods
  uint64_t deposits_unconfirmed = 0;  // sent, but not (yet) confirmed received by its home place agent
  // Samples this UAV refused as implausible, per core::Refusal (plausibility.hpp).
  std::array<uint32_t, kRefusalCount> refused{};
  // Only from a place agent relaying states to the ground station: every
  // writer of this UAV's state vanished (liveliness lost, process ended).
  // A UAV never sets it (its place agent drops such a state).
  bool departed = false;
  // Only from a place agent relaying states to the ground station: the UAV's
  // gateway refused this state as implausible (check_home_state, Refusal::
  // ImplausibleState) and counted it. It is the UAV's answer for its tick -
  // the lockstep conductor waits for no other - but not a position: coverage,
  // neighbours and views never see it (docs/architecture.md "Plausibility").
  // A UAV never sets it (its gateway refuses such a state as malformed).
  bool implausible = false;
  // Lockstep, set by the UAV: its answer for the UAV phase of `tick`, which
  // its gateway reports for it (core::UplinkReports): the deposits this
  // tick's uplink carries in all its samples, and the broadcasts it wrote
  // in the tick (0 or 1). Zero in realtime, in a view, a field and a state
  // relayed to the ground.
  uint32_t tick_deposits = 0;
  uint8_t broadcasts = 0;
  // Not on the wire: who wrote the sample, as the receiving bus identifies
  // the DDS writer (as ClockMsg::writer). The UAV's gateway latches it
  // (core/writer_latch.hpp).
  uint64_t writer = 0;
  // The UAV's uplink: the deposits it made since its previous state (at
  // most kMaxUplinkDeposits; a tick with more writes the state again with
  // the rest, uplink_samples). Its gateway takes them as it takes forwarded
  // deposits. Empty in a view, a field and a state relayed to the ground.
  std::vector<DepositMsg> deposits;
  // Not on the wire: the writer's process (bus::SampleInfo::participant).
  // Every writer of one UAV process shares it, so its gateway takes the
  // UAV's detections and broadcasts only from the process whose state it
  // latched; a state relayed to the ground station names the relaying
  // place agent's.
  uint64_t participant = 0;
};
inline constexpr std::size_t kMaxUplinkDeposits = 64;  // idl MAX_UPLINK_DEPOSITS

// The samples that carry state `s` and the deposits `deposits` of its tick
// to the UAV's gateway: `s` with the first kMaxUplinkDeposits deposits,
// then, while deposits are left, `s` again with the next ones (one sample
// when there are none).
std::vector<UavStateMsg> uplink_samples(const UavStateMsg& s, const std::vector<DepositMsg>& deposits);

// Every state writer of a UAV vanished, as one place agent's reader saw it.
// Relayed to the ground station (UavStateMsg::departed), it carries the tick
// of the last state that place agent held of the UAV: a place agent that lost
// the UAV long ago (it was stopped while the UAV moved on to its backup) tells
// of a departure older than what the ground station heard since.
struct UavDeparture {
  UavDeparture(uint32_t u = 0, std::optional<uint32_t> tick = std::nullopt)  // NOLINT(google-explicit-constructor)
      : uav(u), last_tick(tick) {}
  uint32_t uav = 0;
  std::optional<uint32_t> last_tick;  // none: the process's own reader saw it (no relay)
  uint64_t participant = 0;           // the relaying process (UavStateMsg::participant); 0: own reader or unknown
  // The same departure, whoever relayed it.
  bool operator==(const UavDeparture& o) const { return uav == o.uav && last_tick == o.last_tick; }
};

struct DetectionMsg {
  uint32_t uav = 0;
  uint32_t tick = 0;
  int32_t target = -1;  // target index in the scenario
  Cell cell{};
  // Not on the wire: the writer's process (bus::SampleInfo::participant),
  // as the receiving bus names it; 0 if unknown or written by this process.
  uint64_t participant = 0;
};

// TargetEventMsg::kind on the wire (the values of MarkEvent::Kind).
enum class TargetEventKind : uint8_t { FirstMarked = 0, RevisitDue = 1, Revisited = 2 };
const char* to_string(TargetEventKind k);  // "marked", "due for a revisit", "revisited"

struct TargetEventMsg {
  RegionId region = 0;
  uint32_t tick = 0;
  uint8_t kind = 0;  // TargetEventKind
  Cell cell{};
  uint32_t response_ticks = 0;
  // Not on the wire: the writer's process (bus::SampleInfo::participant),
  // as the receiving bus names it; 0 if unknown or written by this process.
  uint64_t participant = 0;
};

struct HealthMsg {
  RegionId region = 0;
  uint32_t tick = 0;
  float tick_rate_hz = 0;
  uint64_t deposits_received = 0;
  uint64_t deposits_applied = 0;
  uint64_t deposits_rejected = 0;
  uint64_t halos_missing = 0;
  bool finished = false;
  uint32_t tick_gap_max_ms = 0;     // [ms] realtime: longest gap between two tick starts (core/tick_gaps.hpp)
  uint32_t tick_gaps_over_2 = 0;    // realtime: gaps between tick starts longer than two periods
  uint16_t replica = 0;             // 0 the primary, 1.. standbys
  uint64_t deposits_duplicate = 0;  // copies of a deposit already received, dropped
  // Samples this place agent refused as implausible, per core::Refusal
  // (plausibility.hpp; deposits among them are counted in deposits_rejected too).
  std::array<uint32_t, kRefusalCount> refused{};
  uint64_t bytes_received = 0;  // payload bytes of every sample it took (payload_bytes)
  // It matched every other region's place agent: the deposits it forwards
  // reach their owners. The realtime Start waits for every region's (RunBook).
  bool linked = false;
  // 1 the place agent's first start, 2.. a process started again after its
  // death (core::RunRecorder keeps the earlier lives' counts).
  uint32_t life = 1;
  // Not on the wire: the writer's process (bus::SampleInfo::participant),
  // as the receiving bus names it; 0 if unknown or written by this process.
  uint64_t participant = 0;
};

// A place replica in one 32-bit id (departures): replica << 16 | region.
inline constexpr uint32_t place_id(RegionId region, uint16_t replica) {
  return static_cast<uint32_t>(replica) << 16U | (region & 0xFFFFU);
}
inline constexpr RegionId place_id_region(uint32_t id) { return id & 0xFFFFU; }
inline constexpr uint16_t place_id_replica(uint32_t id) { return static_cast<uint16_t>(id >> 16U); }

struct HaloMsg {
  RegionId region = 0;
  uint32_t tick = 0;
  std::vector<float> target;
  std::vector<float> obstacle;
  // Part of the key: the replica that wrote it when a region's replicas share
  // ownership (hot standbys on Fast DDS or mixed swarms), so that no two
  // writers share an instance; 0 otherwise (docs/faults.md).
  uint16_t replica = 0;
};

// A UAV's message to the whole swarm (partition "b").
enum class BroadcastKind : uint8_t {
  LeaderState = 0,   // Shao 2020 Sec. 5: x, y, vx, vy [cell, cell/tick], arrived (0/1)
  TargetFound = 1,   // Shostak 2024 Sec. 5: x, y of the target [cell]
  EtaIntervals = 2,  // Duan 2009 eq. (4): pairs (T_min, T_max) [s] of the candidate trajectories
};
inline constexpr uint8_t kBroadcastKindCount = 3;
inline constexpr std::size_t kMaxBroadcastValues = 64;  // idl bound

// The run as its place agents run it (idl RunScenario), for monitors that
// attach with only the domain id.
inline constexpr std::size_t kMaxScenarioBytes = 65536;  // idl MAX_SCENARIO_BYTES
struct ScenarioMsg {
  uint32_t publisher = 0;  // place id
  std::string text;        // the scenario file, protobuf text format
  uint32_t uavs = 0;
  uint32_t ticks = 0;
  uint64_t seed = 0;
  double tick_rate_hz = 0;
  uint8_t clock = 0;  // 0 realtime, 1 lockstep
  uint32_t lease_ms = 0;
  bool standby = false;
  bool shared_ownership = false;
};

// A ground-station command (idl Command; authenticated by runtime/control.hpp).
// Start: the ground station heard every UAV and place agent (realtime runs
// fly from then on, all together; see runtime::SwarmCommands::started).
// End: the run is over (pheromesh-ground --until-done, once every UAV finished);
// place agents finish and exit.
enum class CommandKind : uint8_t { Pause = 1, Resume = 2, Obstacle = 3, Target = 4, Start = 5, End = 6 };
struct CommandMsg {
  uint32_t issuer = 0;
  uint32_t seq = 0;
  uint64_t issued_ms = 0;
  uint8_t kind = 0;
  int32_t x = 0, y = 0, w = 0, h = 0;
  std::array<uint8_t, 32> mac{};
};
struct BroadcastMsg {
  uint32_t uav = 0;
  uint32_t tick = 0;
  uint8_t kind = 0;  // BroadcastKind
  std::vector<double> values;
  // Not on the wire: the writer's process (bus::SampleInfo::participant),
  // as the receiving bus names it; 0 if unknown or written by this process.
  uint64_t participant = 0;
};

// Lockstep clock (DESIGN.md, "Time").
// Ready: before tick 0, the conductor waits until every UAV and place agent
// reports (PhaseDone of phase Ready) that it matched the readers it writes
// deposits to - discovery takes long under packet loss or on a busy host,
// and a deposit written before the match would be lost.
enum class ClockPhase : uint8_t { Uav = 0, Place = 1, Stop = 2, Ready = 3 };
inline constexpr std::size_t kMaxOccupancy = 1024;  // idl bound
struct TileCount {
  TileCoord tile{};
  uint32_t count = 0;
};
inline constexpr std::size_t kMaxRegionCounts = 4096;  // idl bound
struct RegionCount {
  RegionId region = 0;
  uint32_t count = 0;
};
// A UAV a place phase serves (ClockMsg::served): its pose after the UAV
// phase and its gateway, the region whose place agent composes its view.
inline constexpr std::size_t kMaxClockServed = 8192;  // idl bound
struct ServedUav {
  uint32_t uav = 0;
  RegionId region = 0;
  double x = 0, y = 0;    // [cell]
  double vx = 0, vy = 0;  // [cell/tick]
  uint8_t heading = 0;
  uint8_t role = 0;
  Cell view{};
  // The deposits it sent so far (UavStateMsg::deposits_sent): a backup that
  // adopts it when its home is killed counts its deposits from there.
  uint64_t deposits_sent = 0;
  bool operator==(const ServedUav&) const = default;
};
// The pose of a state, as a place phase lists it (region left to the caller).
inline ServedUav served_pose(const UavStateMsg& s) {
  return {s.uav, 0, s.x, s.y, s.vx, s.vy, s.heading, s.role, s.view, s.deposits_sent};
}
// A served UAV as a state of `tick`: its pose and the deposits it sent
// (a UAV knows a neighbour by its pose alone, UavCore::receive_neighbour).
inline UavStateMsg neighbour_state(const ServedUav& u, uint32_t tick) {
  UavStateMsg s;
  s.uav = u.uav;
  s.tick = tick;
  s.x = u.x;
  s.y = u.y;
  s.vx = u.vx;
  s.vy = u.vy;
  s.heading = u.heading;
  s.role = u.role;
  s.view = u.view;
  s.deposits_sent = u.deposits_sent;
  return s;
}
struct ClockMsg {
  uint32_t tick = 0;
  uint8_t phase = 0;  // ClockPhase
  // UAV phase k: what UAV phase k-1 produced, so that each UAV knows when it
  // holds all of it: the UAVs over each occupied tile, the broadcasts.
  uint32_t broadcasts = 0;
  std::vector<TileCount> occupancy;
  // Place phase k: the deposits of tick k each region must apply.
  std::vector<RegionCount> deposits;
  // Regions whose place agent is gone without a standby (core/faults.hpp,
  // "kill place:R @kt"), from the tick it was killed at: no one waits for
  // their tiles, halo or views; their tiles are in no view (dark).
  std::vector<RegionId> absent;
  // Place phase k: how many UAV states of tick k each region's place agent
  // must hold before it composes the views (its home UAVs that took part in
  // UAV phase k). It waits for these exact samples instead of the UAVs
  // waiting for acknowledgements.
  std::vector<RegionCount> states;
  // Place phase k: every UAV whose state of tick k the conductor accepted,
  // with its gateway (LockstepConductor::announce). Each place agent learns
  // from it which tiles every other region's views need and which
  // neighbours to show; no place agent sends its served UAVs to the others.
  std::vector<ServedUav> served;
  // Place phase k: the UAV phase k+1 begins with it (the conductor does not
  // wait for every place agent's report before it: LockstepConductor::
  // begin_phase); `broadcasts` and `occupancy` are that UAV phase's. Each
  // place agent relays the UAV clock (uav_clock_begun_by) at once, and a UAV
  // acts on it once its view of place tick k is here.
  bool next_uav_phase = false;
  // Not on the wire: who wrote the sample, as the receiving bus identifies
  // the DDS writer (Cyclone: its publication handle; Fast DDS: its GUID,
  // folded). A UAV's bus names the writer's process instead
  // (bus::Bus::take_clock): a place agent gives it the clock through two
  // writers, relayed or in its view (ViewMsg::clock). A forger can copy
  // every field but not this (plausibility.hpp).
  uint64_t writer = 0;
  // Not on the wire: the writer's process (bus::SampleInfo::participant).
  uint64_t participant = 0;
};
inline constexpr uint32_t kRoleUav = 1;
inline constexpr uint32_t kRolePlace = 2;
inline constexpr uint32_t kRoleGround = 3;
inline constexpr uint32_t kProcessIdMask = 0xFFFFFFU;  // the id bits of a process key
inline constexpr uint32_t process_key(uint32_t role, uint32_t id) { return role << 24U | (id & kProcessIdMask); }
struct PhaseDoneMsg {
  uint32_t process = 0;  // process_key(role, id)
  uint32_t tick = 0;
  uint8_t phase = 0;
  // UAV phase: what the UAV wrote (broadcasts 0 or 1, deposits per region).
  uint32_t broadcasts = 0;
  std::vector<RegionCount> deposits;
  // Not on the wire: the writer's process (bus::SampleInfo::participant),
  // by which the conductor and the gateways judge a report (sender_judge.hpp).
  uint64_t participant = 0;
};

// The place agent that serves a UAV: it receives the UAV's state and
// deposits and sends it its view. Fixed for the whole run, so a UAV's DDS
// endpoints never change while it flies (docs/architecture.md, "Views").
inline constexpr RegionId home_region(uint32_t uav, uint32_t region_count) {
  return region_count == 0 ? 0 : uav % region_count;
}

// The UAV's backup gateway: the place agent its radio link falls back on
// while its home's is dead (no standby): the next region.
inline constexpr RegionId backup_region(uint32_t uav, uint32_t region_count) {
  return region_count <= 1 ? 0 : (home_region(uav, region_count) + 1) % region_count;
}

// The place agent a UAV talks to while the regions `dead(r)` says are dead:
// its home, else its backup; none when both are dead (the UAV flies blind and
// its deposits are lost). Deposits still go to their owners through it, so a
// dead place agent darkens exactly its region (core/faults.hpp).
template <typename Dead>
std::optional<RegionId> gateway_region(uint32_t uav, uint32_t region_count, Dead&& dead) {
  const RegionId home = home_region(uav, region_count);
  if (!dead(home)) return home;
  const RegionId backup = backup_region(uav, region_count);
  if (backup != home && !dead(backup)) return backup;
  return std::nullopt;
}

inline constexpr std::size_t kMaxViewTiles = 1024;  // idl bounds
inline constexpr std::size_t kMaxViewUavs = 1024;
inline constexpr std::size_t kMaxFieldTiles = 256;
inline constexpr std::size_t kMaxFieldUavs = 1024;

// What one UAV reads at a tick (idl View): its neighbourhood's tiles of
// `tick` and the states of the other UAVs over them.
struct ViewMsg {
  uint32_t uav = 0;
  uint32_t tick = 0;
  std::vector<TileMsg> tiles;  // tick and region filled in
  std::vector<UavStateMsg> uavs;
  uint32_t deposit_ack = 0;       // highest seq of this UAV's deposits its home place agent received
  uint32_t deposit_ack_from = 0;  // the first seq of them this life of the place agent received (0: none)
  // Lockstep: the UAV clock of tick + 1 that this view's place phase began
  // (idl View.clock), or none. The receiving bus hands it out as a clock
  // (bus::Bus::take_clock), not with the view.
  std::optional<ClockMsg> clock;
  // Not on the wire: the writer's process (bus::SampleInfo::participant).
  uint64_t participant = 0;
};

// One chunk of a region's field of `tick` and of the latest states of the
// UAVs homed there (idl RegionField).
struct FieldMsg {
  RegionId region = 0;
  uint16_t chunk = 0;
  uint16_t chunks = 1;
  uint32_t tick = 0;
  std::vector<TileMsg> tiles;  // tick and region filled in
  std::vector<UavStateMsg> uavs;
  uint16_t replica = 0;  // the place replica that wrote it
  // Relayed states (lockstep): the gateway's reports of its UAVs' UAV phase
  // (core::UplinkReports), each a PhaseDoneMsg of role UAV and phase Uav,
  // in the sample of the states they belong with: one sample up, not one
  // per UAV. Bound kMaxFieldUavs.
  std::vector<PhaseDoneMsg> reports;
  // Not on the wire: the writer's process (bus::SampleInfo::participant),
  // as the receiving bus names it; 0 if unknown or written by this process.
  uint64_t participant = 0;
};

// Semantic checks of received samples (the bus checks structure). Each returns
// a short reason, or nullopt if the sample is acceptable.
// `layers` is the number of layers of the scenario's policy.
std::optional<std::string> check_deposit(const DepositMsg& d, const MapGeometry& geo, RegionId owner, int layers);
std::optional<std::string> check_tile(const TileMsg& t, const MapGeometry& geo, int layers);
std::optional<std::string> check_broadcast(const BroadcastMsg& b);
std::optional<std::string> check_uav_state(const UavStateMsg& s, const MapGeometry& geo);
// Rings are either both empty (a policy without diffusion) or both the
// size of the sender's border ring.
std::optional<std::string> check_halo(const HaloMsg& h, const MapGeometry& geo);

// A process's received traffic, measured the same way on every transport:
// the bytes of a message's fields as the core holds them (its fixed part,
// sizeof, plus the elements of its sequences and strings). DDS and UDP
// headers are left out, so the figure compares designs, not vendors.
std::size_t payload_bytes(const TileMsg& m);
std::size_t payload_bytes(const ViewMsg& m);
std::size_t payload_bytes(const FieldMsg& m);
std::size_t payload_bytes(const HaloMsg& m);
std::size_t payload_bytes(const BroadcastMsg& m);
std::size_t payload_bytes(const ClockMsg& m);
std::size_t payload_bytes(const PhaseDoneMsg& m);
std::size_t payload_bytes(const ScenarioMsg& m);
std::size_t payload_bytes(const UavStateMsg& m);
std::size_t payload_bytes(const DepositBatchMsg& m);
// Messages without sequences: their fixed part.
template <typename M>
requires std::is_trivially_copyable_v<M> std::size_t payload_bytes(const M& /*m*/) { return sizeof(M); }

}  // namespace pheromesh::core
