// pheromesh-ground: flags -> scenario -> bus -> app -> run.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>

#include "ground_app.hpp"
#include "pheromesh/core/scenario.hpp"

int main(int argc, char** argv) {
  using namespace pheromesh;
  groundstation::GroundConfig cfg;
  CLI::App app{"pheromesh ground station: watches the whole swarm, prints progress, and on SIGINT/SIGTERM "
               "writes OUT/metrics.json (coverage, targets found, revisit response, deposit accounting). With --http "
               "it serves the web console (heat maps, UAVs, place agents, plots, controls; docs/console.md) and "
               "Prometheus /metrics; with --record it records the console for `pheromesh replay`.",
               "pheromesh-ground"};
  runtime::add_common_options(app, cfg.common);
  app.add_option("--out", cfg.out_dir, "Folder for metrics.json")->capture_default_str();
  app.add_option("--expect-uavs", cfg.expect_uavs, "UAVs expected (default: the scenario's swarm.uavs)");
  app.add_option("--progress", cfg.progress_period_s, "Seconds between progress lines [s]")->capture_default_str();
  app.add_option("--phase-timeout", cfg.phase_timeout_s, "Lockstep: longest wait for one phase [s]")->capture_default_str();
  app.add_option("--start-timeout", cfg.start_timeout_s,
                 "Lockstep: longest wait before tick 0 for every UAV and place agent to report that it matched the "
                 "readers it deposits to (then tick 0 starts anyway) [s]")
      ->capture_default_str();
  app.add_option("--departed-grace", cfg.departed_grace_s,
                 "Lockstep: a UAV whose liveliness lapsed and that sent nothing for this long is no longer waited for "
                 "(one killed by the launcher at a tick is dropped at once) [s]")
      ->capture_default_str();
  app.add_option("--http", cfg.http_port, "Serve the web console and /metrics on this port (0: any free port)");
  app.add_option("--http-bind", cfg.http_bind, "Address the console listens on (0.0.0.0: every interface)")
      ->capture_default_str();
  app.add_option("--console-hz", cfg.console_hz, "Console frames per second")->capture_default_str()->check(CLI::Range(0.2, 50.0));
  app.add_option("--record", cfg.record_path, "Record the console frames to this file (read by `pheromesh replay`)");
  app.add_option("--launcher-fd", cfg.launcher_fd, "Control socket inherited from `pheromesh run` (kill / restart)");
  app.add_option("--fault-ticks", cfg.fault_ticks,
                 "Lockstep: ticks with faults, comma-separated; before each one's UAV phase the conductor asks the launcher "
                 "(\"faults K\" on --launcher-fd) which processes it killed and drops them")
      ->delimiter(',');
  app.add_option("--faults-timeout", cfg.faults_timeout_s, "Lockstep: longest wait for the launcher's answer to \"faults K\" [s]")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  cfg.scenario_path = cfg.common.scenario;

  return runtime::run_process("ground", cfg.common, [&](core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus) {
    return groundstation::GroundApp(cfg, std::move(scenario), std::move(bus)).run();
  });
}
