// The neighbourhood service of a place agent (docs/architecture.md, "Views").
//
// Every UAV has a fixed home place agent (home_region): the UAV writes its
// state and deposits there and reads one View sample per tick from there,
// with endpoints that are created once and never change while it flies. The
// home place agent learns the whole field and every UAV's latest state from
// the RegionField samples the place agents exchange each tick, and composes
// for each UAV homed on it exactly what a UAV reading the tiles around it
// would get: the tiles within its view radius and the states of the other
// UAVs over those tiles. No DDS here: the place agent shell feeds it.
#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/messages.hpp"

namespace pheromesh::core {

class ViewServer {
 public:
  // `view_radius` [cell]: the policy's (policy_traits); a UAV reads the tiles
  // within ceil(view_radius) of its view cell, as UavCore does.
  ViewServer(const MapGeometry& geo, int layers, double view_radius);

  // The latest value of a tile layer (an older tick never replaces a newer one).
  void update_tile(const TileMsg& t);
  // A UAV's latest state (an older tick never replaces a newer one).
  void update_state(const UavStateMsg& s);
  // A field chunk: its tiles and states, and which chunks of which tick of
  // its region arrived (for holds_fields).
  void update_field(const FieldMsg& f);

  // Lockstep: every chunk of tick `tick` of every region in `regions` arrived.
  [[nodiscard]] bool holds_fields(uint32_t tick, std::span<const RegionId> regions) const;
  // What holds_fields misses, for a log line: "region R: tick T, C of N
  // chunks" per region not complete at `tick` ("none" if nothing arrived).
  [[nodiscard]] std::string missing_fields(uint32_t tick, std::span<const RegionId> regions) const;

  // The view of `uav` at (place) tick `tick` into `out`: the tiles of the
  // neighbourhood of its latest state's view cell, and the states of the
  // other UAVs over those tiles that have not finished and whose tick is at
  // most `max_age` older than that UAV's own state. False (out untouched) if
  // no state of `uav` is known.
  bool compose(uint32_t uav, uint32_t tick, uint32_t max_age, ViewMsg& out) const;

  // Latest state of `uav`, if any.
  [[nodiscard]] const UavStateMsg* state(uint32_t uav) const;

  // Tiles within ceil(view_radius) of `c` (clipped to the map): a UAV's neighbourhood.
  [[nodiscard]] std::vector<TileCoord> neighbourhood(Cell c) const;

 private:
  MapGeometry geo_;
  int layers_;
  int32_t radius_;
  std::map<std::tuple<int32_t, int32_t, int>, TileMsg> tiles_;  // (tx, ty, layer)
  std::map<uint32_t, UavStateMsg> states_;
  // UAVs by the tile they are over (for the neighbours of a view).
  std::map<std::pair<int32_t, int32_t>, std::set<uint32_t>> over_;
  struct Arrived {
    uint32_t tick = 0;
    uint16_t chunks = 0;
    std::set<uint16_t> seen;
  };
  std::map<RegionId, Arrived> fields_;
};

// Splits a region's tiles and home UAV states of one tick into RegionField
// chunks within the IDL bounds (at least one chunk, also when both are empty).
std::vector<FieldMsg> make_field_chunks(RegionId region, uint32_t tick, const std::vector<TileMsg>& tiles,
                                        const std::vector<UavStateMsg>& states);

}  // namespace pheromesh::core
