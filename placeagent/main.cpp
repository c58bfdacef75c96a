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

  auto log = runtime::make_logger("place-" + std::to_string(cfg.region), cfg.common.log_level);
  auto scenario = runtime::load_scenario(cfg.common);
  if (!scenario) {
    log->error("invalid scenario:\n{}", scenario.error().message);
    return 2;
  }
  if (cfg.region >= scenario->geometry().region_count()) {
    log->error("--region {} does not exist: the scenario has {} regions", cfg.region, scenario->geometry().region_count());
    return 2;
  }
  runtime::install_shutdown_handlers();
  auto bus = bus::make_bus(cfg.common.dds, runtime::bus_options(cfg.common, "place-" + std::to_string(cfg.region)));
  if (!bus) {
    log->error("{}", bus.error().message);
    return 3;
  }
  try {
    placeagent::PlaceApp place(cfg, std::move(scenario).value(), std::move(bus).value());
    return place.run();
  } catch (const std::exception& e) {
    log->critical("fatal: {}", e.what());
    return 4;
  }
}
