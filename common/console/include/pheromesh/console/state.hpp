// What the web console shows, as plain data: the ground station builds it
// live from the swarm's samples, a recording stores the frames that built it,
// and `pheromesh replay` rebuilds it from those frames. Both sides apply the
// same frames with the same apply(), so a replay shows exactly what the live
// console showed. No DDS, no I/O here.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "pheromesh/core/geodetic.hpp"
#include "pheromesh/core/grid.hpp"

namespace pheromesh::core {
struct ScenarioConfig;
}  // namespace pheromesh::core

namespace pheromesh::console {

// What does not change during a run: the map, the regions, the layers.
struct ConsoleInfo {
  std::string scenario_name;
  std::string scenario_path;
  std::string policy;
  int32_t width = 0;      // [cell]
  int32_t height = 0;     // [cell]
  int32_t tile_size = 0;  // [cell]
  std::vector<core::Rect> regions;  // index = region id, in cells
  std::vector<std::string> layers;  // pheromone layer names, index = layer
  double tick_rate_hz = 0;
  uint32_t ticks = 0;
  uint32_t uavs_expected = 0;
  uint32_t lease_ms = 0;
  double sensor_radius = 0;  // [cell]
  std::string clock;         // realtime | lockstep
  std::string dds;           // the ground station's vendor
  // Where the map lies (the scenario's geo block), for a replay's MAVLink
  // stream; absent in recordings made before it was recorded.
  std::optional<core::GeoFrame> geo;
};

// One pheromone layer of one tile, quantised to 8 bits: value = q / 255 * scale.
struct TileImage {
  core::Rect rect;              // in cells
  uint32_t tick = 0;            // the place agent's tick of these values
  std::vector<uint8_t> q;       // row-major over rect
  uint64_t version = 0;         // frame that last changed q (or the scale)
};

struct LayerImage {
  float scale = 1.0F;  // value of q = 255; a power of two
  std::map<std::pair<int32_t, int32_t>, TileImage> tiles;  // (tx, ty)
};

struct TrackPoint {
  float x = 0, y = 0;    // [cell]
  uint64_t version = 0;  // frame that added it
};

enum class Liveness : uint8_t { Alive, Stale, Dead, Finished };
const char* to_string(Liveness l);

struct UavView {
  uint32_t id = 0;
  double x = 0, y = 0;  // [cell]
  uint8_t heading = 0;  // 0..7, 45 deg steps counter-clockwise from east
  uint8_t role = 0;     // core::Role
  uint32_t tick = 0;
  Liveness liveness = Liveness::Alive;
  std::deque<TrackPoint> track;  // decimated, at most kTrackPoints
};

struct RegionView {
  uint32_t id = 0;
  Liveness liveness = Liveness::Dead;  // Dead until its first health arrives
  uint32_t tick = 0;
  float tick_rate_hz = 0;
  double deposits_per_s = 0;
  uint64_t deposits_received = 0;
  uint64_t deposits_applied = 0;
  uint64_t deposits_rejected = 0;
  uint16_t replica = 0;         // the replica serving the region: 0 its primary, > 0 a standby that took over
  uint32_t replicas_alive = 0;  // live replicas (with --standby: 2 while primary and standby run)
  uint64_t samples_refused = 0;  // well-formed samples its place agent refused as implausible (core/plausibility.hpp)
};

enum class TargetStatus : uint8_t { NotFound, Found, RevisitDue };
const char* to_string(TargetStatus s);

struct TargetView {
  core::Cell cell;
  TargetStatus status = TargetStatus::NotFound;
  int64_t found_by = -1;  // UAV id
  uint32_t found_tick = 0;
  bool popup = false;     // added during the run
};

struct ObstacleView {
  core::Rect rect;
  bool popup = false;
};

struct SeriesPoint {
  uint64_t version = 0;
  double t_s = 0;        // since the console started
  uint32_t tick = 0;
  double coverage = 0;   // 0..1
  uint32_t targets_found = 0;
  double uncertainty = 0;  // 0..1, see uncertainty.hpp
};

struct CommandLogEntry {
  uint64_t version = 0;
  double t_s = 0;
  std::string who;   // e.g. "http 127.0.0.1:53122 (token ok)"
  std::string what;  // e.g. "kill uav 3"
  bool ok = false;
  std::string result;
};

// Everything that changed since the previous frame. Frames are what the live
// console applies and what a recording stores.
struct TileDelta {
  uint16_t layer = 0;
  int32_t tx = 0, ty = 0;
  core::Rect rect;
  uint32_t tick = 0;
  std::vector<uint8_t> q;
};

struct Frame {
  uint64_t version = 0;  // 1, 2, 3, ...
  double t_s = 0;
  uint32_t tick = 0;
  bool paused = false;
  std::vector<std::pair<uint16_t, float>> scales;  // (layer, new scale): every tile of the layer is in `tiles`
  std::vector<TileDelta> tiles;
  std::vector<UavView> uavs;        // every UAV, without track (apply() extends the tracks)
  std::vector<RegionView> regions;  // every region
  std::vector<TargetView> targets;  // every target
  std::vector<ObstacleView> obstacles;  // every obstacle
  std::optional<SeriesPoint> series;  // a new plot point, if one is due
  std::vector<CommandLogEntry> commands;  // commands handled since the previous frame
};

struct ConsoleState {
  uint64_t version = 0;
  double t_s = 0;
  uint32_t tick = 0;
  bool paused = false;
  std::vector<LayerImage> layers;
  std::map<uint32_t, UavView> uavs;
  std::vector<RegionView> regions;
  std::vector<TargetView> targets;
  std::vector<ObstacleView> obstacles;
  std::vector<SeriesPoint> series;            // at most kSeriesPoints (oldest dropped)
  std::deque<CommandLogEntry> commands;       // at most kCommandLog (oldest dropped)
};

inline constexpr std::size_t kTrackPoints = 64;
inline constexpr std::size_t kSeriesPoints = 3600;
inline constexpr std::size_t kCommandLog = 50;

// An empty state for this run: one LayerImage per layer, one RegionView per region.
ConsoleState initial_state(const ConsoleInfo& info);
// What a scenario says of the console's run: its name, path, policy, map,
// regions, layers, rate, ticks, UAVs and sensor radius. The caller adds the
// clock, the vendor and the lease (and the UAVs it expects, if others).
ConsoleInfo console_info_of(const core::ScenarioConfig& s);

// Applies one frame. Tracks gain the UAV's position when it moved at least
// kTrackStep cells from the track's last point (decimation).
void apply(ConsoleState& s, const Frame& f);
inline constexpr double kTrackStep = 1.0;  // [cell]

}  // namespace pheromesh::console
