// How pheromesh routes samples through DDS partitions (see bus.hpp): the
// same on every transport, so that processes of both vendors match.
#pragma once

#include <string>

#include "pheromesh/core/grid.hpp"

namespace pheromesh::bus::routing {

inline std::string tile_partition(core::TileCoord t) {
  return "t." + std::to_string(t.tx) + "." + std::to_string(t.ty);
}
inline std::string region_partition(core::RegionId r) { return "r." + std::to_string(r); }
// A border ring from region `from` to its neighbour `to` (only the cells `to` reads).
inline std::string halo_partition(core::RegionId from, core::RegionId to) {
  return "h." + std::to_string(from) + "." + std::to_string(to);
}
inline std::string home_partition(core::RegionId r) { return "s." + std::to_string(r); }
inline std::string view_partition(uint32_t uav) { return "u." + std::to_string(uav); }
// Local traffic (docs/architecture.md, "Views"): the tiles an owner sends
// one home place agent for its UAVs' views, and the states every place agent
// serves, to the others.
inline std::string tiles_for_partition(core::RegionId home) { return "f." + std::to_string(home); }
inline constexpr const char* kAllTilesFor = "f.*";
// The lockstep tree (docs/architecture.md, "Time"): the clock a place agent
// relays to the UAVs it serves - those homed on it ("c.<r>") and those it is
// the backup of ("cb.<r>": only what they need while their home lives,
// core::UavClockRelay) - and the reports those UAVs send it to relay to the
// conductor (whose own clock and reports travel in "c").
inline std::string uav_clock_partition(core::RegionId gateway) { return "c." + std::to_string(gateway); }
inline std::string uav_backup_clock_partition(core::RegionId backup) { return "cb." + std::to_string(backup); }
inline std::string uav_report_partition(core::RegionId gateway) { return "d." + std::to_string(gateway); }
// Relays (docs/architecture.md, "Relays"): a UAV talks to its gateway place
// agents only. Its detections and broadcasts go up to its gateway, which
// relays them on ("g", "b"); the swarm's broadcasts and the ground station's
// commands come down from its gateways.
inline std::string detection_uplink_partition(core::RegionId gateway) { return "g." + std::to_string(gateway); }
inline std::string broadcast_uplink_partition(core::RegionId gateway) { return "bu." + std::to_string(gateway); }
inline std::string broadcast_downlink_partition(core::RegionId gateway) { return "bd." + std::to_string(gateway); }
inline std::string command_downlink_partition(core::RegionId gateway) { return "k." + std::to_string(gateway); }
inline constexpr const char* kServedPartition = "p";
inline constexpr const char* kAllHomes = "s.*";
inline constexpr const char* kFieldPartition = "f";
inline constexpr const char* kAllTiles = "t.*";
inline constexpr const char* kGroundPartition = "g";
inline constexpr const char* kClockPartition = "c";
inline constexpr const char* kBroadcastPartition = "b";
inline constexpr const char* kCommandPartition = "k";

}  // namespace pheromesh::bus::routing
