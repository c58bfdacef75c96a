#include "pheromesh/frontdoor/sim_outputs.hpp"

#include <filesystem>

#include "pheromesh/core/policy.hpp"
#include "pheromesh/report/report.hpp"
#include "pheromesh/report/tidy.hpp"

namespace pheromesh::frontdoor {

nlohmann::json sim_metrics(const core::Simulator& sim, double wall_seconds) {
  report::RunInfo info;  // no DDS, no discovery in-process
  info.runner = report::Runner::Simulator;
  info.clock = "lockstep";
  info.uavs_expected = sim.scenario().uavs;
  auto j = report::metrics_json(sim.recorder(), info);
  // The launcher counts killed processes; the simulator counts the kills it ran.
  j["processes_killed"] = sim.recorder().uavs_killed() + sim.recorder().places_killed();
  j["wall_seconds"] = wall_seconds;
  j["uav_steps_per_second"] = static_cast<double>(sim.uav_steps()) / wall_seconds;
  return j;
}

bool write_sim_field(const core::Simulator& sim, const std::string& path) {
  return report::write_field(path, sim.scenario().geometry(), core::policy_traits(sim.scenario()).layers,
                              [&](int layer, core::Cell c) { return sim.field_value(layer, c); });
}

std::string write_sim_outputs(const core::Simulator& sim, const std::string& out_dir) {
  const std::filesystem::path out(out_dir);
  const core::RunRecorder& rec = sim.recorder();
  if (auto w = report::write_series_csv((out / "series.csv").string(), rec.tick_series()); !w) return w.error().message;
  const std::string field = (out / "final_field.txt").string();
  if (!write_sim_field(sim, field)) return "cannot write " + field;
  const auto value = [&](int layer, core::Cell c) { return sim.field_value(layer, c); };
  if (auto w = report::write_field_csv((out / "final_field.csv").string(), sim.scenario().geometry(),
                                       core::policy_traits(sim.scenario()).layers, value);
      !w) {
    return w.error().message;
  }
  const std::vector<core::TrackRow> tracks = rec.tracks();
  if (!tracks.empty()) {
    if (auto w = report::write_tracks_csv((out / "tracks.csv").string(), tracks); !w) return w.error().message;
  } else {
    std::error_code ignored;  // an earlier run's, which this one did not make
    std::filesystem::remove(out / "tracks.csv", ignored);
  }
  return "";
}

}  // namespace pheromesh::frontdoor
