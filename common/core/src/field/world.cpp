// Ground truth of a simulated world and the simulated sensor.
#include "pheromesh/core/world.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace pheromesh::core {

World::World(const MapGeometry& geo, const std::vector<Rect>& obstacles, const std::vector<Cell>& targets)
    : geo_(geo),
      obstacle_(static_cast<std::size_t>(geo.width()) * static_cast<std::size_t>(geo.height()), 0),
      target_index_(obstacle_.size(), -1),
      targets_(targets) {
  for (const Rect& r : obstacles) add_obstacle(r);
  for (std::size_t i = 0; i < targets_.size(); ++i) {
    const Cell c = targets_[i];
    // Two targets on one cell: the first one in scenario order is reported.
    if (geo.in_map(c) && target_index_[geo.index(c)] < 0) {
      target_index_[geo.index(c)] = static_cast<int32_t>(i);
    }
  }
}

int64_t World::add_obstacle(const Rect& r) {
  // Clip to the map; a rect that sticks out only marks its in-map part.
  const int64_t x0 = std::max<int64_t>(r.x0, 0);
  const int64_t y0 = std::max<int64_t>(r.y0, 0);
  const int64_t x1 = std::min<int64_t>(int64_t{r.x0} + r.w, geo_.width());
  const int64_t y1 = std::min<int64_t>(int64_t{r.y0} + r.h, geo_.height());
  int64_t added = 0;
  for (int64_t y = y0; y < y1; ++y) {
    for (int64_t x = x0; x < x1; ++x) {
      auto& o = obstacle_[geo_.index(Cell{static_cast<int32_t>(x), static_cast<int32_t>(y)})];
      added += o == 0 ? 1 : 0;
      o = 1;
    }
  }
  return added;
}

int32_t World::add_target(Cell c) {
  targets_.push_back(c);
  const auto i = static_cast<int32_t>(targets_.size() - 1);
  if (geo_.in_map(c) && target_index_[geo_.index(c)] < 0) target_index_[geo_.index(c)] = i;
  return i;
}

bool World::is_obstacle(Cell c) const { return geo_.in_map(c) && obstacle_[geo_.index(c)] != 0; }

int32_t World::target_at(Cell c) const { return geo_.in_map(c) ? target_index_[geo_.index(c)] : -1; }

std::vector<Cell> World::disk(Cell c, double radius) const {
  std::vector<Cell> out;
  if (!(radius >= 0.0)) {
    return out;  // negative or NaN radius: empty disk
  }
  // No disk needs to reach further than the map's extent.
  const double extent = static_cast<double>(std::max(geo_.width(), geo_.height()));
  const auto r = static_cast<int64_t>(std::floor(std::min(radius, extent)));
  const double r2 = radius * radius;
  const int64_t y0 = std::max<int64_t>(int64_t{c.y} - r, 0);
  const int64_t y1 = std::min<int64_t>(int64_t{c.y} + r, geo_.height() - 1);
  const int64_t x0 = std::max<int64_t>(int64_t{c.x} - r, 0);
  const int64_t x1 = std::min<int64_t>(int64_t{c.x} + r, geo_.width() - 1);
  for (int64_t y = y0; y <= y1; ++y) {
    for (int64_t x = x0; x <= x1; ++x) {
      const int64_t dx = x - c.x;
      const int64_t dy = y - c.y;
      if (static_cast<double>(dx * dx + dy * dy) <= r2) {
        out.push_back(Cell{static_cast<int32_t>(x), static_cast<int32_t>(y)});
      }
    }
  }
  return out;
}

World::Reading World::sense(Cell c, double radius) const {
  Reading reading;
  for (const Cell d : disk(c, radius)) {
    if (obstacle_[geo_.index(d)] != 0) {
      reading.obstacles.push_back(d);
    }
    const int32_t t = target_index_[geo_.index(d)];
    if (t >= 0) {
      reading.targets.push_back(t);
    }
  }
  return reading;
}

std::vector<uint8_t> World::reachable_from(const std::vector<Cell>& starts) const {
  std::vector<uint8_t> reached(obstacle_.size(), 0);
  std::vector<Cell> stack;
  for (const Cell s : starts) {
    if (geo_.in_map(s) && obstacle_[geo_.index(s)] == 0 && reached[geo_.index(s)] == 0) {
      reached[geo_.index(s)] = 1;
      stack.push_back(s);
    }
  }
  while (!stack.empty()) {
    const Cell c = stack.back();
    stack.pop_back();
    for (int32_t dy = -1; dy <= 1; ++dy) {
      for (int32_t dx = -1; dx <= 1; ++dx) {
        const Cell n{c.x + dx, c.y + dy};
        if ((dx == 0 && dy == 0) || !geo_.in_map(n)) {
          continue;
        }
        const std::size_t i = geo_.index(n);
        if (obstacle_[i] == 0 && reached[i] == 0) {
          reached[i] = 1;
          stack.push_back(n);
        }
      }
    }
  }
  return reached;
}

}  // namespace pheromesh::core
