// pheromesh-ground: flags -> scenario -> bus -> app -> run.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>

#include "ground_app.hpp"
#include "pheromesh/core/scenario.hpp"

int main(int argc, char** argv) {
  using namespace pheromesh;
  groundstation::GroundConfig cfg;
  CLI::App app{"pheromesh ground station (headless): watches the whole swarm, prints progress, and on SIGINT/SIGTERM "
               "writes OUT/metrics.json (coverage, targets found, revisit response, deposit accounting).",
               "pheromesh-ground"};
  runtime::add_common_options(app, cfg.common);
  app.add_option("--out", cfg.out_dir, "Folder for metrics.json")->capture_default_str();
  app.add_option("--expect-uavs", cfg.expect_uavs, "UAVs expected (default: the scenario's swarm.uavs)");
  app.add_option("--progress", cfg.progress_period_s, "Seconds between progress lines [s]")->capture_default_str();
  app.add_option("--phase-timeout", cfg.phase_timeout_s, "Lockstep: longest wait for one phase [s]")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  return runtime::run_process("ground", cfg.common, [&](core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus) {
    return groundstation::GroundApp(cfg, std::move(scenario), std::move(bus)).run();
  });
}
