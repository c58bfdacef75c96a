// The exhaustive fixed-route search Shao 2020 Sec. 4.3.3 compares the pheromone
// search with (Shao 2020 Fig. 6), flown as a UAV policy with transit, so that
// it runs in the simulator beside the swarm and under the same faults.
//
// The paper only says the exhaustive search "needs fixed routes". Our reading
// (ours, not the paper's):
//  - the map's rows are cut into one horizontal strip per UAV, strip i being
//    rows [i·H/N, (i+1)·H/N); the strip is swept by boustrophedon lanes
//    2·floor(SD)+1 rows apart, the first at the strip's first row + floor(SD)
//    (clipped to the map): the lanes of the baseline of `pheromesh experiment
//    shao-50x50`, whose routes, unlike these, start inside each strip;
//  - a UAV starts at its start cell (the swarm's start area) and flies real
//    transit to the first lane end, then sweeps its lanes, nearest lane
//    first, starting each sweep at the end its previous one finished at;
//  - it moves like a Shao searcher: one step to one of the 8 neighbouring
//    cells per tick, never into an obstacle. The route is planned offline on
//    the known map (the search is "exhaustive with fixed routes"): between
//    consecutive free lane cells it takes a shortest 8-connected path through
//    free cells, among equally short steps the one nearest (Euclidean) to the
//    goal, then the first in heading order E, NE, N, NW, W, SW, S, SE. Lane
//    cells that lie in obstacles or cannot be reached are left out; when the
//    lanes are flown, it visits (nearest first by path length, ties in
//    row-major order) every cell of its strip reachable from its start that
//    its sensor has not yet covered — the far sides of the blocks its lanes
//    went around;
//  - same sensor as the searchers (radius SD): it reports each target when it
//    comes within range; it deposits nothing (it reads no pheromone) and,
//    once its route is flown, it hovers at the route's end;
//  - a fixed route does not adapt: when UAVs die, nobody flies their strips.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/world.hpp"

namespace pheromesh::core {

// UAV `id`'s strip [row_begin, row_end) and its lane rows, in sweep order.
struct LawnmowerStrip {
  int32_t row_begin = 0, row_end = 0;
  std::vector<int32_t> lanes;
};
LawnmowerStrip lawnmower_strip(const ScenarioConfig& s, uint32_t id);

// UAV `id`'s whole route, one cell per tick: route[0] is its start cell,
// route[t] where it is after t moves. Consecutive cells are 8-neighbours
// (or equal, never), all free.
std::vector<Cell> lawnmower_transit_route(const ScenarioConfig& s, const World& world, uint32_t id);

// A shortest 8-connected path from `from` to `to` through free cells,
// `from` excluded and `to` included, with the tie rule above; empty if `to`
// cannot be reached (or equals `from`).
std::vector<Cell> free_path(const World& world, Cell from, Cell to);

std::unique_ptr<UavPolicy> make_shao_lawnmower_uav(const ScenarioConfig& s, const MapGeometry& geo, const World& world,
                                                   uint32_t id);

}  // namespace pheromesh::core
