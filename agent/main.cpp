// pheromesh-uav: flags -> scenario -> bus -> app -> run.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>

#include "pheromesh/core/scenario.hpp"
#include "uav_app.hpp"

int main(int argc, char** argv) {
  using namespace pheromesh;
  agent::UavConfig cfg;
  CLI::App app{"pheromesh UAV agent: one UAV running the Shao 2020 ACO search. It reads the pheromone tiles around "
               "it, decides, moves, senses targets and obstacles, deposits to the place agents there and publishes "
               "its state.",
               "pheromesh-uav"};
  runtime::add_common_options(app, cfg.common);
  app.add_option("--id", cfg.id, "UAV id (0-based; also picks its start cell and random stream)")->required();
  app.add_option("--wait-for-places", cfg.wait_for_places_s, "Seconds to wait at start for every place agent [s]")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  auto log = runtime::make_logger("uav-" + std::to_string(cfg.id), cfg.common.log_level);
  auto scenario = runtime::load_scenario(cfg.common);
  if (!scenario) {
    log->error("invalid scenario:\n{}", scenario.error().message);
    return 2;
  }
  runtime::install_shutdown_handlers();
  auto bus = bus::make_bus(cfg.common.dds, runtime::bus_options(cfg.common, "uav-" + std::to_string(cfg.id)));
  if (!bus) {
    log->error("{}", bus.error().message);
    return 3;
  }
  try {
    agent::UavApp uav(cfg, std::move(scenario).value(), std::move(bus).value());
    return uav.run();
  } catch (const std::exception& e) {
    log->critical("fatal: {}", e.what());
    return 4;
  }
}
