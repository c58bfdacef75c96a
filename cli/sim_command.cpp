#include "sim_command.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/scenario_warnings.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/simulator.hpp"
#include "pheromesh/report/report.hpp"
#include "pheromesh/report/tidy.hpp"
#include "pheromesh/frontdoor/sim_recording.hpp"

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

int refused_states_verdict(const nlohmann::json& metrics, bool strict) {
  // The same lines after `sim` and `run` (report::refused_state_lines).
  for (const auto& line : report::refused_state_lines(metrics)) spdlog::warn("{}", line);
  const auto first = report::first_refusal_line(metrics);
  if (!first || !strict) return 0;
  spdlog::error("--strict: {}; the run fails (exit {})", *first, kExitRefusedStates);
  return kExitRefusedStates;
}

int run_sim(const SimOptions& o) {
  auto loaded = load_overridden(o.scenario, o.overrides);
  if (!loaded) {
    spdlog::error("invalid scenario:\n{}", loaded.error().message);
    return 2;
  }
  core::ScenarioConfig s = std::move(loaded).value();
  if (!s.overrides.empty()) spdlog::info("overrides: {}", core::describe_overrides(s.overrides));
  for (const auto& w : core::scenario_warnings(s)) spdlog::warn("{}", w);
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

namespace {

// The fault schedule on the simulator, and what it means in the log; false
// if the simulator refuses it.
bool apply_faults(core::Simulator& sim, const core::ScenarioConfig& s, const core::FaultSchedule& faults) {
  if (!faults.empty()) {
    auto notes = sim.set_faults(faults, s.standby);
    if (!notes) {
      spdlog::error("faults: {}", notes.error().message);
      return false;
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
  return true;
}

// --record: the console recording (its folder made first); nullptr and an
// error in the log if it cannot be opened.
std::unique_ptr<frontdoor::SimRecording> open_recording(const std::string& path, const core::Simulator& sim) {
  const std::string& record = path;
  // Usually inside OUT, which the run has not made yet.
  if (const auto parent = std::filesystem::path(record).parent_path(); !parent.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(parent, ec);
    if (ec) {
      spdlog::error("cannot record the console: cannot create {}: {}", parent.string(), ec.message());
      return nullptr;
    }
  }
  auto opened = frontdoor::SimRecording::open(record, sim);
  if (!opened) {
    spdlog::error("cannot record the console: {}", opened.error().message);
    return nullptr;
  }
  auto recording = std::move(opened).value();
  spdlog::info("recording the console to {} (pheromesh replay {})", record, record);
  return recording;
}

// Runs the simulator to the end with a progress line every tenth of the run;
// returns the wall time [s]. recording_failed: a frame could not be written.
double run_with_progress(core::Simulator& sim, const core::ScenarioConfig& s, const SimOptions& o,
                         frontdoor::SimRecording* recording, bool& recording_failed) {
  const auto t0 = std::chrono::steady_clock::now();
  uint32_t next_report = s.ticks / 10;
  sim.run([&](uint32_t k) {
    if (recording && !recording_failed && !recording->after_tick(k)) {
      recording_failed = true;
      spdlog::error("cannot write to the recording {}", o.record);
    }
    if (!o.quiet && k >= next_report && next_report > 0) {
      spdlog::info("tick {:6d}/{} | coverage {:5.1f}% | targets {}/{}", k, s.ticks,
                   100.0 * sim.recorder().coverage().coverage(), sim.recorder().acquisitions().found(), s.targets.size());
      next_report += s.ticks / 10;
    }
  });
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return secs;
}

// 0, or 5 if the recording is incomplete.
int close_recording(frontdoor::SimRecording& recording, bool recording_failed, const std::string& path) {
  const std::string& record = path;
  auto closed = recording.close();
  if (recording_failed || !closed) {
    spdlog::error("the recording {} is incomplete: {}", record,
                  closed ? std::string("a frame could not be written") : closed.error().message);
    return 5;
  }
  spdlog::info("recorded {} console frames ({} bytes) in {}", recording.frames(), closed.value(), record);
  return 0;
}

void log_summary(const core::Simulator& sim, const core::ScenarioConfig& s, const SimOptions& o,
                 const core::FaultSchedule& faults, const nlohmann::json& j, double secs) {
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
}

}  // namespace

int simulate(const core::ScenarioConfig& s, const core::FaultSchedule& faults, const SimOptions& o) {
  const core::MapGeometry geo = s.geometry();
  spdlog::info("sim '{}': {} regions, {} uavs, {} ticks, seed {}", s.name, geo.region_count(), s.uavs, s.ticks, s.seed);

  core::Simulator sim(s);
  if (!apply_faults(sim, s, faults)) return 2;
  if (o.tracks) sim.keep_tracks();
  std::unique_ptr<frontdoor::SimRecording> recording;
  if (!o.record.empty()) {
    recording = open_recording(o.record, sim);
    if (!recording) return 5;
  }
  bool recording_failed = false;
  const double secs = run_with_progress(sim, s, o, recording.get(), recording_failed);

  std::string error;
  const auto j = sim_metrics(sim, secs);
  if (!report::write_json(o.out_dir, "metrics.json", j, error)) {
    spdlog::error("{}", error);
    return 5;
  }
  if (const std::string e = write_sim_outputs(sim, o.out_dir); !e.empty()) {
    spdlog::error("{}", e);
    return 5;
  }
  if (recording) {
    if (const int rc = close_recording(*recording, recording_failed, o.record); rc != 0) return rc;
  }
  log_summary(sim, s, o, faults, j, secs);
  return refused_states_verdict(j, o.strict);
}

}  // namespace pheromesh::cli
