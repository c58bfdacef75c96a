#include "sim_command.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/simulator.hpp"
#include "pheromesh/runtime/report.hpp"

namespace pheromesh::cli {

namespace {
// The scenario's own `fault:` lines (ScenarioConfig::faults, docs/faults.md)
// once the scenario format has them; none before.
template <class Scenario>
core::FaultSchedule scenario_faults(const Scenario& s) {
  if constexpr (requires { s.faults; }) {
    return s.faults;
  } else {
    return {};
  }
}
}  // namespace

int run_sim(const SimOptions& o) {
  auto loaded = load_overridden(o.scenario, o.overrides);
  if (!loaded) {
    spdlog::error("invalid scenario:\n{}", loaded.error().message);
    return 2;
  }
  core::ScenarioConfig s = std::move(loaded).value();
  if (!s.overrides.empty()) spdlog::info("overrides: {}", core::describe_overrides(s.overrides));
  core::FaultSchedule faults = scenario_faults(s);
  if (!o.faults.empty()) {
    auto parsed = core::parse_fault_schedule(o.faults, "--faults");
    if (!parsed) {
      spdlog::error("{}", parsed.error().message);
      return 2;
    }
    core::merge_fault_schedules(faults, parsed.value());
  }
  return simulate(s, faults, o);
}

int simulate(const core::ScenarioConfig& s, const core::FaultSchedule& faults, const SimOptions& o) {
  const core::MapGeometry geo = s.geometry();
  spdlog::info("sim '{}': {} regions, {} uavs, {} ticks, seed {}", s.name, geo.region_count(), s.uavs, s.ticks, s.seed);

  core::Simulator sim(s);
  if (!faults.empty()) {
    auto notes = sim.set_faults(faults, s.standby);
    if (!notes) {
      spdlog::error("faults: {}", notes.error().message);
      return 2;
    }
    for (const auto& n : notes.value()) spdlog::info("faults: {}", n);
    for (const auto& [u, k] : faults.uav_kills()) {
      if (k <= s.ticks) spdlog::info("faults: uav {} acts in ticks 0..{} only", u, static_cast<int64_t>(k) - 1);
    }
    for (const auto& [r, k] : faults.place_kills()) {
      if (k <= s.ticks && sim.region_kill_tick(r)) {
        spdlog::info("faults: region {} frozen from tick {} (its deposits and those of its home UAVs are lost)", r, k);
      }
    }
  } else if (s.standby) {
    spdlog::info("faults: standbys (--standby, run.standby) without a fault schedule change nothing");
  }
  const auto t0 = std::chrono::steady_clock::now();
  uint32_t next_report = s.ticks / 10;
  sim.run([&](uint32_t k) {
    if (!o.quiet && k >= next_report && next_report > 0) {
      spdlog::info("tick {:6d}/{} | coverage {:5.1f}% | targets {}/{}", k, s.ticks,
                   100.0 * sim.recorder().coverage().coverage(), sim.recorder().acquisitions().found(), s.targets.size());
      next_report += s.ticks / 10;
    }
  });
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  std::string error;
  const auto j = sim_metrics(sim, secs);
  if (!runtime::write_json(o.out_dir, "metrics.json", j, error)) {
    spdlog::error("{}", error);
    return 5;
  }
  const std::string field = (std::filesystem::path(o.out_dir) / "final_field.txt").string();
  if (!write_sim_field(sim, field)) {
    spdlog::error("cannot write {}", field);
    return 5;
  }
  spdlog::info("done in {:.2f} s ({:.0f} UAV-steps/s): coverage {:.1f}%, targets {}/{} at ticks {} -> {}/metrics.json",
               secs, static_cast<double>(sim.uav_steps()) / secs, 100.0 * sim.recorder().coverage().coverage(),
               sim.recorder().acquisitions().found(), s.targets.size(), j["acquisition_ticks"].dump(), o.out_dir);
  if (!faults.empty()) {
    spdlog::info("faults: {} uav(s) and {} place agent(s) killed, {} region(s) frozen; deposits sent {} = applied {} "
                 "+ rejected {} + lost {}",
                 sim.recorder().uavs_killed(), sim.recorder().places_killed(), sim.recorder().regions_frozen(),
                 j["deposits_sent"].get<uint64_t>(), j["deposits_applied"].get<uint64_t>(),
                 j["deposits_rejected"].get<uint64_t>(), j["deposits_lost"].get<uint64_t>());
  }
  return 0;
}

nlohmann::json sim_metrics(const core::Simulator& sim, double wall_seconds) {
  runtime::RunInfo info;  // no discovery in-process
  info.transport = "none (in-process simulator)";
  info.clock = "lockstep";
  info.uavs_expected = sim.scenario().uavs;
  auto j = runtime::metrics_json(sim.recorder(), info);
  // The launcher counts killed processes; the simulator counts the kills it ran.
  j["processes_killed"] = sim.recorder().uavs_killed() + sim.recorder().places_killed();
  j["wall_seconds"] = wall_seconds;
  j["uav_steps_per_second"] = static_cast<double>(sim.uav_steps()) / wall_seconds;
  return j;
}

bool write_sim_field(const core::Simulator& sim, const std::string& path) {
  return runtime::write_field(path, sim.scenario().geometry(), core::policy_traits(sim.scenario()).layers,
                              [&](int layer, core::Cell c) { return sim.field_value(layer, c); });
}

}  // namespace pheromesh::cli
