// The pheromesh bus: one small, vendor-neutral interface for the pheromesh
// topics. Nothing above this header includes a DDS vendor header.
//
// Routing (writer-side matching through DDS partitions, so a process receives
// only what it subscribed to):
//   tiles, UAV states for neighbours  -> partition "t.<tx>.<ty>" of the tile
//   deposits                          -> partition "r.<region>" of the owner
//   halo rings                        -> partition "h.<region>" of the sender
//   UAV broadcasts (to the whole swarm) -> partition "b"
//   lockstep clock and phase reports  -> partition "c"
//   UAV states for the ground station, detections, target events, health
//                                     -> partition "g"
//   ground-station commands           -> partition "k"
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/result.hpp"

namespace pheromesh::bus {

struct BusOptions {
  std::string process_name;  // for logs, e.g. "uav-3"
  uint32_t domain = 0;       // DDS domain id, 0..232
  // DDS profile: "onehost" (loopback, multicast discovery, >= 100 processes
  // per host), "onehost-unicast" (loopback, unicast discovery, up to 120),
  // "default" (vendor defaults) or a path to a vendor configuration file.
  std::string profile = "onehost";
  std::chrono::milliseconds liveliness_lease{1000};
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
  virtual bool publish_deposit(const core::DepositMsg& m) = 0;                  // to m.region
  virtual bool publish_uav_state(const core::UavStateMsg& m, core::TileCoord over) = 0;
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
  virtual void subscribe_commands() = 0;
  virtual void take_commands(std::vector<core::CommandMsg>& out) = 0;

  // --- subscribing (call once per kind; set_neighbourhood as often as needed)
  virtual void subscribe_deposits(core::RegionId own) = 0;
  virtual void subscribe_halos(std::span<const core::RegionId> neighbours) = 0;
  // Tiles and neighbour UAV states of exactly these tiles; readers for tiles
  // no longer listed are deleted.
  virtual void set_neighbourhood(std::span<const core::TileCoord> tiles) = 0;
  // Everything the ground station needs: all tiles, all UAV states,
  // detections, target events, health.
  virtual void subscribe_ground() = 0;
  // Every UAV's broadcasts (UAVs and the ground station).
  virtual void subscribe_broadcasts() = 0;

  // --- taking: append what arrived since the last call
  virtual void take_deposits(std::vector<core::DepositMsg>& out) = 0;
  virtual void take_halos(std::vector<core::HaloMsg>& out) = 0;
  virtual void take_tiles(std::vector<core::TileMsg>& out) = 0;
  virtual void take_uav_states(std::vector<core::UavStateMsg>& out) = 0;
  virtual void take_detections(std::vector<core::DetectionMsg>& out) = 0;
  virtual void take_target_events(std::vector<core::TargetEventMsg>& out) = 0;
  virtual void take_health(std::vector<core::HealthMsg>& out) = 0;
  virtual void take_broadcasts(std::vector<core::BroadcastMsg>& out) = 0;
  // UAVs (ground subscription) whose every writer vanished (liveliness lost or
  // process ended) since the last call.
  virtual void take_departed_uavs(std::vector<uint32_t>& out) = 0;
  // Place agents (ground subscription) whose health writer vanished.
  virtual void take_departed_regions(std::vector<core::RegionId>& out) = 0;

  // Block until every reliable sample written so far is acknowledged by the
  // matched readers, or the timeout passes. Returns true if all were acked.
  virtual bool flush(std::chrono::milliseconds timeout) = 0;

  // Number of readers currently matched by this process's deposit writers,
  // summed (used to wait for a place agent before depositing).
  [[nodiscard]] virtual uint32_t matched_deposit_readers(core::RegionId region) = 0;

  [[nodiscard]] virtual BusStats stats() const = 0;
};

// Vendors compiled into this build, e.g. {"cyclone"}.
std::vector<std::string> available_vendors();
// The vendor chosen by --dds, else $PHEROMESH_DDS, else "cyclone".
std::string default_vendor();
core::Result<std::unique_ptr<Bus>> make_bus(const std::string& vendor, const BusOptions& options);

}  // namespace pheromesh::bus
