// Run metrics computed by the ground station (and the simulator).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "pheromesh/core/world.hpp"

namespace pheromesh::core {

// Offsets (dx, dy) of the cells within Euclidean distance `radius` of a
// cell, the radius capped at `max_extent`; empty for a negative or NaN radius.
std::vector<Cell> sensor_disk_offsets(double radius, int32_t max_extent);

// Coverage of reachable cells: a cell counts once it was within the sensor
// radius of some UAV at least once.
class CoverageTracker {
 public:
  CoverageTracker(const World& world, const std::vector<Cell>& starts, double sensor_radius);
  // A UAV over `uav` at `tick` covers its sensor disk. A cell keeps the
  // earliest tick that covered it, whatever order the states arrive in (two
  // UAVs' states travel on two DDS writers), so covered_by_tick() is the
  // same for any arrival order.
  void observe(Cell uav, uint32_t tick = 0);
  [[nodiscard]] double coverage() const;  // 0..1
  [[nodiscard]] int64_t reachable_cells() const { return reachable_count_; }
  [[nodiscard]] int64_t covered_cells() const { return covered_count_; }
  // Cells covered at ticks 0..last_tick (element k: by the end of tick k).
  [[nodiscard]] std::vector<int64_t> covered_by_tick(uint32_t last_tick) const;

 private:
  static constexpr uint32_t kNever = UINT32_MAX;
  const World* world_;
  double radius_;
  std::vector<uint8_t> reachable_;
  std::vector<uint32_t> first_covered_;  // per cell: the earliest tick that covered it, kNever if none
  int64_t reachable_count_ = 0, covered_count_ = 0;
  std::vector<Cell> disk_offsets_;
};

// First acquisition tick of each target: the earliest tick any detection of
// it names, whatever order the detections arrive in (two UAVs' detections
// travel on two DDS writers, and a late-matching reader can get a writer's
// history after its newer samples).
class AcquisitionTracker {
 public:
  explicit AcquisitionTracker(std::size_t targets) : first_(targets) {}
  // Returns true if the target was not found before (a detection of an
  // earlier tick than the one recorded moves the tick and returns false).
  bool acquire(int32_t target, uint32_t tick);
  void add_target() { first_.emplace_back(); }
  [[nodiscard]] std::size_t size() const { return first_.size(); }
  [[nodiscard]] std::optional<uint32_t> first(std::size_t target) const { return target < first_.size() ? first_[target] : std::nullopt; }
  [[nodiscard]] std::size_t found() const;
  // Tick of the k-th first acquisition (sorted ascending).
  [[nodiscard]] std::vector<uint32_t> acquisition_ticks() const;

 private:
  std::vector<std::optional<uint32_t>> first_;
};

}  // namespace pheromesh::core
