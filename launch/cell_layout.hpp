// Where each process of a swarm runs and whom it names in discovery, in
// cells (docs/dds.md, "Cell discovery"; docs/deployment.md), on one host or
// over several. Pure: the launcher plans with it, `pheromesh attach` scans
// with it, and the unit tests pin it (tests/unit/test_cell_layout.cpp).
//
// Placement by locality: place agent R's replica K runs on host (R + K) %
// hosts (a standby on another host than its primary), UAV U on the host of
// its home place agent (home_region), so that a UAV's traffic to its gateway
// stays on its host; the ground station on the ground host.
//
// Hubs (the ground station and every place agent replica) have a fixed
// participant index on their host, so that their discovery ports are known
// beforehand: 0 .. hubs_on(host) - 1, numbered on each host by itself (the
// ground station first, then by replica and region). The participant index
// limit (120) is therefore per host, not per swarm. A UAV is a member: it
// names its gateways by their host's address and index; Cyclone gives it
// ports from the kernel, Fast DDS the participant id member_id(U), past every
// index a hub can have.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "pheromesh/bus/cell_discovery.hpp"
#include "pheromesh/core/result.hpp"

namespace pheromesh::cli {

// A Fast DDS UAV's participant id (its ports): past every hub index.
inline constexpr uint32_t kFirstMemberId = pheromesh::bus::kMaxParticipantIndex + 1;

struct SwarmShape {
  uint32_t regions = 1;
  uint32_t uavs = 0;
  uint32_t replicas = 1;  // place agents per region the swarm may run: 2 with standbys (at the start or on a fault)
  bool lockstep = false;  // a lockstep UAV names its backup gateway from the start
  uint32_t domain = 0;
  uint32_t hosts = 1;
  uint32_t ground_host = 0;
  // Each host's IPv4 address, in host-index order; empty on one host
  // (loopback).
  std::vector<std::string> addresses;
  // UAVs the user pinned to a host (--pin-uavs): UAV id -> host. The others
  // fly beside their home place agent.
  std::map<uint32_t, uint32_t> uav_hosts;
};

// --pin-uavs: "U=H" or "A-B=H" items, comma-separated (UAV ids, host
// indices), each UAV at most once; an error names the item and what is
// wrong with it.
core::Result<std::map<uint32_t, uint32_t>> parse_uav_pins(const std::string& text, uint32_t uavs, uint32_t hosts);

class CellLayout {
 public:
  explicit CellLayout(SwarmShape shape);

  // The host that runs process `index` (replica `replica`) of `role`
  // ("ground", "place", "uav").
  [[nodiscard]] uint32_t host_of(const std::string& role, uint32_t index, uint32_t replica = 0) const;
  // A hub's address and participant index on its host.
  [[nodiscard]] bus::CellPeer hub(const std::string& role, uint32_t index, uint32_t replica = 0) const;
  [[nodiscard]] uint32_t hubs_on(uint32_t host) const;
  [[nodiscard]] uint32_t most_hubs_on_a_host() const;
  // The cell of a process: its peers (and reserve), its index if a hub, the
  // address it binds.
  [[nodiscard]] bus::CellDiscovery cell_of(const std::string& role, uint32_t index, uint32_t replica = 0) const;
  [[nodiscard]] static uint32_t member_id(uint32_t uav) { return kFirstMemberId + uav; }
  [[nodiscard]] std::string address_of(uint32_t host) const;
  // Why these cells cannot be (an index or a port out of range), if they
  // cannot. `fastdds_members`: some UAVs run on Fast DDS (their ports follow
  // member_id).
  [[nodiscard]] std::optional<std::string> check(bool fastdds_members) const;
  [[nodiscard]] const SwarmShape& shape() const { return s_; }

 private:
  SwarmShape s_;
};

// Containers and pods (docs/deploy-containers.md): every process runs alone
// at an address of its own and finds its hubs by name, so every hub takes
// participant index 0 at its address and no index limit applies to the
// swarm. The names are templates: {region} stands for the region's number.
struct HubNames {
  std::string place = "place-{region}";
  std::string ground = "ground";
};
// Why `names` cannot name the hubs (a place template without {region}, a
// placeholder other than {region}, an empty name), if they cannot.
std::optional<std::string> check_hub_names(const HubNames& names);
// The name of the ground station (role "ground") or of region `region`'s
// place agent (role "place").
std::string hub_name(const HubNames& names, const std::string& role, uint32_t region);
// The cell of `role` ("ground", "place", "uav", "monitor") `index` when every
// process is alone at its address: the same peers as CellLayout::cell_of on
// one host with one replica per region, each a hub's *name* at index 0. The
// interface address is left empty: the caller resolves the names and binds
// the address on the route to them (resolve_named_cell in cell_command.hpp).
bus::CellDiscovery named_cell(const SwarmShape& shape, const HubNames& names, const std::string& role, uint32_t index);

// A monitor's cell (`pheromesh attach`): a member of every hub's cell. It
// names indices 0 .. hubs - 1 on every host of `addresses` (loopback if
// none) and binds `interface_address`.
bus::CellDiscovery monitor_cell(uint32_t domain, uint32_t hubs, const std::vector<std::string>& addresses,
                                const std::string& interface_address);

// The address of this host that a datagram to `peer` leaves from (no
// datagram is sent), or nullopt if there is no route.
std::optional<std::string> local_address_towards(const std::string& peer);

// Whether `address` is one of this host's (a socket can bind it).
bool is_local_address(const std::string& address);

}  // namespace pheromesh::cli
