// The console's next frame from what the ground station heard (pure; the
// ground station feeds it, then adds the series point and the command log,
// records and publishes the frame). It decides what the console shows:
// which tiles changed (all of a layer whose colour scale changed), each UAV's
// and place agent's liveness by the thresholds below, each region's rate of
// applied deposits, each target's status.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "pheromesh/console/state.hpp"
#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/run_metrics.hpp"
#include "pheromesh/core/world.hpp"

namespace pheromesh::console {

class FrameBuilder {
 public:
  using Clock = std::chrono::steady_clock;
  using TileKey = std::pair<int, std::pair<int32_t, int32_t>>;  // (layer, (tx, ty))
  // Not heard for longer: shown stale (unless the swarm is paused).
  static constexpr std::chrono::milliseconds kUavStaleAfter{1000};
  static constexpr std::chrono::milliseconds kRegionStaleAfter{2000};
  // A region's deposit rate is measured over at least this long.
  static constexpr std::chrono::milliseconds kRatePeriod{1000};

  explicit FrameBuilder(const core::MapGeometry& geo) : geo_(geo) {}

  // --- what the ground station heard
  void heard_uav(uint32_t uav, Clock::time_point now) { uav_heard_[uav] = now; }
  void heard_region(core::RegionId r, Clock::time_point now) { region_heard_[r] = now; }
  void target_found(int32_t target, uint32_t uav, uint32_t tick) { found_by_[target] = {uav, tick}; }
  void revisit(core::Cell target, bool due) { revisit_due_[{target.x, target.y}] = due; }
  [[nodiscard]] std::size_t uavs_heard() const { return uav_heard_.size(); }
  [[nodiscard]] std::size_t regions_heard() const { return region_heard_.size(); }

  struct Sources {
    const std::map<TileKey, core::TileMsg>& tiles;  // latest tile per (layer, tile)
    const core::RunRecorder& rec;
    const core::World& world;                       // targets and obstacles, pop-ups included
    std::size_t scenario_targets = 0;               // world targets past these came from the console
    const std::vector<core::Rect>& obstacles;       // the scenario's
    const std::vector<core::Rect>& popup_obstacles;  // added from the console
    bool paused = false;
  };
  // The frame that follows `last` (the state published so far) at `now`,
  // `t_s` seconds into the console. No series point, no commands.
  Frame build(const ConsoleState& last, const Sources& s, Clock::time_point now, double t_s);

 private:
  struct Rate {
    Clock::time_point t{};
    uint64_t applied = 0;
    double per_s = 0;
  };
  core::MapGeometry geo_;
  std::map<uint32_t, Clock::time_point> uav_heard_;
  std::map<core::RegionId, Clock::time_point> region_heard_;
  std::map<core::RegionId, Rate> region_rate_;
  std::map<int32_t, std::pair<uint32_t, uint32_t>> found_by_;  // target -> (uav, tick)
  std::map<std::pair<int32_t, int32_t>, bool> revisit_due_;     // target cell -> due
};

}  // namespace pheromesh::console
