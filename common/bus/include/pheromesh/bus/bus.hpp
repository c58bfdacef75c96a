// The pheromesh bus: one vendor-neutral bus for the pheromesh topics over
// one small vendor seam (transport.hpp). Nothing above this header includes
// a DDS vendor header.
//
//   bus.hpp       Bus: the roles' wiring and thin publish_* / take_* wrappers
//   typed.hpp     Writer<M>, Reader<M>: typed endpoints, IDL bounds checked once
//   topic.hpp     Topic<M>: kind (names, QoS), key, routing rule, bounds;
//                 how to add a topic (one trait + one Convert<M> per vendor)
//   transport.hpp Transport: the 10 virtual methods a vendor implements
//   memory.hpp    the in-memory transport, for unit tests
//
// Routing (writer-side matching through DDS partitions, so a process receives
// only what it subscribed to). Every endpoint is created once, when a process
// joins; nothing is created, deleted or re-partitioned while a swarm flies
// (docs/architecture.md, "Views"):
//   UAV state and its deposits (its uplink) -> "s.<gateway>": its gateway
//                   place agent (its home, or its backup once the home is gone)
//   deposits     -> "r.<region>": a place agent forwards those of its UAVs
//                   for other regions to their owner
//   views        -> "u.<uav>": from the home place agent to that UAV only
//   region fields (tiles + home UAV states) -> "f": the ground station
//   served UAV states -> "p": every other place agent  } PlaceField: a topic
//   tiles for a home's views -> "f.<home>": that place   } of their own
//                   agent only
//   halo rings   -> "h.<from>.<to>": what neighbour <to> reads of <from>'s border ring
//   UAV broadcasts (to the whole swarm) -> "bu.<gateway>", relayed by the
//                   gateway to "b" (every place agent, the ground), and by
//                   every place agent to the UAVs it serves ("bd.<region>")
//   lockstep clock and phase reports  -> "c" (relayed: "c.<region>", "d.<region>")
//   detections -> "g.<gateway>", relayed to "g"
//   UAV states and departures, relayed by the place agents -> "g" (GroundState:
//                   one sample per place agent and take, its states batched)
//   target events, health -> "g"
//   ground-station commands -> "k" (the place agents), relayed to "k.<region>" (their UAVs)
//   tiles (TileState; only test probes write them now) -> "t.<tx>.<ty>"
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "pheromesh/bus/cell_discovery.hpp"
#include "pheromesh/bus/qos.hpp"
#include "pheromesh/bus/topic.hpp"
#include "pheromesh/bus/transport.hpp"
#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/result.hpp"

namespace pheromesh::bus {

// The environment variable in which `pheromesh run` tells each process how
// many processes of the swarm its host starts (BusOptions::swarm_processes).
inline constexpr const char* kSwarmProcessesEnv = "PHEROMESH_SWARM_PROCESSES";

struct BusOptions {
  std::string process_name;  // for logs, e.g. "uav-3"
  uint32_t domain = 0;       // DDS domain id, 0..232
  // DDS profile: "onehost" (loopback, multicast discovery, >= 100 processes
  // per host), "onehost-unicast" (loopback, unicast discovery, up to 120),
  // "netns" (one network namespace per process on a bridge, multicast
  // discovery on its phm0 interface: pheromesh run's network faults),
  // "lan" (several hosts, multicast discovery), "lan-unicast" (several
  // hosts, discovery through `peers`), "default" (vendor defaults) or a path
  // to a vendor configuration file.
  std::string profile = "onehost";
  // IPv4 addresses of unicast discovery peers, for the lan profiles
  // (resolve_peers turns --dds-peers into these).
  std::vector<std::string> peers;
  std::chrono::milliseconds liveliness_lease{1000};
  // Fast DDS participant id (ports 7410 + 250 domain + 2 id) given by the
  // launcher so that no two processes search for free ports; -1: search.
  int32_t participant_id = -1;
  // How many processes of the swarm share this host (0: not known), given
  // by the launcher: a Cyclone process of a large one-host swarm asks for
  // acknowledgements less often, so that discovery does not drown in them
  // (dds_profiles.hpp, kQuietHeartbeatAbove).
  uint32_t swarm_processes = 0;
  // Discovery scoped to a cell (cell_discovery.hpp): when set, it replaces
  // the profile's discovery (and the profile's other settings: the cell's are
  // the one-host unicast profile's). A cell's fixed index overrides
  // participant_id.
  std::optional<CellDiscovery> cell;
  // Hot-standby place agents in this swarm (qos.hpp, docs/faults.md).
  Replication replication;
  // The swarm's clock: what a realtime swarm replaces every tick goes best
  // effort (qos.hpp, endpoint_qos). Every process of a swarm must agree.
  Pacing pacing = Pacing::Lockstep;
  // DDS Security (security.hpp, docs/security.md): the directory `pheromesh
  // security init` made, and the identity in it this process uses (empty:
  // its process_name). Empty secure_dir: no security, the open profile.
  std::string secure_dir;
  std::string identity;
};

// The pheromesh bus of one process: the typed endpoints of the roles a
// process plays, over one Transport (a DDS vendor, or the in-memory bus of
// the unit tests). No method is virtual: the vendor seam is Transport
// (transport.hpp), the types are Topic<M> (topic.hpp) and Writer<M> /
// Reader<M> (typed.hpp), which any process may also use directly.
//
// The role methods below (join_uav, subscribe_*, offer_views) are the wiring
// of who writes and reads what (bus.cpp, once for every transport); publish_*
// and take_* are thin wrappers of that role's Writer<M> / Reader<M>.
class Bus {
 public:
  explicit Bus(std::unique_ptr<Transport> transport);
  ~Bus();
  Bus(const Bus&) = delete;
  Bus& operator=(const Bus&) = delete;

  [[nodiscard]] std::string vendor() const;
  [[nodiscard]] Transport& transport() { return *transport_; }

  // --- publishing; false if the sample was refused (bounds) or the write failed
  bool publish_tile(const core::TileMsg& m);
  // Into the deposit partition of `via`, the owner of the deposits: a place
  // agent forwards its home UAVs' deposits for one region in one batch per
  // take (core::deposit_batches; a UAV's deposits travel in its state,
  // UavStateMsg::deposits).
  bool publish_deposits(const core::DepositBatchMsg& m, core::RegionId via);
  // One deposit, as a batch of one (its forwarder: the region this process
  // relays for, else 0; tests, probes and the latency bench).
  bool publish_deposit(const core::DepositMsg& m, core::RegionId via);
  bool publish_uav_state(const core::UavStateMsg& m);  // to the home given to join_uav; BusMisuse before
  bool publish_view(const core::ViewMsg& m);           // to UAV m.uav
  bool publish_field(const core::FieldMsg& m);  // to the ground station ("f")
  // Place agents among themselves: the states of the UAVs one serves this
  // tick, to every other ("p"), and the tiles of its region another's UAVs'
  // views need, to that one ("f.<home>").
  bool publish_served(const core::FieldMsg& m);
  bool publish_tiles_for(const core::FieldMsg& m, core::RegionId home);
  // A UAV's (after join_uav) to its gateway; anyone else's to the ground station.
  bool publish_detection(const core::DetectionMsg& m);
  bool publish_target_event(const core::TargetEventMsg& m);
  bool publish_health(const core::HealthMsg& m);
  // To neighbour `to`: m holds only the ring cells `to` reads (core::trim_halo).
  bool publish_halo(const core::HaloMsg& m, core::RegionId to);
  // A UAV's (after join_uav) to its gateway; anyone else's to "b".
  bool publish_broadcast(const core::BroadcastMsg& m);

  // --- lockstep clock: a tree (docs/architecture.md, "Time"). The conductor
  // and the place agents meet in "c"; each place agent relays every clock
  // it accepted to the UAVs it serves ("c.<region>" to those homed on it,
  // "cb.<region>" to those it is the backup of) and their reports to the
  // conductor ("d.<region>" -> "c").
  bool publish_clock(const core::ClockMsg& m);  // conductor
  // A lockstep UAV's report goes to its gateway place agent (join_clock_tree,
  // move_uplink); anyone else's to the conductor.
  bool publish_phase_done(const core::PhaseDoneMsg& m);
  void subscribe_clock();       // place agents: the conductor's clock
  void subscribe_phase_done();  // conductor
  // A UAV (join_clock_tree): also the clocks its views carry
  // (core::ViewMsg::clock; the views wait for take_views), and each clock
  // names the process that wrote it (ClockMsg::writer), not the DDS writer.
  void take_clock(std::vector<core::ClockMsg>& out);
  void take_phase_done(std::vector<core::PhaseDoneMsg>& out);
  // A lockstep UAV, after join_uav: its report writer to its gateway, and
  // its reader of the clock as its gateways relay it (gateways[0]: its home,
  // to the UAVs homed there; the others: its backups, to the UAVs they back
  // up, so that it hears the tick at which its home is listed absent).
  void join_clock_tree(std::span<const core::RegionId> gateways);
  // A place agent of `own`: its clock writer to the UAVs it serves, its
  // reader of their reports and its writer of reports to the conductor,
  // opened now.
  void subscribe_uav_reports(core::RegionId own);
  // The writer of this process's lockstep reports to the conductor (`c`;
  // a UAV in the clock tree writes to its gateway, join_clock_tree), opened
  // now.
  void offer_phase_done();
  bool relay_clock(const core::ClockMsg& m, core::RegionId own);             // to the UAVs homed on `own`
  bool relay_clock_to_backups(const core::ClockMsg& m, core::RegionId own);  // to those `own` backs up
  void take_uav_reports(std::vector<core::PhaseDoneMsg>& out);
  // Readers matched by this UAV's report writer to its gateway (0 before join_clock_tree).
  [[nodiscard]] uint32_t matched_report_readers();

  // --- relays (docs/architecture.md, "Relays"): a place agent of `own`
  // relays between the UAVs it serves and the rest of the swarm, so that a
  // UAV talks to its gateway place agents only. subscribe_uplinks opens its
  // readers of its UAVs' detections and broadcasts and of the swarm's
  // broadcasts ("b"), and every relay writer.
  void subscribe_uplinks(core::RegionId own);
  void take_uplink_detections(std::vector<core::DetectionMsg>& out);
  void take_uplink_broadcasts(std::vector<core::BroadcastMsg>& out);
  bool relay_detection(const core::DetectionMsg& m);      // to the ground station
  // To the ground station: the states (and departure notes) the place
  // agent of `own` (replica `replica`) admitted in one take, at its tick
  // `tick`, in one sample (GroundState carries a FieldMsg of states only),
  // and after them the lockstep reports it made of its UAVs' UAV phase
  // (FieldMsg::reports; the ground station takes them with take_phase_done).
  bool relay_states(std::span<const core::UavStateMsg> states, core::RegionId own, uint16_t replica, uint32_t tick,
                    std::span<const core::PhaseDoneMsg> reports = {});
  bool relay_broadcast_up(const core::BroadcastMsg& m);   // to every place agent and the ground
  bool relay_broadcast_down(const core::BroadcastMsg& m); // to the UAVs it serves
  bool relay_command(const core::CommandMsg& m);          // to the UAVs it serves
  // A UAV, after join_uav: the place agents it hears the swarm through (its
  // home and its backup); subscribe_commands and subscribe_broadcasts then
  // read what they relay.
  void join_gateways(std::span<const core::RegionId> gateways);

  // --- ground-station commands (pause, pop-ups): the ground station
  // writes, every UAV and place agent reads, late joiners get the history.
  bool publish_command(const core::CommandMsg& m);
  // --- the run's scenario (place agents publish it once, transient-local;
  // a monitor that attaches with only the domain id reads it)
  bool publish_scenario(const core::ScenarioMsg& m);
  void subscribe_scenario();
  void take_scenarios(std::vector<core::ScenarioMsg>& out);
  void subscribe_commands();
  void take_commands(std::vector<core::CommandMsg>& out);

  // --- joining and subscribing (each once per process)
  // A UAV: its state writer towards its home place agent (the state carries
  // its deposits), its view reader, its detection writer and (if its policy
  // broadcasts) its broadcast writer: every endpoint it writes with, before
  // it flies.
  void join_uav(uint32_t uav, core::RegionId home, bool broadcasts = false);
  // A UAV whose home place agent died: its state (and so its deposits) goes
  // to `gateway` (its backup) from now on (new writers; the rare endpoint
  // change). True if the bus had to name its cell's reserve peers first
  // (Transport::reach_reserve: a realtime UAV in cells discovers its backup
  // only now, so the writes wait in the new writers' histories until it
  // matches).
  bool move_uplink(core::RegionId gateway);
  // A place agent: deposits for `own` (from its UAVs and forwarded), the
  // states of the UAVs homed on it (and their departures:
  // take_departed_uavs), and every region's field.
  // history false (a place agent started again): none of the deposits
  // written before it matched (its dead life counted them).
  void subscribe_deposits(core::RegionId own, bool history = true);
  void subscribe_home_states(core::RegionId own, bool history = true);
  void subscribe_fields();  // the ground station
  // A place agent: the other place agents' served states (`served`: only in
  // realtime; in lockstep the place clock lists them) and the tiles sent
  // for its own UAVs' views; and its writers of both, opened now.
  void subscribe_place_exchange(core::RegionId own, bool served = true);
  void offer_place_exchange(std::span<const core::RegionId> others, bool served = true);
  // A place agent: the view writers of the UAVs homed on it, created before
  // they fly (publish_view would otherwise create one on first use).
  void offer_views(std::span<const uint32_t> uavs);
  // Deposit writers into these regions' partitions, opened now (a place
  // agent forwards its home UAVs' deposits with them; made before the swarm flies).
  void offer_deposits(std::span<const core::RegionId> regions);
  // A place agent: what its neighbours send it of their border rings.
  void subscribe_halos(std::span<const core::RegionId> neighbours, core::RegionId own);
  // Everything the ground station needs: every region's field, all UAV
  // states, detections, target events, health.
  void subscribe_ground();
  // Only the place agents' and UAVs' health (part of subscribe_ground).
  void subscribe_health();
  // Every UAV's broadcasts (UAVs and the ground station).
  void subscribe_broadcasts();

  // --- taking: append what arrived since the last call (a role not
  // subscribed takes nothing). Every take keeps this process's
  // manual-by-topic writers alive (Transport::keep_alive).
  // Each deposit of the batches taken, in order, as if it had come alone
  // (its participant: the batch's writer's).
  void take_deposits(std::vector<core::DepositMsg>& out);
  void take_halos(std::vector<core::HaloMsg>& out);
  // Tiles of the fields (and of TileState writers), ground station only.
  void take_tiles(std::vector<core::TileMsg>& out);
  void take_fields(std::vector<core::FieldMsg>& out);
  void take_served(std::vector<core::FieldMsg>& out);
  void take_tiles_for_views(std::vector<core::FieldMsg>& out);
  // Views without their clock: a lockstep UAV's go to take_clock, any
  // other's are dropped (a place agent attaches them in lockstep only).
  void take_views(std::vector<core::ViewMsg>& out);
  void take_uav_states(std::vector<core::UavStateMsg>& out);
  void take_detections(std::vector<core::DetectionMsg>& out);
  void take_target_events(std::vector<core::TargetEventMsg>& out);
  void take_health(std::vector<core::HealthMsg>& out);
  void take_broadcasts(std::vector<core::BroadcastMsg>& out);
  // UAVs whose every state writer vanished (liveliness lost or process
  // ended) since the last call: a place agent's home UAVs, as its reader
  // saw it; the ground station's, as the place agents relayed it (with the
  // tick of the last state the relaying place agent held: UavDeparture).
  void take_departed_uavs(std::vector<core::UavDeparture>& out);
  // Place replicas (ground subscription) whose health writer vanished, as
  // core::place_id(region, replica).
  void take_departed_regions(std::vector<uint32_t>& out);

  // Block until one of this process's readers of `kinds` holds a sample not
  // yet taken (or a departure notice), or `deadline` passes; true if one
  // does. Backed by the vendor's own wait set, so no process polls. Wait only
  // on kinds the caller then takes, or the wait returns at once.
  bool wait(std::initializer_list<TopicKind> kinds, std::chrono::steady_clock::time_point deadline);
  bool wait_any(std::span<const TopicKind> kinds, std::chrono::steady_clock::time_point deadline);
  // Call `callback` in the vendor's receive thread whenever one of this
  // process's readers of `kinds` gets a sample (Transport::on_data); an
  // empty callback removes it, once no call is under way. False where the
  // transport has no receive thread (then only wait() wakes). The callback
  // must create no endpoint (Writer::offer throws BusMisuse there): a
  // vendor's receive thread that creates one can deadlock (Fast DDS 2.9:
  // the new writer waits for the lock the receive thread holds).
  bool on_data(std::span<const TopicKind> kinds, std::function<void()> callback);
  // Whether this thread is in an on_data callback now.
  [[nodiscard]] static bool in_data_callback();

  // Block until every reliable sample written so far is acknowledged by the
  // matched readers, or the timeout passes. Returns true if all were acked.
  bool flush(std::chrono::milliseconds timeout);
  // The same for this process's writers of `kinds` only (lockstep: the
  // samples a phase must have delivered; a killed process's readers stay
  // matched until its participant lease ends and never acknowledge).
  bool flush(std::initializer_list<TopicKind> kinds, std::chrono::milliseconds timeout);

  // Readers matched by this process's deposit writer into the partition of
  // `region` (a place agent: the owner it forwards to); 0 if it has no such
  // writer. A query only: the writers are opened by offer_deposits.
  [[nodiscard]] uint32_t matched_deposit_readers(core::RegionId region) const;
  // A place agent's readers of what it sends the others: the tiles for the
  // views of `home`'s UAVs (offer_place_exchange), its ring to `neighbour`
  // (offer_halos).
  [[nodiscard]] uint32_t matched_tile_readers(core::RegionId home) const;
  [[nodiscard]] uint32_t matched_halo_readers(core::RegionId own, core::RegionId neighbour) const;
  // Opens the writers of a place agent's health, field and target events
  // (to the ground station) before flying: a lockstep place agent writes in
  // its vendor's receive thread, which must not create endpoints (Fast DDS
  // 2.9 deadlocks there: the new writer waits for the receive thread's lock).
  void offer_place_reports();
  // Opens the writers of its rings to its neighbours before flying.
  void offer_halos(std::span<const core::RegionId> neighbours, core::RegionId own);
  // Readers matched by this UAV's state writer to its gateway (the gateway
  // place agent and its standbys; 0 before join_uav).
  [[nodiscard]] uint32_t matched_state_readers();

  [[nodiscard]] BusStats stats() const;

  // --- for Writer<M> / Reader<M> (typed.hpp)
  // Counts and logs a sample not written because it is over an IDL bound.
  bool refuse(const Oversize& o);
  // Counts samples a typed reader took and their payload bytes (BusStats).
  void taken(std::size_t samples, std::size_t bytes) {
    samples_taken_ += samples;
    bytes_taken_ += bytes;
  }
  // Every endpoint opened through this bus, by kind (wait and flush by kind).
  void opened(TopicKind kind, Endpoint endpoint, EndpointId id);

 private:
  struct Roles;  // the role endpoints (bus.cpp)
  std::unique_ptr<Transport> transport_;
  std::unique_ptr<Roles> roles_;
  std::vector<std::pair<TopicKind, EndpointId>> writers_, readers_;
  uint64_t writes_refused_ = 0;
  uint64_t samples_taken_ = 0, bytes_taken_ = 0;
  std::vector<core::FieldMsg> relayed_batches_;  // take_uav_states' buffer
  std::vector<core::ViewMsg> held_views_;        // taken by take_clock, for take_views
  std::vector<core::ClockMsg> view_clocks_;      // lifted out of views, for take_clock
  void lift_clocks(std::vector<core::ViewMsg>& views, std::size_t first);
};

// Vendors compiled into this build, e.g. {"cyclone"}.
std::vector<std::string> available_vendors();
// The vendor chosen by --dds, else $PHEROMESH_DDS, else "cyclone".
std::string default_vendor();
// The vendor's transport. pheromesh::bus links both vendors in; the
// pheromesh programs load the one they use from its DDS module
// (libpheromesh_dds_<vendor>.so in lib/pheromesh).
core::Result<std::unique_ptr<Transport>> make_transport(const std::string& vendor, const BusOptions& options);
// The vendor's transport in a Bus.
inline core::Result<std::unique_ptr<Bus>> make_bus(const std::string& vendor, const BusOptions& options) {
  auto t = make_transport(vendor, options);
  if (!t) return t.error();
  return std::make_unique<Bus>(std::move(t).value());
}

// The lan profiles' discovery peers from a comma-separated list of IPv4
// addresses and host names (--dds-peers, $PHEROMESH_DDS_PEERS): every IPv4
// address of each name, in order, without repeats. A name that does not
// resolve (yet: a Kubernetes pod not started) is left out and named in
// `unresolved`; an entry that is neither an address nor a host name is an
// error.
struct ResolvedPeers {
  std::vector<std::string> addresses;
  std::vector<std::string> unresolved;
};
core::Result<ResolvedPeers> resolve_peers(const std::string& list);

}  // namespace pheromesh::bus
