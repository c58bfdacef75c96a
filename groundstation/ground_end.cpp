// The end of a ground station's run: the End it announces (--until-done),
// the wait for the place agents' final health, and OUT/metrics.json,
// final_field.txt and the tidy files (docs/outputs.md).
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <filesystem>

#include "ground_app.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/report/report.hpp"
#include "pheromesh/report/tidy.hpp"

namespace pheromesh::groundstation {

using Clock = std::chrono::steady_clock;

void GroundApp::end_run() {
  ended_ = true;
  core::CommandMsg end;
  end.kind = static_cast<uint8_t>(core::CommandKind::End);
  const auto a = publish_swarm_command(end);
  if (a.status == 200) {
    log_->info("every uav finished or is gone: {}", a.message);
  } else {
    log_->error("every uav finished or is gone, but the end of the run cannot be announced: {}", a.message);
  }
}

void GroundApp::drain() {
  // After an End the place agents, maybe on other hosts, finish their last
  // tick and publish it: longer.
  const auto deadline = Clock::now() + std::chrono::seconds(ended_ ? 10 : 3);
  for (;;) {
    poll();
    if (book_.places_finished(rec_) || Clock::now() > deadline) break;
    wait_for_data(std::min(deadline, Clock::now() + std::chrono::milliseconds(20)));
  }
}

int GroundApp::finish() {
  drain();
  log_notes(intake_.judge_pending());
  print_progress();
  if (console_) close_console();
  finish_mavlink();
  return write_results();
}

int GroundApp::write_results() {
  const auto field_value = [this](int layer, core::Cell c) { return intake_.field_value(layer, c); };
  rec_.set_field_summary(core::field_summary(scenario_, field_value));
  std::string error;
  const report::RunInfo info{bus_->vendor(),
                             cfg_.common.clock,
                             report::Runner::Processes,
                             cfg_.expect_uavs,
                             book_.discovery_s(),
                             conductor_.phase_times().uav_ms,
                             conductor_.phase_times().place_ms,
                             bus_->stats().bytes_taken};
  if (!report::write_json(cfg_.out_dir, "metrics.json", report::metrics_json(rec_, info), error)) {
    log_->error("{}", error);
    return 5;
  }
  const std::filesystem::path out(cfg_.out_dir);
  const std::vector<std::string>& layers = core::policy_traits(scenario_).layers;
  const std::string field_path = (out / "final_field.txt").string();
  const bool field_ok = report::write_field(field_path, geo_, layers, field_value);
  if (!field_ok) log_->error("cannot write {}", field_path);
  // The tidy files (docs/outputs.md): in lockstep equal to the simulator's.
  std::vector<core::Result<std::size_t>> tidy;
  tidy.push_back(report::write_series_csv((out / "series.csv").string(), rec_.tick_series()));
  tidy.push_back(report::write_field_csv((out / "final_field.csv").string(), geo_, layers, field_value));
  if (cfg_.tracks) tidy.push_back(report::write_tracks_csv((out / "tracks.csv").string(), rec_.tracks()));
  for (const auto& w : tidy) {
    if (!w) log_->error("{}", w.error().message);
  }
  log_->info("wrote {}/metrics.json, series.csv, final_field.txt and final_field.csv{}", cfg_.out_dir,
             cfg_.tracks ? ", tracks.csv" : "");
  return 0;
}

}  // namespace pheromesh::groundstation
