// Scenario loading: protobuf text format against common/proto/scenario.proto.
// Errors name the file, the line and the field ("f.textproto:12:3: field
// 'map.tile_size': must be between 4 and 32").
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/result.hpp"
#include "pheromesh/core/policy_duan.hpp"
#include "pheromesh/core/policy_liu.hpp"
#include "pheromesh/core/policy_ravankar.hpp"
#include "pheromesh/core/policy_shao_navigation.hpp"
#include "pheromesh/core/policy_shostak.hpp"
#include "pheromesh/core/shao_params.hpp"

namespace pheromesh::core {

// The search policy a scenario runs (policy.hpp).
enum class PolicyKind : uint8_t { ShaoSearch = 0, ShaoNavigation, Liu, Shostak, Ravankar, Duan };
const char* policy_name(PolicyKind k);  // as in the scenario file: "shao_search", ...

struct ScenarioConfig {
  std::string name;
  std::string source_path;  // file it was loaded from ("" for text)
  // map
  int32_t width = 0, height = 0;  // [cell]
  int32_t tile_size = 10;         // [cell], 4..32 (a tile fits one DDS sample)
  int32_t regions_x = 1, regions_y = 1;
  std::vector<Rect> obstacles;
  std::vector<Cell> targets;
  // swarm
  uint32_t uavs = 10;
  Rect start_area{};           // UAVs start at distinct free cells in here
  uint32_t ticks = 1000;       // default run length [tick]
  double tick_rate_hz = 10.0;  // realtime clock rate [Hz]
  uint64_t seed = 1;
  ShaoLayerParams layers;
  ShaoAcoParams aco;
  PolicyKind policy = PolicyKind::ShaoSearch;
  ShaoNavigationConfig shao_navigation;  // policy ShaoNavigation
  LiuConfig liu;                         // policy Liu
  ShostakConfig shostak;                 // policy Shostak
  RavankarConfig ravankar;               // policy Ravankar
  DuanConfig duan;                       // policy Duan

  [[nodiscard]] MapGeometry geometry() const { return {width, height, tile_size, regions_x, regions_y}; }
};

Result<ScenarioConfig> load_scenario(const std::string& path);
// `display_name` is used in error messages in place of a path.
Result<ScenarioConfig> parse_scenario(std::string_view text, const std::string& display_name);

// Start cell of UAV `id` (0-based): deterministic for the scenario (free cells
// of start_area in row-major order, distributed round-robin).
Cell start_cell(const ScenarioConfig& s, uint32_t id);

}  // namespace pheromesh::core
