// The neighbourhood service of a place agent (docs/architecture.md, "Views").
//
// Every UAV has a fixed home place agent (home_region): the UAV writes its
// state and deposits there and reads one View sample per tick from there,
// with endpoints that are created once and never change while it flies -
// unless its home dies without a standby: then its backup gateway
// (gateway_region) serves it the same way.
// Local traffic (issue 25): a home does not hold the whole map. Each tick
// every place agent tells the others which UAVs it serves and where they
// are (their states, `p` chunks); each owner then sends each home exactly
// the tiles of its region that those UAVs' views need (`f.<home>` chunks),
// and the home composes each view from them and its own tiles: the tiles
// within the view radius and the states of the other UAVs over those
// tiles. A tile is shown only if it is of the view's tick (lockstep) or
// recent (realtime), so a dead owner's tiles are absent, not frozen. No DDS
// here: the place agent shell feeds it.
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/messages.hpp"

namespace pheromesh::core {

class ViewServer {
 public:
  // `view_radius` [cell]: the policy's (policy_traits); a UAV reads the tiles
  // within ceil(view_radius) of its view cell, as UavCore does. Without
  // `neighbours` (PolicyTraits::reads_neighbours) a view carries no other
  // UAVs' states, only tiles.
  ViewServer(const MapGeometry& geo, int layers, double view_radius, bool neighbours = true);

  // The latest value of a tile layer (an older tick never replaces a newer
  // one), which arrived at this place agent's tick `arrived` (compose).
  void update_tile(const TileMsg& t, uint32_t arrived);
  // A UAV's latest state (an older tick never replaces a newer one).
  void update_state(const UavStateMsg& s);
  // A chunk of the states another place agent serves this tick (`p`),
  // arrived at this place agent's tick `arrived`: the states, and which UAVs
  // that region serves (served_by).
  void update_served(const FieldMsg& f, uint32_t arrived = 0);
  // Lockstep: the served UAVs of every region in `regions` as the place
  // clock of `tick` lists them (ClockMsg::served), in place of each region's
  // chunk: a region listed with no UAV serves none. An entry of a region
  // not in `regions` is not taken; one of a UAV outside the swarm (id >=
  // `swarm`) or with a pose off the map is malformed, and its reason goes
  // to `malformed`.
  void update_served(std::span<const ServedUav> served, uint32_t tick, std::span<const RegionId> regions,
                     uint32_t swarm, std::vector<std::string>& malformed);
  // A chunk of tiles an owner sent for this place agent's views (`f.<own>`),
  // arrived at tick `arrived`.
  void update_tiles(const FieldMsg& f, uint32_t arrived);

  // Lockstep: every chunk of tick `tick` of the served states of each region
  // in `regions` arrived.
  [[nodiscard]] bool holds_served(uint32_t tick, std::span<const RegionId> regions) const;
  // Lockstep: every chunk of tick `tick` of tiles from each owner in `owners` arrived.
  [[nodiscard]] bool holds_tiles(uint32_t tick, std::span<const RegionId> owners) const;
  // What holds_served / holds_tiles miss, for a log line: "region R: tick T,
  // C of N chunks" per region not complete at `tick` ("none" if nothing arrived).
  [[nodiscard]] std::string missing_served(uint32_t tick, std::span<const RegionId> regions) const;
  [[nodiscard]] std::string missing_tiles(uint32_t tick, std::span<const RegionId> owners) const;

  // The UAVs `region` serves, as its newest complete `p` chunks said; none
  // if nothing of it arrived at or after tick `heard_since` (realtime: a dead
  // place agent serves nobody, and no owner sends it tiles).
  [[nodiscard]] std::vector<uint32_t> served_by(RegionId region, uint32_t heard_since = 0) const;

  // The tiles the views of `uavs` need (the union of the neighbourhoods of
  // their view cells, each widened by `margin` cells), sorted, without repeats;
  // UAVs whose state is unknown add nothing.
  [[nodiscard]] std::vector<TileCoord> needed_tiles(std::span<const uint32_t> uavs, int32_t margin = 0) const;
  // The tile join (issue 43): of `own` (this region's tiles of a tick),
  // those the views of the UAVs `home` serves need (served_by(home,
  // heard_since), needed_tiles with `margin`), appended to `out` in the
  // order of needed_tiles, each tile's layers in their order in `own`.
  void tiles_for(RegionId home, uint32_t heard_since, int32_t margin, std::span<const TileMsg> own,
                 std::vector<TileMsg>& out) const;
  // The regions other than `self` whose tiles the views of `uavs` need
  // (needed_tiles with `margin`), sorted, without repeats.
  [[nodiscard]] std::vector<RegionId> owners_for(std::span<const uint32_t> uavs, int32_t margin, RegionId self) const;

  // The view of `uav` at (place) tick `tick` into `out`: the tiles of the
  // neighbourhood of its latest state's view cell that arrived at tick
  // `min_tile_tick` or later, and the states of the other UAVs over those tiles that
  // have not finished and whose tick is at most `max_age` older than that
  // UAV's own state. False (out untouched) if no state of `uav` is known.
  bool compose(uint32_t uav, uint32_t tick, uint32_t max_age, uint32_t min_tile_tick, ViewMsg& out) const;

  // Latest state of `uav`, if any.
  [[nodiscard]] const UavStateMsg* state(uint32_t uav) const;

  // Tiles within ceil(view_radius) of `c` (clipped to the map): a UAV's neighbourhood.
  [[nodiscard]] std::vector<TileCoord> neighbourhood(Cell c) const;

 private:
  // Which chunks of which tick of a region arrived.
  struct Arrived {
    uint32_t tick = 0;
    uint16_t chunks = 0;
    std::vector<uint16_t> seen;    // the chunks of `tick` that arrived, each once
    std::vector<uint32_t> uavs;    // served states: the UAVs in the chunks of `tick`
    std::vector<uint32_t> served;  // the UAVs of the newest tick whose every chunk arrived
    uint32_t heard = 0;            // the receiver's tick its newest chunk arrived at (update_served)
    [[nodiscard]] bool complete(uint32_t t) const { return tick == t && seen.size() >= chunks; }
  };
  // Records chunk `chunk` of `chunks` of `region`'s tick `tick` in `to`;
  // false if it is older than what `to` holds, or arrived before.
  static bool arrive(std::map<RegionId, Arrived>& to, RegionId region, uint32_t tick, uint16_t chunk, uint16_t chunks);
  static std::string missing(const std::map<RegionId, Arrived>& from, uint32_t tick, std::span<const RegionId> regions);
  [[nodiscard]] Cell view_centre(const UavStateMsg& s) const;
  // A tile's key in tiles_ and over_ (tx, ty of a valid tile fit in 32 bits each).
  [[nodiscard]] static uint64_t tile_key(TileCoord t) {
    return (uint64_t{static_cast<uint32_t>(t.ty)} << 32U) | static_cast<uint32_t>(t.tx);
  }

  MapGeometry geo_;
  int layers_;
  int32_t radius_;
  bool neighbours_;
  // The newest value of each tile layer that arrived, by tile_key: layer l
  // of a tile at index l of its slots. Hash maps whose entries are
  // overwritten in place: a new tick of a tile or a UAV already seen
  // reuses its entry's storage (a place agent runs this for every tick of
  // the swarm's served UAVs and of its views' tiles).
  struct Held {
    TileMsg tile;
    uint32_t arrived = 0;
    bool held = false;
  };
  std::unordered_map<uint64_t, std::vector<Held>> tiles_;
  std::unordered_map<uint32_t, UavStateMsg> states_;  // references stay valid as it grows
  // The UAVs over each tile, by tile_key, ascending (only for a policy that
  // reads neighbours: nothing else asks).
  std::unordered_map<uint64_t, std::vector<uint32_t>> over_;
  std::map<RegionId, Arrived> served_, tiles_from_;
  // update_served (the place clock's list): the listed regions, and the
  // region and index in the list of each well-formed entry of one of them,
  // kept between ticks for their storage.
  std::vector<RegionId> regions_;
  std::vector<std::pair<RegionId, std::size_t>> listed_;
};

// Splits a region's tiles and home UAV states of one tick into RegionField
// chunks within the IDL bounds (at least one chunk, also when both are empty).
std::vector<FieldMsg> make_field_chunks(RegionId region, uint32_t tick, const std::vector<TileMsg>& tiles,
                                        const std::vector<UavStateMsg>& states);

}  // namespace pheromesh::core
