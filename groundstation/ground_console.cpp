// The ground station's web console and its recording (docs/console.md).
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdlib>
#include <limits>

#include "ground_app.hpp"
#include "pheromesh/console/commands.hpp"
#include "pheromesh/console/swarm_metrics.hpp"
#include "pheromesh/console/view.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/uav_core.hpp"
#include "pheromesh/report/report.hpp"

namespace pheromesh::groundstation {

using Clock = std::chrono::steady_clock;
using Answer = console::ConsoleSource::Answer;


void GroundApp::start_console() {
  console_t0_ = Clock::now();
  next_frame_ = console_t0_;
  next_series_ = console_t0_;
  auto key = auth::control_key_from_env();
  if (cfg_.attach) {
    // A monitor steers nothing: the swarm's ground station signs its commands.
  } else if (!key) {
    log_->error("{}; console commands to the swarm are disabled", key.error().message);
  } else {
    control_key_ = key.value();
  }
  if (!cfg_.http_port && cfg_.record_path.empty()) return;

  const console::ConsoleInfo info = console_info();
  uncertainty_ =
      std::make_unique<console::UncertaintyTracker>(geo_, world_.reachable_from(core::all_starts(scenario_)),
                                                    info.sensor_radius, std::max(1.0, scenario_.ticks / 10.0));
  intake_.set_uncertainty(uncertainty_.get());
  console_ = std::make_unique<LiveConsole>(info, control_status());
  if (!cfg_.record_path.empty()) start_recording(info);
  if (cfg_.http_port) start_server();
  build_frame();
}

console::ConsoleInfo GroundApp::console_info() const {
  console::ConsoleInfo info = console::console_info_of(scenario_);
  info.scenario_path = cfg_.scenario_path;
  info.uavs_expected = cfg_.expect_uavs;
  info.lease_ms = cfg_.common.lease_ms;
  info.clock = cfg_.common.clock;
  info.dds = bus_->vendor();
  return info;
}

ControlStatus GroundApp::control_status() const {
  ControlStatus control;
  control.enabled = cfg_.http_port.has_value();
  control.process_control = launcher_.connected();
  if (!control.process_control)
    control.reason = "kill and restart need the launcher: start the swarm with `pheromesh run --http PORT`";
  if (!control_key_) {
    control.reason += std::string(control.reason.empty() ? "" : "; ") + "pause and pop-ups need $" +
                      auth::kControlKeyEnv + " (set by pheromesh run)";
  }
  return control;
}

void GroundApp::start_recording(const console::ConsoleInfo& info) {
  auto w = console::RecordingWriter::open(cfg_.record_path, info);
  if (!w) {
    log_->error("cannot record the console: {}", w.error().message);
    return;
  }
  recording_ = std::move(w).value();
  log_->info("recording the console to {}", cfg_.record_path);
}

void GroundApp::start_server() {
  console::ServerOptions o;
  o.bind = cfg_.http_bind;
  o.port = *cfg_.http_port;
  const char* token = std::getenv("PHEROMESH_CONSOLE_TOKEN");
  o.token = token != nullptr && *token != '\0' ? token : console::random_token();
  o.limits = cfg_.http_limits;
  server_ = std::make_unique<console::ConsoleServer>(*console_, o);
  auto port = server_->start();
  if (!port) {
    log_->error("web console: {}", port.error().message);
    server_.reset();
  } else {
    log_->info("web console at {}", server_->url());
  }
}

void GroundApp::close_console() {
  // The last frame holds the final state; a replay ends with it too.
  build_frame();
  console_->close();
  const auto final_json = console::frame_json(console_->state(), console_->console_info(), 0, 0);
  std::string error;
  if (!report::write_json(cfg_.out_dir, "console_final.json", final_json, error)) log_->error("{}", error);
  if (server_) server_->stop();
  if (!recording_) return;
  // The recording appears under its name only now, complete (recording.hpp).
  if (auto closed = recording_->close(); !closed) {
    log_->error("{}", closed.error().message);
  } else {
    log_->info("recorded {} console frames ({} bytes) in {}", frames_, closed.value(), recording_->path());
  }
}

void GroundApp::service() {
  service_mavlink();
  if (!console_) return;
  for (auto& p : console_->take_pending()) p->done.set_value(execute(p->body, p->who));
  log_refusals();
  const auto now = Clock::now();
  if (now < next_frame_) return;
  build_frame();
  const auto period = std::chrono::nanoseconds(static_cast<int64_t>(1e9 / std::max(0.1, cfg_.console_hz)));
  next_frame_ += period;
  if (next_frame_ < now) next_frame_ = now + period;  // fell behind: no burst
}

void GroundApp::build_frame() {
  const auto now = Clock::now();
  const console::FrameBuilder::Sources sources{
      intake_.tiles(), rec_, world_, scenario_.targets.size(), scenario_.obstacles, popup_obstacles_, paused_};
  console::Frame f = frame_builder_.build(console_->state(), sources, now, seconds_since(console_t0_));
  if (now >= next_series_ && uncertainty_) {
    f.series = console::SeriesPoint{0,
                                    f.t_s,
                                    f.tick,
                                    rec_.coverage().coverage(),
                                    static_cast<uint32_t>(rec_.acquisitions().found()),
                                    uncertainty_->mean(f.tick)};
    next_series_ = now + std::chrono::seconds(1);
  }
  f.commands = std::move(command_log_);
  command_log_.clear();
  ++frames_;
  if (recording_ && !recording_failed_ && !recording_->write(f)) {
    recording_failed_ = true;
    log_->error("cannot write to the recording {}; recording stopped", recording_->path());
  }
  console_->publish(f);
  console_->set_metrics(metrics_text());  // of the state just published
}

std::string GroundApp::metrics_text() const {
  console::SwarmCounters c;
  c.coverage = rec_.coverage().coverage();
  c.uncertainty = uncertainty_ ? uncertainty_->mean(rec_.max_tick()) : 1.0;
  c.targets_found = rec_.acquisitions().found();
  c.targets_total = world_.targets().size();
  c.deposits_sent = rec_.deposits_sent();
  c.samples_rejected = rec_.samples_rejected() + bus_->stats().samples_dropped;
  const core::RefusalCounts by_places = rec_.refused_by_places(), by_uavs = rec_.refused_by_uavs();
  for (std::size_t i = 0; i < core::kRefusalCount; ++i) {
    const auto why = static_cast<core::Refusal>(i);
    c.samples_refused["places"][core::refusal_name(why)] = by_places[why];
    c.samples_refused["uavs"][core::refusal_name(why)] = by_uavs[why];
    c.samples_refused["ground"][core::refusal_name(why)] = rec_.refused()[why];
  }
  c.frames = frames_;
  c.commands_ok = commands_ok_;
  c.commands_refused = commands_refused_;
  if (server_) {
    const auto s = server_->stats();
    c.http_requests = s.requests;
    c.http_body_bytes = s.body_bytes;
    c.http_refused = s.refused;
    c.http_connections = s.open_connections;
    c.http_long_polls_unheld = s.long_polls_unheld;
    c.commands_refused += s.commands_unauthorised;  // refused before their body was read
  }
  if (recording_) c.recording_bytes = recording_->bytes_written();
  return console::swarm_metrics_text(console_->state(), c);
}

}  // namespace pheromesh::groundstation
