// pheromesh-place: flags -> scenario -> bus -> app -> run.
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
  uint32_t replica = 0;
  placeagent::add_place_options(app, cfg, replica);
  if (auto rc = cli::parse_command_line(app, argc, argv)) return *rc;
  cfg.common.place_replica = static_cast<int32_t>(replica);
  cfg.replica = static_cast<uint16_t>(replica);

  const std::string name = "place-" + std::to_string(cfg.region) + (replica > 0 ? ".r" + std::to_string(replica) : "");
  return runtime::run_process(name, cfg.common, [&](core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus) {
    if (auto rc = placeagent::check_place_config(cfg, scenario)) return *rc;
    placeagent::PlaceApp place(cfg, std::move(scenario), std::move(bus));
    return runtime::bound_teardown(place.run());
  });
}
