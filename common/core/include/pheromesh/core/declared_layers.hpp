// A place model over layers a policy declares by their parameters instead of
// writing its own PlaceModel: every layer takes LayerAdd deposits (the
// generic deposit kind, messages.hpp), capped at its maximum, and each tick
// evaporates and diffuses to its 8 neighbours. Made for plugins
// (policy_plugin.hpp, docs/writing-a-policy.md); a built-in policy may use it
// too.
//
// One tick of a layer with evaporation e and diffusion g, over the whole map
// (N(i): the cells of the map around i, |N(j)| their number):
//
//   v'(i) = (1 - e) · ( (1 - g) · v(i) + g · Σ_{j ∈ N(i)} v(j) / |N(j)| )
//
// so a cell keeps (1 - g) of its pheromone and hands g of it to its
// neighbours in equal parts; nothing leaks at the map's edge, and with e = 0
// the layer's total is kept (below the cap: v' is at most the layer's max). Regions exchange their border cells (HaloRing),
// so a map split into regions gives exactly the field of the undivided map.
// A HaloRing carries two layers: at most two layers of a policy diffuse.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/result.hpp"

namespace pheromesh::core {

struct LayerSpec {
  std::string name;          // shown in the console and reports
  double evaporation = 0.0;  // e: share lost per tick, [0, 1)
  double diffusion = 0.0;    // g: share handed to the 8 neighbours per tick, [0, 1)
  float max = kMaxLayerValue;  // a cell holds at most this; also the plausibility range [0, max]
};

// At most this many layers diffuse (the two rings of a HaloRing).
inline constexpr std::size_t kMaxDiffusingLayers = 2;

// An error naming the first bad layer (its index and name), or true.
Result<bool> check_layer_specs(std::span<const LayerSpec> layers);

// The layers' names and plausibility ranges into `traits` (PolicyTraits::layers, layer_ranges).
void declare_layers(PolicyTraits& traits, std::span<const LayerSpec> layers);

// The place model of `region`. Throws std::invalid_argument for layers that
// fail check_layer_specs (a policy checks them when it parses its config).
std::unique_ptr<PlaceModel> make_declared_layers_place(std::vector<LayerSpec> layers, const MapGeometry& geo,
                                                       RegionId region);

}  // namespace pheromesh::core
