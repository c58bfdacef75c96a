// Start cells (scenario.hpp, start_cell) and the free cells of a start area
// (start_cells_internal.hpp).
#include <algorithm>
#include <cstdint>

#include "pheromesh/core/scenario.hpp"
#include "scenario/start_cells_internal.hpp"

namespace pheromesh::core {
namespace scenario_detail {

// Free (non-obstacle) columns of row y inside `area`, as a sorted list of
// merged obstacle intervals [x_begin, x_end) clipped to the area.
std::vector<std::pair<int32_t, int32_t>> blocked_intervals(const Rect& area, const std::vector<Rect>& obstacles, int32_t y) {
  std::vector<std::pair<int32_t, int32_t>> iv;
  for (const Rect& o : obstacles) {
    if (y < o.y0 || y >= o.y0 + o.h) continue;
    const int32_t b = std::max(o.x0, area.x0);
    const int32_t e = std::min(o.x0 + o.w, area.x0 + area.w);
    if (b < e) iv.emplace_back(b, e);
  }
  std::sort(iv.begin(), iv.end());
  std::vector<std::pair<int32_t, int32_t>> merged;
  for (const auto& i : iv) {
    if (!merged.empty() && i.first <= merged.back().second) {
      merged.back().second = std::max(merged.back().second, i.second);
    } else {
      merged.push_back(i);
    }
  }
  return merged;
}

int64_t free_in_row(const Rect& area, const std::vector<Rect>& obstacles, int32_t y) {
  int64_t n_free = area.w;
  for (const auto& [b, e] : blocked_intervals(area, obstacles, y)) n_free -= e - b;
  return n_free;
}

int64_t free_cells(const Rect& area, const std::vector<Rect>& obstacles) {
  int64_t n = 0;
  for (int32_t y = area.y0; y < area.y0 + area.h; ++y) n += free_in_row(area, obstacles, y);
  return n;
}

}  // namespace scenario_detail

using scenario_detail::blocked_intervals;

namespace {

// The start area's rows, each with its obstacle intervals and free cells,
// computed once for every UAV placed from them.
struct StartAreaRows {
  std::vector<std::vector<std::pair<int32_t, int32_t>>> blocked;  // per row from area.y0
  std::vector<int64_t> free;                                      // per row
  int64_t count = 0;                                              // free cells in the area
};

StartAreaRows start_area_rows(const ScenarioConfig& s) {
  const Rect& area = s.start_area;
  StartAreaRows rows;
  for (int32_t y = area.y0; y < area.y0 + area.h; ++y) {
    rows.blocked.push_back(blocked_intervals(area, s.obstacles, y));
    int64_t n_free = area.w;
    for (const auto& [b, e] : rows.blocked.back()) n_free -= e - b;
    rows.free.push_back(n_free);
    rows.count += n_free;
  }
  return rows;
}

Cell place_in_rows(const ScenarioConfig& s, const StartAreaRows& rows, uint32_t id) {
  const Rect& area = s.start_area;
  const int64_t count = rows.count;
  if (count <= 0) return {area.x0, area.y0};  // unreachable for a validated scenario
  const auto uavs = static_cast<uint64_t>(std::max<uint32_t>(s.uavs, 1));
  // Evenly spaced indices into the free cells: distinct for id < uavs since
  // validation guarantees count >= uavs; larger ids wrap around.
  auto k = static_cast<int64_t>((uint64_t{id} * static_cast<uint64_t>(count) / uavs) % static_cast<uint64_t>(count));
  for (std::size_t r = 0; r < rows.free.size(); ++r) {
    const int64_t n_free = rows.free[r];
    if (k >= n_free) {
      k -= n_free;
      continue;
    }
    int32_t x = area.x0;
    for (const auto& [b, e] : rows.blocked[r]) {
      if (x + k < b) break;
      k -= b - x;
      x = e;
    }
    return {static_cast<int32_t>(x + k), area.y0 + static_cast<int32_t>(r)};
  }
  return {area.x0, area.y0};
}

}  // namespace

Cell start_cell(const ScenarioConfig& s, uint32_t id) { return place_in_rows(s, start_area_rows(s), id); }

std::vector<Cell> start_cells(const ScenarioConfig& s) {
  const StartAreaRows rows = start_area_rows(s);
  std::vector<Cell> out;
  out.reserve(s.uavs);
  for (uint32_t id = 0; id < s.uavs; ++id) out.push_back(place_in_rows(s, rows, id));
  return out;
}

}  // namespace pheromesh::core
