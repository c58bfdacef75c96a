// pheromesh-ground: flags -> scenario -> bus -> app -> run. With --attach the
// scenario comes from the running swarm (its place agents publish it).
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>

#include "ground_app.hpp"
#include "pheromesh/cliutil/command_line.hpp"
#include "pheromesh/core/scenario.hpp"
#ifdef PHEROMESH_WITH_PYTHON
#include "pheromesh/pypolicy/enable.hpp"  // policies written in Python (docs/python.md)
#endif

int main(int argc, char** argv) {
  using namespace pheromesh;
#ifdef PHEROMESH_WITH_PYTHON
  pypolicy::enable_python_policies();
#endif
  groundstation::GroundConfig cfg;
  CLI::App app{
      "pheromesh ground station: watches the whole swarm, prints progress, and on SIGINT/SIGTERM "
      "writes OUT/metrics.json (coverage, targets found, revisit response, deposit accounting). With --http "
      "it serves the web console (heat maps, UAVs, place agents, plots, controls; docs/console.md) and "
      "Prometheus /metrics; with --record it records the console for `pheromesh replay`.",
      "pheromesh-ground"};
  double attach_timeout_s = 60.0;
  groundstation::add_ground_options(app, cfg, attach_timeout_s);
  app.get_option("--scenario")->required(false);
  if (auto rc = cli::parse_command_line(app, argc, argv)) return *rc;
  cfg.scenario_path = cfg.common.scenario;
  if (cfg.attach) return groundstation::attach(cfg, attach_timeout_s);
  if (cfg.common.scenario.empty()) {
    std::fprintf(
        stderr,
        "--scenario is required (or --attach, to monitor a running swarm)\nRun with --help for more information.\n");
    return 106;
  }

  return runtime::run_process("ground", cfg.common, [&](core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus) {
    groundstation::GroundApp ground(cfg, std::move(scenario), std::move(bus));
    return runtime::bound_teardown(ground.run());
  });
}
