// Map / tile / region / cell indexing. A map of width x height cells is cut
// into square tiles of tile_size cells (the last row/column may be smaller);
// tiles are grouped into regions_x x regions_y rectangular regions, one place
// agent per region.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pheromesh::core {

struct Cell {
  int32_t x = 0;  // [cell]
  int32_t y = 0;  // [cell]
  friend bool operator==(const Cell&, const Cell&) = default;
};

struct TileCoord {
  int32_t tx = 0;
  int32_t ty = 0;
  friend bool operator==(const TileCoord&, const TileCoord&) = default;
};

// Half-open rectangle of cells [x0, x0+w) x [y0, y0+h).
struct Rect {
  int32_t x0 = 0;
  int32_t y0 = 0;
  int32_t w = 0;
  int32_t h = 0;
  [[nodiscard]] bool contains(Cell c) const { return c.x >= x0 && c.x < x0 + w && c.y >= y0 && c.y < y0 + h; }
  [[nodiscard]] int64_t area() const { return int64_t{w} * h; }
  friend bool operator==(const Rect&, const Rect&) = default;
};

using RegionId = uint32_t;

class MapGeometry {
 public:
  // Preconditions (checked by scenario validation, asserted here): all > 0,
  // regions_x <= tiles_x(), regions_y <= tiles_y().
  MapGeometry(int32_t width, int32_t height, int32_t tile_size, int32_t regions_x, int32_t regions_y);

  [[nodiscard]] int32_t width() const { return width_; }
  [[nodiscard]] int32_t height() const { return height_; }
  [[nodiscard]] int32_t tile_size() const { return tile_size_; }
  [[nodiscard]] int32_t tiles_x() const { return tiles_x_; }
  [[nodiscard]] int32_t tiles_y() const { return tiles_y_; }
  [[nodiscard]] int32_t regions_x() const { return regions_x_; }
  [[nodiscard]] int32_t regions_y() const { return regions_y_; }
  [[nodiscard]] uint32_t region_count() const { return static_cast<uint32_t>(regions_x_ * regions_y_); }
  [[nodiscard]] Rect map_rect() const { return {0, 0, width_, height_}; }

  [[nodiscard]] bool in_map(Cell c) const { return c.x >= 0 && c.y >= 0 && c.x < width_ && c.y < height_; }
  [[nodiscard]] bool valid_tile(TileCoord t) const { return t.tx >= 0 && t.ty >= 0 && t.tx < tiles_x_ && t.ty < tiles_y_; }
  // Row-major index of a cell in the whole map.
  [[nodiscard]] std::size_t index(Cell c) const { return static_cast<std::size_t>(c.y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(c.x); }

  [[nodiscard]] TileCoord tile_of(Cell c) const { return {c.x / tile_size_, c.y / tile_size_}; }
  [[nodiscard]] Rect tile_rect(TileCoord t) const;

  [[nodiscard]] RegionId region_of_tile(TileCoord t) const;
  [[nodiscard]] RegionId region_of(Cell c) const { return region_of_tile(tile_of(c)); }
  [[nodiscard]] Rect region_rect(RegionId r) const;             // in cells
  [[nodiscard]] std::vector<TileCoord> region_tiles(RegionId r) const;
  // Regions that own at least one cell within Euclidean distance `radius` [cell] of c.
  [[nodiscard]] std::vector<RegionId> regions_within(Cell c, double radius) const;
  // Tiles that intersect the square [c - r, c + r] (clipped to the map).
  [[nodiscard]] std::vector<TileCoord> tiles_within(Cell c, int32_t r) const;
  // Regions that touch region r (8-neighbourhood of regions, r excluded).
  [[nodiscard]] std::vector<RegionId> neighbour_regions(RegionId r) const;
  // |N(i)|: number of in-map 8-neighbours of c (3 at corners, 5 on borders, 8 inside).
  [[nodiscard]] int32_t neighbour_count(Cell c) const;

 private:
  int32_t width_, height_, tile_size_, regions_x_, regions_y_, tiles_x_, tiles_y_;
  [[nodiscard]] int32_t region_tile_begin_x(int32_t rx) const { return rx * tiles_x_ / regions_x_; }
  [[nodiscard]] int32_t region_tile_begin_y(int32_t ry) const { return ry * tiles_y_ / regions_y_; }
};

}  // namespace pheromesh::core
