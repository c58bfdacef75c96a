// The exhaustive fixed-route search with transit (Shao 2020 Sec. 4.3.3,
// Shao 2020 Fig. 6): routes and the UAV policy that flies them. The reading
// of the paper is in lawnmower.hpp.
#include "pheromesh/shao/lawnmower.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <optional>
#include <set>

#include "pheromesh/core/heading.hpp"
#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/metrics.hpp"

namespace pheromesh::core {

LawnmowerStrip lawnmower_strip(const ScenarioConfig& s, uint32_t id) {
  LawnmowerStrip st;
  const int64_t h = s.height;
  const int64_t n = std::max<uint32_t>(s.uavs, 1);
  st.row_begin = static_cast<int32_t>(int64_t{id} * h / n);
  st.row_end = static_cast<int32_t>((int64_t{id} + 1) * h / n);
  const auto half = static_cast<int32_t>(std::floor(std::max(s.aco.sensor_radius, 0.0)));
  const int32_t lane = 2 * half + 1;
  for (int32_t y = st.row_begin + half; y < st.row_end + half; y += lane) {
    const int32_t yy = std::min(y, s.height - 1);
    if (st.lanes.empty() || st.lanes.back() != yy) st.lanes.push_back(yy);
  }
  // Nearest lane first: a strip below the start is swept downwards, one above
  // it upwards.
  const Cell start = start_cell(s, id);
  if (!st.lanes.empty() && std::abs(start.y - st.lanes.back()) < std::abs(start.y - st.lanes.front())) {
    std::reverse(st.lanes.begin(), st.lanes.end());
  }
  return st;
}

std::vector<Cell> free_path(const World& world, Cell from, Cell to) {
  const MapGeometry& geo = world.geometry();
  if (!geo.in_map(to) || world.is_obstacle(to) || (from.x == to.x && from.y == to.y)) return {};
  // Distances to `to` over free cells (8-connected), by breadth-first search.
  constexpr int32_t kFar = std::numeric_limits<int32_t>::max();
  std::vector<int32_t> dist(static_cast<std::size_t>(geo.width()) * static_cast<std::size_t>(geo.height()), kFar);
  std::deque<Cell> queue{to};
  dist[geo.index(to)] = 0;
  while (!queue.empty()) {
    const Cell c = queue.front();
    queue.pop_front();
    if (c.x == from.x && c.y == from.y) break;
    for (int h = 0; h < 8; ++h) {
      const Cell st = step_of(static_cast<Heading>(h));
      const Cell nb{c.x + st.x, c.y + st.y};
      if (!geo.in_map(nb) || world.is_obstacle(nb) || dist[geo.index(nb)] != kFar) continue;
      dist[geo.index(nb)] = dist[geo.index(c)] + 1;
      queue.push_back(nb);
    }
  }
  if (!geo.in_map(from) || dist[geo.index(from)] == kFar) return {};
  std::vector<Cell> path;
  Cell at = from;
  while (at.x != to.x || at.y != to.y) {
    const int32_t d = dist[geo.index(at)];
    Cell best{};
    double best_e = std::numeric_limits<double>::infinity();
    for (int h = 0; h < 8; ++h) {
      const Cell st = step_of(static_cast<Heading>(h));
      const Cell nb{at.x + st.x, at.y + st.y};
      if (!geo.in_map(nb) || dist[geo.index(nb)] != d - 1) continue;
      const double e = std::hypot(static_cast<double>(to.x - nb.x), static_cast<double>(to.y - nb.y));
      if (e < best_e) {
        best_e = e;
        best = nb;
      }
    }
    path.push_back(best);
    at = best;
  }
  return path;
}

namespace {

// Breadth-first distances from `from` over free cells (8-connected); -1: unreachable.
std::vector<int32_t> distances_from(const World& world, Cell from) {
  const MapGeometry& geo = world.geometry();
  std::vector<int32_t> dist(static_cast<std::size_t>(geo.width()) * static_cast<std::size_t>(geo.height()), -1);
  if (!geo.in_map(from)) return dist;
  std::deque<Cell> queue{from};
  dist[geo.index(from)] = 0;
  while (!queue.empty()) {
    const Cell c = queue.front();
    queue.pop_front();
    for (int h = 0; h < 8; ++h) {
      const Cell st = step_of(static_cast<Heading>(h));
      const Cell nb{c.x + st.x, c.y + st.y};
      if (!geo.in_map(nb) || world.is_obstacle(nb) || dist[geo.index(nb)] >= 0) continue;
      dist[geo.index(nb)] = dist[geo.index(c)] + 1;
      queue.push_back(nb);
    }
  }
  return dist;
}

}  // namespace

std::vector<Cell> lawnmower_transit_route(const ScenarioConfig& s, const World& world, uint32_t id) {
  const MapGeometry& geo = world.geometry();
  const Cell start = start_cell(s, id);
  std::vector<Cell> route{start};
  const LawnmowerStrip strip = lawnmower_strip(s, id);
  // The first sweep starts at the lane end nearer the start; then they alternate.
  bool east = 2 * start.x < geo.width();
  for (int32_t y : strip.lanes) {
    for (int32_t k = 0; k < geo.width(); ++k) {
      const Cell goal{east ? k : geo.width() - 1 - k, y};
      if (world.is_obstacle(goal)) continue;
      const Cell at = route.back();
      if (at.x == goal.x && at.y == goal.y) continue;
      if (std::max(std::abs(goal.x - at.x), std::abs(goal.y - at.y)) == 1) {
        route.push_back(goal);  // the next lane cell: one step
        continue;
      }
      const std::vector<Cell> leg = free_path(world, at, goal);  // transit, or around an obstacle
      route.insert(route.end(), leg.begin(), leg.end());         // empty: unreachable, left out
    }
    east = !east;
  }
  // Clean-up: a detour around an obstacle can leave cells of the strip beyond
  // the sensor's reach (e.g. the far side of a block the lane crosses). Visit
  // them, nearest first, so that the route covers its whole strip.
  const std::vector<Cell> disk = sensor_disk_offsets(s.aco.sensor_radius, std::max(geo.width(), geo.height()));
  std::vector<uint8_t> seen(static_cast<std::size_t>(geo.width()) * static_cast<std::size_t>(geo.height()), 0);
  auto observe = [&](Cell c) {
    for (const Cell o : disk) {
      const Cell d{c.x + o.x, c.y + o.y};
      if (geo.in_map(d)) seen[geo.index(d)] = 1;
    }
  };
  for (const Cell c : route) observe(c);
  const std::vector<int32_t> from_start = distances_from(world, start);
  for (;;) {
    const std::vector<int32_t> dist = distances_from(world, route.back());
    std::optional<Cell> next;
    int32_t best = std::numeric_limits<int32_t>::max();
    for (int32_t y = strip.row_begin; y < strip.row_end; ++y) {
      for (int32_t x = 0; x < geo.width(); ++x) {
        const std::size_t i = geo.index({x, y});
        if (seen[i] != 0 || from_start[i] < 0 || dist[i] < 0 || dist[i] >= best) continue;
        best = dist[i];
        next = Cell{x, y};
      }
    }
    if (!next) break;
    for (const Cell c : free_path(world, route.back(), *next)) {
      route.push_back(c);
      observe(c);
    }
    observe(*next);  // reached (or the start cell itself)
  }
  return route;
}

namespace {

class LawnmowerUav final : public UavPolicy {
 public:
  LawnmowerUav(const ScenarioConfig& s, const World& world, uint32_t id)
      : s_(&s), world_(&world), route_(lawnmower_transit_route(s, world, id)) {}

  void step(const UavView& view, UavActions& out) override {
    const Cell before = cell();
    if (view.tick > 0 && next_ + 1 < route_.size()) ++next_;  // one step per tick, then hover
    const Cell at = cell();
    // Same sensor as the searchers: a target is reported when it comes in range.
    std::set<int32_t> now_in_range;
    for (int32_t t : world_->sense(at, s_->aco.sensor_radius).targets) {
      now_in_range.insert(t);
      if (!in_range_.contains(t))
        out.detections.push_back({0, view.tick, t, world_->targets()[static_cast<std::size_t>(t)]});
    }
    in_range_ = std::move(now_in_range);
    out.state.x = at.x;
    out.state.y = at.y;
    out.state.vx = at.x - before.x;
    out.state.vy = at.y - before.y;
    heading_ = heading_of_velocity(out.state.vx, out.state.vy, heading_);
    out.state.heading = heading_;
    out.state.role = static_cast<uint8_t>(Role::Searcher);
  }
  [[nodiscard]] Cell cell() const override { return route_[next_]; }

 private:
  const ScenarioConfig* s_;
  const World* world_;
  std::vector<Cell> route_;
  std::size_t next_ = 0;
  uint8_t heading_ = 0;
  std::set<int32_t> in_range_;
};

}  // namespace

std::unique_ptr<UavPolicy> make_shao_lawnmower_uav(const ScenarioConfig& s, const MapGeometry& /*geo*/,
                                                   const World& world, uint32_t id) {
  return std::make_unique<LawnmowerUav>(s, world, id);
}

}  // namespace pheromesh::core
