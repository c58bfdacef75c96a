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

int run_sim(const SimOptions& o) {
  auto loaded = core::load_scenario(o.scenario);
  if (!loaded) {
    spdlog::error("invalid scenario:\n{}", loaded.error().message);
    return 2;
  }
  core::ScenarioConfig s = std::move(loaded).value();
  if (o.seed > 0) s.seed = o.seed;
  if (o.ticks > 0) s.ticks = o.ticks;
  if (o.uavs > 0) s.uavs = o.uavs;
  const core::MapGeometry geo = s.geometry();
  spdlog::info("sim '{}': {} regions, {} uavs, {} ticks, seed {}", s.name, geo.region_count(), s.uavs, s.ticks, s.seed);

  core::Simulator sim(s);
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
  const runtime::RunInfo info{"none (in-process simulator)", "lockstep", s.uavs, std::nullopt};  // no discovery in-process
  auto j = runtime::metrics_json(sim.recorder(), info);
  j["wall_seconds"] = secs;
  j["uav_steps_per_second"] = static_cast<double>(sim.uav_steps()) / secs;
  if (!runtime::write_json(o.out_dir, "metrics.json", j, error)) {
    spdlog::error("{}", error);
    return 5;
  }
  const std::string field = (std::filesystem::path(o.out_dir) / "final_field.txt").string();
  if (!runtime::write_field(field, geo, core::policy_traits(sim.scenario()).layers, [&](int layer, core::Cell c) { return sim.field_value(layer, c); })) {
    spdlog::error("cannot write {}", field);
    return 5;
  }
  spdlog::info("done in {:.2f} s ({:.0f} UAV-steps/s): coverage {:.1f}%, targets {}/{} at ticks {} -> {}/metrics.json",
               secs, static_cast<double>(sim.uav_steps()) / secs, 100.0 * sim.recorder().coverage().coverage(),
               sim.recorder().acquisitions().found(), s.targets.size(), j["acquisition_ticks"].dump(), o.out_dir);
  return 0;
}

}  // namespace pheromesh::cli
