// pheromesh-ground --attach: a monitor that finds a running swarm by its
// domain id alone. The place agents publish the run (scenario text and
// options, transient-local); a first participant reads it, then the monitor
// joins with the run's options (ownership must match the place agents').
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdlib>
#include <memory>
#include <string>
#include <thread>

#include "ground_app.hpp"
#include "pheromesh/auth/control.hpp"
#include "pheromesh/bus/security.hpp"

namespace pheromesh::groundstation {

int attach(GroundConfig cfg, double timeout_s) {
  auto log = runtime::make_logger("ground", cfg.common.log_level);
  runtime::install_shutdown_handlers();
  const auto t0 = std::chrono::system_clock::now();
  const auto t0_ms = std::chrono::duration_cast<std::chrono::milliseconds>(t0.time_since_epoch()).count();
  // Times in this monitor's log count from its start.
  setenv("PHEROMESH_RUN_T0_MS", std::to_string(t0_ms).c_str(), 1);
  // A monitor signs nothing, even with the swarm's key in its environment.
  unsetenv(auth::kControlKeyEnv);

  // The monitor's bus with the options in cfg.common; null (logged) if it
  // cannot be made.
  const auto make_bus = [&](bool standby) -> std::unique_ptr<bus::Bus> {
    auto options = runtime::bus_options(cfg.common, "ground-attach", standby, log.get());
    if (!options) {
      log->error("{}", options.error().message);
      return nullptr;
    }
    // Under DDS Security the monitor has its own read-only identity.
    options->identity = bus::kMonitorIdentity;
    auto made = bus::make_bus(cfg.common.dds, options.value());
    if (!made) {
      log->error("{}", made.error().message);
      return nullptr;
    }
    return std::move(made).value();
  };

  core::ScenarioMsg run;
  {
    const auto bus = make_bus(/*standby=*/false);  // only to read the run
    if (!bus) return 3;
    bus->subscribe_scenario();
    log->info("looking for a swarm on domain {} over {} (profile {}{}), up to {:.0f} s", cfg.common.domain,
              bus->vendor(), cfg.common.dds_profile,
              cfg.common.secure.empty() ? "" : ", DDS Security as 'monitor'", timeout_s);
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::milliseconds(static_cast<int64_t>(timeout_s * 1000));
    std::vector<core::ScenarioMsg> got;
    while (got.empty()) {
      if (runtime::shutdown_requested()) return 130;
      if (std::chrono::steady_clock::now() > deadline) {
        log->error(
            "no place agent published a run on domain {} within {:.0f} s (is the swarm on this domain, with a "
            "profile that reaches this host: --dds-profile lan / lan-unicast --dds-peers?)",
            cfg.common.domain, timeout_s);
        return 2;
      }
      bus->wait({bus::TopicKind::Scenario}, std::chrono::steady_clock::now() + std::chrono::milliseconds(100));
      bus->take_scenarios(got);
    }
    run = got.front();
  }
  auto scenario = runtime::scenario_from_message(run, cfg.common);
  if (!scenario) {
    log->error("the swarm's scenario does not load here:\n{}", scenario.error().message);
    return 2;
  }
  const double found_s = std::chrono::duration<double>(std::chrono::system_clock::now() - t0).count();
  log->info("found run '{}' {:.2f} s after the start: {} uavs, {} ticks, {} clock{}", scenario->name, found_s,
            scenario->uavs, scenario->ticks, cfg.common.clock, cfg.common.standby ? ", standby place agents" : "");
  cfg.expect_uavs = scenario->uavs;
  cfg.until_done = false;
  cfg.launcher_fd = -1;
  cfg.fault_ticks.clear();
  cfg.scenario_path = "(published by the swarm)";
  auto bus = make_bus(scenario->standby);
  if (!bus) return 3;
  try {
    return GroundApp(cfg, std::move(scenario).value(), std::move(bus)).run();
  } catch (const std::exception& e) {
    log->critical("fatal: {}", e.what());
    return 4;
  }
}

}  // namespace pheromesh::groundstation
