// Ground truth of a simulated world (obstacles, targets) and the simulated
// sensor: what a UAV at a cell senses within its sensor radius.
#pragma once

#include <cstdint>
#include <vector>

#include "pheromesh/core/grid.hpp"

namespace pheromesh::core {

class World {
 public:
  // `geo` is copied (seven numbers): a World built from a temporary, such as
  // `World(scenario.geometry(), ...)`, once kept a pointer to it.
  World(const MapGeometry& geo, const std::vector<Rect>& obstacles, const std::vector<Cell>& targets);

  [[nodiscard]] const MapGeometry& geometry() const { return geo_; }
  // Pop-ups during a run (ground-station commands). add_obstacle clips to
  // the map and returns the number of cells that became obstacles;
  // add_target returns the new target's index.
  int64_t add_obstacle(const Rect& r);
  int32_t add_target(Cell c);
  [[nodiscard]] bool is_obstacle(Cell c) const;  // false outside the map
  [[nodiscard]] const std::vector<Cell>& targets() const { return targets_; }
  // Index of the target at c, or -1.
  [[nodiscard]] int32_t target_at(Cell c) const;

  // Cells within Euclidean distance `radius` [cell] of c, inside the map, in
  // row-major order (c included).
  [[nodiscard]] std::vector<Cell> disk(Cell c, double radius) const;
  // Sensor reading: obstacle cells and target indices within `radius` of c.
  struct Reading {
    std::vector<Cell> obstacles;
    std::vector<int32_t> targets;
  };
  [[nodiscard]] Reading sense(Cell c, double radius) const;

  // Free cells reachable (8-connectivity through free cells) from any of `starts`.
  [[nodiscard]] std::vector<uint8_t> reachable_from(const std::vector<Cell>& starts) const;

 private:
  MapGeometry geo_;
  std::vector<uint8_t> obstacle_;
  std::vector<int32_t> target_index_;
  std::vector<Cell> targets_;
};

}  // namespace pheromesh::core
