// Vendor-neutral messages carried by the bus. They mirror idl/pheromesh.idl;
// the bus implementations convert between these and the generated types.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "pheromesh/core/grid.hpp"

namespace pheromesh::core {

inline constexpr std::size_t kMaxTileCells = 1024;  // 32 x 32, idl bound
inline constexpr std::size_t kMaxRingCells = 4096;  // idl bound

struct TileMsg {
  uint8_t layer = 0;
  TileCoord tile{};
  uint32_t tick = 0;
  RegionId region = 0;
  uint16_t width = 0, height = 0;  // [cell]
  std::vector<float> values;       // row-major, width*height
};

enum class DepositKind : uint8_t { PathVisit = 0, TargetMark = 1, ObstacleMark = 2 };
inline constexpr uint8_t kDepositKindCount = 3;

struct DepositMsg {
  uint32_t uav = 0;
  uint32_t seq = 0;   // per UAV, strictly increasing
  uint32_t tick = 0;  // UAV tick
  RegionId region = 0;
  uint8_t kind = 0;   // DepositKind
  Cell cell{};
  float amount = 0.0F;
};

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
  bool finished = false;  // last state of a UAV that ended its run
};

struct DetectionMsg {
  uint32_t uav = 0;
  uint32_t tick = 0;
  int32_t target = -1;  // target index in the scenario
  Cell cell{};
};

struct TargetEventMsg {
  RegionId region = 0;
  uint32_t tick = 0;
  uint8_t kind = 0;  // MarkEvent::Kind
  Cell cell{};
  uint32_t response_ticks = 0;
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
};

struct HaloMsg {
  RegionId region = 0;
  uint32_t tick = 0;
  std::vector<float> target;
  std::vector<float> obstacle;
};

// Lockstep clock (DESIGN.md, "Time").
enum class ClockPhase : uint8_t { Uav = 0, Place = 1, Stop = 2 };
struct ClockMsg {
  uint32_t tick = 0;
  uint8_t phase = 0;  // ClockPhase
};
inline constexpr uint32_t kRoleUav = 1;
inline constexpr uint32_t kRolePlace = 2;
inline constexpr uint32_t process_key(uint32_t role, uint32_t id) { return role << 24U | (id & 0xFFFFFFU); }
struct PhaseDoneMsg {
  uint32_t process = 0;  // process_key(role, id)
  uint32_t tick = 0;
  uint8_t phase = 0;
};

// Semantic checks of received samples (the bus checks structure). Each returns
// a short reason, or nullopt if the sample is acceptable.
std::optional<std::string> check_deposit(const DepositMsg& d, const MapGeometry& geo, RegionId owner);
std::optional<std::string> check_tile(const TileMsg& t, const MapGeometry& geo);
std::optional<std::string> check_uav_state(const UavStateMsg& s, const MapGeometry& geo);
std::optional<std::string> check_halo(const HaloMsg& h, const MapGeometry& geo);

}  // namespace pheromesh::core
