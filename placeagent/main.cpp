// pheromesh-place: flags -> scenario -> bus -> app -> run.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>

#include "place_app.hpp"
#include "pheromesh/core/scenario.hpp"

int main(int argc, char** argv) {
  using namespace pheromesh;
  placeagent::PlaceConfig cfg;
  CLI::App app{"pheromesh place agent: owns the pheromone tiles of one map region, applies the deposits UAVs send it, "
               "evaporates and diffuses them (exchanging border halos with neighbouring regions) and publishes its "
               "tiles and health.",
               "pheromesh-place"};
  runtime::add_common_options(app, cfg.common);
  app.add_option("--region", cfg.region, "Region id owned by this process (0 .. regions_x*regions_y-1)")->required();
  app.add_option("--max-ticks", cfg.max_ticks, "Stop after this many ticks (0: run until SIGINT/SIGTERM)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  const std::string name = "place-" + std::to_string(cfg.region);
  return runtime::run_process(name, cfg.common, [&](core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus) {
    if (cfg.region >= scenario.geometry().region_count()) {
      spdlog::error("--region {} does not exist: the scenario has {} regions", cfg.region,
                    scenario.geometry().region_count());
      return 2;
    }
    return placeagent::PlaceApp(cfg, std::move(scenario), std::move(bus)).run();
  });
}
