// MapGeometry: map -> tiles -> regions indexing (see grid.hpp).
#include "pheromesh/core/grid.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>

namespace pheromesh::core {

namespace {

int32_t ceil_div(int32_t a, int32_t b) { return (a + b - 1) / b; }

// Region index of tile index t when `tiles` tiles are split into `regions`
// groups that begin at floor(r * tiles / regions). The largest r with
// floor(r*T/R) <= t is floor(((t+1)*R - 1) / T).
int32_t group_of(int32_t t, int32_t tiles, int32_t regions) {
  const int64_t r = (int64_t{t + 1} * regions - 1) / tiles;
  return static_cast<int32_t>(std::clamp<int64_t>(r, 0, regions - 1));
}

}  // namespace

MapGeometry::MapGeometry(int32_t width, int32_t height, int32_t tile_size, int32_t regions_x, int32_t regions_y)
    : width_(width),
      height_(height),
      tile_size_(tile_size),
      regions_x_(regions_x),
      regions_y_(regions_y),
      tiles_x_(tile_size > 0 ? ceil_div(width, tile_size) : 0),
      tiles_y_(tile_size > 0 ? ceil_div(height, tile_size) : 0) {
  assert(width > 0 && height > 0 && tile_size > 0 && regions_x > 0 && regions_y > 0);
  assert(regions_x <= tiles_x_ && regions_y <= tiles_y_);
}

Rect MapGeometry::tile_rect(TileCoord t) const {
  if (!valid_tile(t)) return {};
  const int32_t x0 = t.tx * tile_size_;
  const int32_t y0 = t.ty * tile_size_;
  // The last tile column/row may be narrower than tile_size.
  return {x0, y0, std::min(tile_size_, width_ - x0), std::min(tile_size_, height_ - y0)};
}

RegionId MapGeometry::region_of_tile(TileCoord t) const {
  assert(valid_tile(t));
  const int32_t rx = group_of(std::clamp(t.tx, 0, tiles_x_ - 1), tiles_x_, regions_x_);
  const int32_t ry = group_of(std::clamp(t.ty, 0, tiles_y_ - 1), tiles_y_, regions_y_);
  return static_cast<RegionId>(ry * regions_x_ + rx);
}

Rect MapGeometry::region_rect(RegionId r) const {
  if (r >= region_count()) return {};
  const auto rx = static_cast<int32_t>(r % static_cast<uint32_t>(regions_x_));
  const auto ry = static_cast<int32_t>(r / static_cast<uint32_t>(regions_x_));
  const int32_t x0 = region_tile_begin_x(rx) * tile_size_;
  const int32_t y0 = region_tile_begin_y(ry) * tile_size_;
  // region_tile_begin_x(regions_x) == tiles_x, whose cell edge may lie past the map: clip.
  const int32_t x1 = std::min(region_tile_begin_x(rx + 1) * tile_size_, width_);
  const int32_t y1 = std::min(region_tile_begin_y(ry + 1) * tile_size_, height_);
  return {x0, y0, x1 - x0, y1 - y0};
}

std::vector<TileCoord> MapGeometry::region_tiles(RegionId r) const {
  std::vector<TileCoord> out;
  if (r >= region_count()) return out;
  const auto rx = static_cast<int32_t>(r % static_cast<uint32_t>(regions_x_));
  const auto ry = static_cast<int32_t>(r / static_cast<uint32_t>(regions_x_));
  const int32_t tx0 = region_tile_begin_x(rx);
  const int32_t tx1 = region_tile_begin_x(rx + 1);
  const int32_t ty0 = region_tile_begin_y(ry);
  const int32_t ty1 = region_tile_begin_y(ry + 1);
  out.reserve(static_cast<std::size_t>((tx1 - tx0) * (ty1 - ty0)));
  for (int32_t ty = ty0; ty < ty1; ++ty) {
    for (int32_t tx = tx0; tx < tx1; ++tx) out.push_back({tx, ty});
  }
  return out;
}

std::vector<RegionId> MapGeometry::regions_within(Cell c, double radius) const {
  std::vector<RegionId> out;
  if (!(radius >= 0.0)) return out;  // also rejects NaN
  for (RegionId r = 0; r < region_count(); ++r) {
    const Rect rr = region_rect(r);
    // Distance [cell] from c to the nearest cell of the rect, per axis.
    const int64_t dx = std::max<int64_t>({int64_t{rr.x0} - c.x, 0, int64_t{c.x} - (int64_t{rr.x0} + rr.w - 1)});
    const int64_t dy = std::max<int64_t>({int64_t{rr.y0} - c.y, 0, int64_t{c.y} - (int64_t{rr.y0} + rr.h - 1)});
    // Same distance expression as RegionField::add_path_visit, so "within D0"
    // means the same thing in both places.
    if (std::sqrt(static_cast<double>(dx * dx + dy * dy)) <= radius) out.push_back(r);
  }
  return out;  // ascending by construction
}

std::vector<TileCoord> MapGeometry::tiles_within(Cell c, int32_t r) const {
  std::vector<TileCoord> out;
  if (r < 0) return out;
  const int64_t x_lo = std::max<int64_t>(int64_t{c.x} - r, 0);
  const int64_t x_hi = std::min<int64_t>(int64_t{c.x} + r, width_ - 1);
  const int64_t y_lo = std::max<int64_t>(int64_t{c.y} - r, 0);
  const int64_t y_hi = std::min<int64_t>(int64_t{c.y} + r, height_ - 1);
  if (x_lo > x_hi || y_lo > y_hi) return out;  // square entirely off the map
  const auto tx0 = static_cast<int32_t>(x_lo / tile_size_);
  const auto tx1 = static_cast<int32_t>(x_hi / tile_size_);
  const auto ty0 = static_cast<int32_t>(y_lo / tile_size_);
  const auto ty1 = static_cast<int32_t>(y_hi / tile_size_);
  out.reserve(static_cast<std::size_t>((tx1 - tx0 + 1) * (ty1 - ty0 + 1)));
  for (int32_t ty = ty0; ty <= ty1; ++ty) {
    for (int32_t tx = tx0; tx <= tx1; ++tx) out.push_back({tx, ty});
  }
  return out;
}

std::vector<RegionId> MapGeometry::neighbour_regions(RegionId r) const {
  std::vector<RegionId> out;
  if (r >= region_count()) return out;
  const auto rx = static_cast<int32_t>(r % static_cast<uint32_t>(regions_x_));
  const auto ry = static_cast<int32_t>(r / static_cast<uint32_t>(regions_x_));
  // Row-major walk over the 3x3 block gives ascending ids.
  for (int32_t y = std::max(ry - 1, 0); y <= std::min(ry + 1, regions_y_ - 1); ++y) {
    for (int32_t x = std::max(rx - 1, 0); x <= std::min(rx + 1, regions_x_ - 1); ++x) {
      if (x == rx && y == ry) continue;
      out.push_back(static_cast<RegionId>(y * regions_x_ + x));
    }
  }
  return out;
}

int32_t MapGeometry::neighbour_count(Cell c) const {
  // In-map cells of the 3x3 box around c, minus c itself if it is in the map.
  const int64_t x_lo = std::max<int64_t>(int64_t{c.x} - 1, 0);
  const int64_t x_hi = std::min<int64_t>(int64_t{c.x} + 1, width_ - 1);
  const int64_t y_lo = std::max<int64_t>(int64_t{c.y} - 1, 0);
  const int64_t y_hi = std::min<int64_t>(int64_t{c.y} + 1, height_ - 1);
  const int64_t box = std::max<int64_t>(x_hi - x_lo + 1, 0) * std::max<int64_t>(y_hi - y_lo + 1, 0);
  return static_cast<int32_t>(box - (in_map(c) ? 1 : 0));
}

}  // namespace pheromesh::core
