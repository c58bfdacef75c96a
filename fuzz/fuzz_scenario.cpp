// Fuzz harness: a scenario file (protobuf text format, docs/scenario-format.md)
// through parse_scenario, which also parses the `fault:` lines, then what
// every process derives from an accepted scenario at start: the geometry,
// each region's tiles and neighbours, the policy's layers and the start
// cells. Input: the file's bytes.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/scenario.hpp"

using namespace pheromesh;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  auto parsed = core::parse_scenario(text, "fuzz.textproto");
  if (!parsed) {
    // A refusal must say something: an empty message is a bug too.
    if (parsed.error().message.empty()) __builtin_trap();
    return 0;
  }
  const core::ScenarioConfig& s = parsed.value();
  const core::MapGeometry geo = s.geometry();
  // Bounded, so one input stays fast: a valid map may have ~10^6 regions.
  const core::RegionId regions = geo.region_count() < 256 ? geo.region_count() : 256;
  for (core::RegionId r = 0; r < regions; ++r) {
    (void)geo.region_rect(r);
    (void)geo.region_tiles(r);
    (void)geo.neighbour_regions(r);
  }
  (void)core::policy_traits(s);
  // Start cells of the swarm (bounded: validation allows many UAVs).
  const uint32_t n = s.uavs < 64 ? s.uavs : 64;
  for (uint32_t id = 0; id < n; ++id) {
    const core::Cell c = core::start_cell(s, id);
    if (!geo.in_map(c)) __builtin_trap();  // a validated scenario starts every UAV on the map
  }
  return 0;
}
