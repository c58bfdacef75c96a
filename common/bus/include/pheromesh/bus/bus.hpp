// The pheromesh bus: one small, vendor-neutral interface for the pheromesh
// topics. Nothing above this header includes a DDS vendor header.
//
// Routing (writer-side matching through DDS partitions, so a process receives
// only what it subscribed to). Every endpoint is created once, when a process
// joins; nothing is created, deleted or re-partitioned while a swarm flies
// (docs/architecture.md, "Views"):
//   UAV state    -> "s.<home>": its home place agent and the ground ("s.*")
//   deposits     -> "r.<region>": a UAV writes to its home place agent, which
//                   forwards those for other regions to their owner
//   views        -> "u.<uav>": from the home place agent to that UAV only
//   region fields (tiles + home UAV states) -> "f": place agents, ground
//   halo rings   -> "h.<region>" of the sender
//   UAV broadcasts (to the whole swarm) -> "b"
//   lockstep clock and phase reports  -> "c"
//   detections, target events, health -> "g"
//   ground-station commands           -> "k"
//   tiles (TileState; only test probes write them now) -> "t.<tx>.<ty>"
#pragma once

#include <chrono>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/result.hpp"
#include "pheromesh/bus/qos.hpp"

namespace pheromesh::bus {

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
  // Hot-standby place agents in this swarm (qos.hpp, docs/faults.md).
  Replication replication;
  // DDS Security (security.hpp, docs/security.md): the directory `pheromesh
  // security init` made, and the identity in it this process uses (empty:
  // its process_name). Empty secure_dir: no security, the open profile.
  std::string secure_dir;
  std::string identity;
};

// Samples dropped by the bus itself (structurally malformed: sequence bounds,
// unknown enum values) and writes it refused.
struct BusStats {
  uint64_t samples_dropped = 0;
  uint64_t writes_refused = 0;
  uint64_t writes_failed = 0;
};

class Bus {
 public:
  virtual ~Bus() = default;
  Bus() = default;
  Bus(const Bus&) = delete;
  Bus& operator=(const Bus&) = delete;

  [[nodiscard]] virtual std::string vendor() const = 0;

  // --- publishing; false if the sample was refused (bounds) or the write failed
  virtual bool publish_tile(const core::TileMsg& m) = 0;
  // Into the deposit partition of `via`: a UAV's home place agent, or the
  // owner m.region when a place agent forwards it.
  virtual bool publish_deposit(const core::DepositMsg& m, core::RegionId via) = 0;
  virtual bool publish_uav_state(const core::UavStateMsg& m) = 0;  // to the home given to join_uav
  virtual bool publish_view(const core::ViewMsg& m) = 0;           // to UAV m.uav
  virtual bool publish_field(const core::FieldMsg& m) = 0;
  virtual bool publish_detection(const core::DetectionMsg& m) = 0;
  virtual bool publish_target_event(const core::TargetEventMsg& m) = 0;
  virtual bool publish_health(const core::HealthMsg& m) = 0;
  virtual bool publish_halo(const core::HaloMsg& m) = 0;
  virtual bool publish_broadcast(const core::BroadcastMsg& m) = 0;  // to partition "b"

  // --- lockstep clock
  virtual bool publish_clock(const core::ClockMsg& m) = 0;       // conductor
  virtual bool publish_phase_done(const core::PhaseDoneMsg& m) = 0;
  virtual void subscribe_clock() = 0;                             // UAVs and place agents
  virtual void subscribe_phase_done() = 0;                        // conductor
  virtual void take_clock(std::vector<core::ClockMsg>& out) = 0;
  virtual void take_phase_done(std::vector<core::PhaseDoneMsg>& out) = 0;

  // --- ground-station commands (pause, pop-ups): the ground station
  // writes, every UAV and place agent reads, late joiners get the history.
  virtual bool publish_command(const core::CommandMsg& m) = 0;
  // --- the run's scenario (place agents publish it once, transient-local;
  // a monitor that attaches with only the domain id reads it)
  virtual bool publish_scenario(const core::ScenarioMsg& m) = 0;
  virtual void subscribe_scenario() = 0;
  virtual void take_scenarios(std::vector<core::ScenarioMsg>& out) = 0;
  virtual void subscribe_commands() = 0;
  virtual void take_commands(std::vector<core::CommandMsg>& out) = 0;

  // --- joining and subscribing (each once per process)
  // A UAV: its state writer and deposit writer towards its home place agent,
  // its view reader, its detection writer and (if its policy broadcasts) its
  // broadcast writer: every endpoint it writes with, before it flies.
  virtual void join_uav(uint32_t uav, core::RegionId home, bool broadcasts = false) = 0;
  // A place agent: deposits for `own` (from its UAVs and forwarded), the
  // states of the UAVs homed on it, and every region's field.
  virtual void subscribe_deposits(core::RegionId own) = 0;
  virtual void subscribe_home_states(core::RegionId own) = 0;
  virtual void subscribe_fields() = 0;
  // A place agent: the view writers of the UAVs homed on it, created before
  // they fly (publish_view would otherwise create one on first use).
  virtual void offer_views(std::span<const uint32_t> uavs) = 0;
  virtual void subscribe_halos(std::span<const core::RegionId> neighbours) = 0;
  // Everything the ground station needs: every region's field, all UAV
  // states, detections, target events, health.
  virtual void subscribe_ground() = 0;
  // Every UAV's broadcasts (UAVs and the ground station).
  virtual void subscribe_broadcasts() = 0;

  // --- taking: append what arrived since the last call
  virtual void take_deposits(std::vector<core::DepositMsg>& out) = 0;
  virtual void take_halos(std::vector<core::HaloMsg>& out) = 0;
  // Tiles of the fields (and of TileState writers), ground station only.
  virtual void take_tiles(std::vector<core::TileMsg>& out) = 0;
  virtual void take_fields(std::vector<core::FieldMsg>& out) = 0;
  virtual void take_views(std::vector<core::ViewMsg>& out) = 0;
  virtual void take_uav_states(std::vector<core::UavStateMsg>& out) = 0;
  virtual void take_detections(std::vector<core::DetectionMsg>& out) = 0;
  virtual void take_target_events(std::vector<core::TargetEventMsg>& out) = 0;
  virtual void take_health(std::vector<core::HealthMsg>& out) = 0;
  virtual void take_broadcasts(std::vector<core::BroadcastMsg>& out) = 0;
  // UAVs (ground subscription) whose every writer vanished (liveliness lost or
  // process ended) since the last call.
  virtual void take_departed_uavs(std::vector<uint32_t>& out) = 0;
  // Place replicas (ground subscription) whose health writer vanished, as
  // core::place_id(region, replica).
  virtual void take_departed_regions(std::vector<uint32_t>& out) = 0;

  // Block until one of this process's readers of `kinds` holds a sample not
  // yet taken (or a departure notice), or `deadline` passes; true if one
  // does. Backed by the vendor's own wait set, so no process polls. Wait only
  // on kinds the caller then takes, or the wait returns at once.
  virtual bool wait(std::initializer_list<TopicKind> kinds, std::chrono::steady_clock::time_point deadline) = 0;

  // Block until every reliable sample written so far is acknowledged by the
  // matched readers, or the timeout passes. Returns true if all were acked.
  virtual bool flush(std::chrono::milliseconds timeout) = 0;
  // The same for this process's writers of `kinds` only (lockstep: the
  // samples a phase must have delivered; a killed process's readers stay
  // matched until its participant lease ends and never acknowledge).
  virtual bool flush(std::initializer_list<TopicKind> kinds, std::chrono::milliseconds timeout) = 0;

  // Readers matched by this process's deposit writer into the partition of
  // `region` (a UAV: its home place agent before depositing).
  [[nodiscard]] virtual uint32_t matched_deposit_readers(core::RegionId region) = 0;
  // Readers matched by this UAV's state writer (its home place agent and the
  // ground station; 0 before join_uav).
  [[nodiscard]] virtual uint32_t matched_state_readers() = 0;

  [[nodiscard]] virtual BusStats stats() const = 0;
};

// Vendors compiled into this build, e.g. {"cyclone"}.
std::vector<std::string> available_vendors();
// The vendor chosen by --dds, else $PHEROMESH_DDS, else "cyclone".
std::string default_vendor();
core::Result<std::unique_ptr<Bus>> make_bus(const std::string& vendor, const BusOptions& options);

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
