// The place agent's flags and the checks of them against the scenario.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>

#include "place_app.hpp"

namespace pheromesh::placeagent {

void add_place_options(CLI::App& app, PlaceConfig& cfg, uint32_t& replica) {
  runtime::add_common_options(app, cfg.common);
  app.add_option("--region", cfg.region, "Region id owned by this process (0 .. regions_x*regions_y-1)")->required();
  app.add_option("--field-hz", cfg.field_hz,
                 "Realtime: how often the field goes to the ground station [Hz]: the tiles changed since the last "
                 "time, all of them every 2 s and at the end (lockstep: every tile, every tick)")
      ->check(CLI::Range(0.1, 1000.0))
      ->capture_default_str();
  app.add_option("--life", cfg.life,
                 "Which life of this place agent this process is: 1 its first start, 2.. started again after its "
                 "death (pheromesh run's restart passes it). From life 2 on it starts empty and takes none of the "
                 "deposits written before it started: its dead life counted them")
      ->check(CLI::Range(1U, 1000000U))
      ->capture_default_str();
  app.add_option("--replica", replica,
                 "Replica number in a swarm with --standby: 0 the primary, 1.. hot standbys (the lowest live one owns "
                 "the region's output; docs/faults.md)")
      ->check(CLI::Range(0, 999))
      ->capture_default_str();
}

std::optional<int> check_place_config(const PlaceConfig& cfg, const core::ScenarioConfig& scenario) {
  if (cfg.region >= scenario.geometry().region_count()) {
    spdlog::error("--region {} does not exist: the scenario has {} regions", cfg.region,
                  scenario.geometry().region_count());
    return 2;
  }
  if (cfg.replica > 0 && !(cfg.common.standby || scenario.standby)) {
    spdlog::error(
        "--replica {} needs a swarm with standbys: pass --standby to every process (or set run.standby in "
        "the scenario)",
        cfg.replica);
    return 2;
  }
  return std::nullopt;
}

}  // namespace pheromesh::placeagent
