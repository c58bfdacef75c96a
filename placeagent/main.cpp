// pheromesh-place: flags -> scenario -> bus -> app -> run.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>

#include "pheromesh/cliutil/command_line.hpp"
#include "pheromesh/core/scenario.hpp"
#include "place_app.hpp"
#ifdef PHEROMESH_WITH_PYTHON
#include "pheromesh/pypolicy/enable.hpp"  // policies written in Python (docs/python.md)
#endif

int main(int argc, char** argv) {
  using namespace pheromesh;
#ifdef PHEROMESH_WITH_PYTHON
  pypolicy::enable_python_policies();
#endif
  placeagent::PlaceConfig cfg;
  CLI::App app{
      "pheromesh place agent: owns the pheromone tiles of one map region, applies the deposits UAVs send it, "
      "evaporates and diffuses them (exchanging border halos with neighbouring regions) and publishes its "
      "tiles and health. Realtime, it runs until the ground station's End or SIGINT/SIGTERM; lockstep, for the "
      "ticks the conductor gives. `pheromesh run` starts one per region.",
      "pheromesh-place"};
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
  uint32_t replica = 0;
  app.add_option("--replica", replica,
                 "Replica number in a swarm with --standby: 0 the primary, 1.. hot standbys (the lowest live one owns "
                 "the region's output; docs/faults.md)")
      ->check(CLI::Range(0, 999))
      ->capture_default_str();
  if (auto rc = cli::parse_command_line(app, argc, argv)) return *rc;
  cfg.common.place_replica = static_cast<int32_t>(replica);
  cfg.replica = static_cast<uint16_t>(replica);

  const std::string name = "place-" + std::to_string(cfg.region) + (replica > 0 ? ".r" + std::to_string(replica) : "");
  return runtime::run_process(name, cfg.common, [&](core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus) {
    if (cfg.region >= scenario.geometry().region_count()) {
      spdlog::error("--region {} does not exist: the scenario has {} regions", cfg.region,
                    scenario.geometry().region_count());
      return 2;
    }
    if (replica > 0 && !(cfg.common.standby || scenario.standby)) {
      spdlog::error(
          "--replica {} needs a swarm with standbys: pass --standby to every process (or set run.standby in "
          "the scenario)",
          replica);
      return 2;
    }
    placeagent::PlaceApp place(cfg, std::move(scenario), std::move(bus));
    return runtime::bound_teardown(place.run());
  });
}
