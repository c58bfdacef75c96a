// Discovery scoped to a cell (issue 25): a participant that announces itself
// only to the participants named here, by unicast, and to nobody else.
//
// Standard discovery makes every participant of a domain discover every
// other one, which costs ~N^2 and stops a 2-core host at ~100-150 UAV
// processes (docs/dds.md, "Scale"). In a cell a UAV names only its gateway
// place agent (and a standby); the gateway, which has a well-known port,
// learns each UAV from the UAV's own announcement and answers it. Neither
// vendor gossips participants, so a UAV never learns the other UAVs.
//
// The functions here only write each vendor's configuration text (no vendor
// header), so that a launcher can make one per process and a unit test can
// read it; the transports apply it (BusOptions::cell).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "pheromesh/core/result.hpp"

namespace pheromesh::bus {

// The standard RTPS port mapping, which Cyclone and Fast DDS both use by
// default (DDSI-RTPS 2.2, 9.6.1.1): participant `index` of domain `domain`
// receives discovery unicast on 7400 + 250 domain + 10 + 2 index and user
// data on the port after it.
inline constexpr uint32_t kPortBase = 7400;
inline constexpr uint32_t kDomainGain = 250;
inline constexpr uint32_t kParticipantGain = 2;
inline constexpr uint32_t kUnicastDiscoveryOffset = 10;
// The largest domain id the mapping allows (the spec's, and Cyclone's check).
inline constexpr uint32_t kMaxDomainId = 232;
// Cyclone's configuration takes participant indices below 120; such an
// index also keeps a participant's ports inside its domain's block of 250.
inline constexpr uint32_t kMaxParticipantIndex = 119;
// Linux hands out ports from 32768 up (net.ipv4.ip_local_port_range) to any
// socket bound to port 0, Cyclone's members among them: a well-known port
// there can be taken before its owner starts.
inline constexpr uint32_t kEphemeralPortsFrom = 32768;

[[nodiscard]] constexpr uint32_t unicast_discovery_port(uint32_t domain, uint32_t index) {
  return kPortBase + kDomainGain * domain + kUnicastDiscoveryOffset + kParticipantGain * index;
}

// A participant this one announces itself to: its host and its participant
// index in the cell's domain (its port is unicast_discovery_port).
struct CellPeer {
  std::string address;  // IPv4 address
  uint32_t index = 0;
};

struct CellDiscovery {
  uint32_t domain = 0;
  // This participant's fixed participant index: a hub (gateway), whose
  // discovery port its members name. None: a member, whose ports nobody
  // needs to know beforehand (Cyclone: chosen by the kernel; Fast DDS: from
  // BusOptions::participant_id, else the first free index).
  std::optional<uint32_t> index;
  // The only participants it announces itself to: a member's hub and
  // standby; a hub's fellow hubs and the ground station. A hub with no peers
  // only answers the members that announce themselves to it (for Cyclone it
  // names itself: Cyclone would otherwise add localhost at indices 0-9).
  std::vector<CellPeer> peers;
  // Peers it names only when told to (Transport::reach_reserve): a realtime
  // UAV's backup gateway, whose place agent it talks to only once its home is
  // gone. Discovering it ahead doubled the members of every place agent's
  // cell and, at 500 UAVs in 16 cells, more than doubled the swarm's
  // discovery time and CPU (docs/dds.md, "Cell discovery").
  std::vector<CellPeer> reserve;
  // The one address it binds and sends from (loopback on one host).
  std::string interface_address = "127.0.0.1";
};

// A cell as one line of text, as `pheromesh run` hands it to each process
// it spawns in $PHEROMESH_CELL (--dds-profile cells):
//   [index=I;]peers=ADDR:I[,ADDR:I...][;reserve=ADDR:I[,ADDR:I...]][;iface=ADDR]
// (iface: the address it binds, when not loopback: its host's on a LAN), e.g. "index=3;peers=127.0.0.1:0,127.0.0.1:4" (a hub) or
// "peers=127.0.0.1:2;reserve=127.0.0.1:3" (a member whose backup gateway is
// hub 3). The domain is the process's.
inline constexpr const char* kCellEnv = "PHEROMESH_CELL";
std::string format_cell(const CellDiscovery& cell);
// The cell of `text` in `domain`, checked (check_cell); an error names the
// part that is wrong.
core::Result<CellDiscovery> parse_cell(const std::string& text, uint32_t domain);

// The cell if every port it implies is a valid well-known port (domain id,
// index and ports below the ephemeral range), else an error naming the field.
core::Result<CellDiscovery> check_cell(const CellDiscovery& cell);

// Cyclone DDS configuration XML (a <CycloneDDS> document for
// dds_create_domain): no multicast, the peers with their ports, the
// participant index or none, and the one-host profile's other settings,
// its heartbeat interval for `swarm_processes` among them (cyclone_heartbeat
// in dds_profiles.hpp).
std::string cyclone_cell_config(const CellDiscovery& cell, uint32_t swarm_processes = 0);

// A Fast DDS XML profile document and the name of its participant profile:
// UDP on the interface only, metatraffic unicast only, initial peers with
// their ports (so no range of participant ids is probed), the participant
// id for a hub. The name (and its transport's id) differs per cell, so that
// several cells' profiles can be loaded into one process.
struct FastDdsCellProfile {
  std::string xml;
  std::string name;
};
FastDdsCellProfile fastdds_cell_profile(const CellDiscovery& cell);

}  // namespace pheromesh::bus
