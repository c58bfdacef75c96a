// pheromesh-uav: flags -> scenario -> bus -> app -> run.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>

#include "pheromesh/cliutil/command_line.hpp"
#include "pheromesh/core/scenario.hpp"
#include "uav_app.hpp"
#ifdef PHEROMESH_WITH_PYTHON
#include "pheromesh/pypolicy/enable.hpp"  // policies written in Python (docs/python.md)
#elif defined(PHEROMESH_UAV_PYTHON_SIBLING)
#include "python_sibling.hpp"  // they run in pheromesh-uav-python
#endif

int main(int argc, char** argv) {
  using namespace pheromesh;
#ifdef PHEROMESH_WITH_PYTHON
  pypolicy::enable_python_policies();
#elif defined(PHEROMESH_UAV_PYTHON_SIBLING)
  agent::run_python_policies_in(PHEROMESH_UAV_PYTHON_SIBLING, argv);
#endif
  agent::UavConfig cfg;
  CLI::App app{
      "pheromesh UAV agent: one UAV flying the scenario's policy (policy { ... }: any policy of the policy "
      "table, the Shao 2020 search when the file names none, or a plugin's). Each tick it reads the "
      "pheromone around it, decides, moves, senses targets and obstacles, deposits to the place agents "
      "there and publishes its state. `pheromesh run` starts one per UAV.",
      "pheromesh-uav"};
  runtime::add_common_options(app, cfg.common);
  app.add_option("--id", cfg.id, "UAV id (0-based; also picks its start cell and random stream)")->required();
  app.add_option("--wait-for-places", cfg.wait_for_places_s, "Seconds to wait at start for every place agent [s]")
      ->capture_default_str();
  app.add_option("--wait-for-start", cfg.wait_for_start_s,
                 "Realtime: seconds to wait for the ground station's start (sent once every process is heard) "
                 "before flying anyway [s]")
      ->capture_default_str();
  app.add_option(
      "--seq-base", cfg.seq_base,
      "Number deposits from this value + 1 (pheromesh run gives a restarted UAV a base above its earlier life's)");
  if (auto rc = cli::parse_command_line(app, argc, argv)) return *rc;

  const std::string name = "uav-" + std::to_string(cfg.id);
  return runtime::run_process(name, cfg.common, [&](core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus) {
    agent::UavApp uav(cfg, std::move(scenario), std::move(bus));
    return runtime::bound_teardown(uav.run());
  });
}
