// The ground station's web console, recording and commands (docs/console.md).
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
#include "pheromesh/runtime/report.hpp"

namespace pheromesh::groundstation {

using Clock = std::chrono::steady_clock;
using Answer = console::ConsoleSource::Answer;

namespace {
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

uint64_t wall_ms() {
  return static_cast<uint64_t>(
      std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
          .count());
}
}  // namespace

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
  console::ConsoleInfo info;
  info.scenario_name = scenario_.name;
  info.scenario_path = cfg_.scenario_path;
  info.policy = core::policy_name(scenario_.policy);
  info.width = geo_.width();
  info.height = geo_.height();
  info.tile_size = geo_.tile_size();
  for (core::RegionId r = 0; r < geo_.region_count(); ++r) info.regions.push_back(geo_.region_rect(r));
  info.layers = core::policy_traits(scenario_).layers;
  info.tick_rate_hz = scenario_.tick_rate_hz;
  info.ticks = scenario_.ticks;
  info.uavs_expected = cfg_.expect_uavs;
  info.lease_ms = cfg_.common.lease_ms;
  info.sensor_radius = core::policy_traits(scenario_).sensor_radius;
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
  if (!runtime::write_json(cfg_.out_dir, "console_final.json", final_json, error)) log_->error("{}", error);
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
    c.commands_refused += s.commands_unauthorised;  // refused before their body was read
  }
  if (recording_) c.recording_bytes = recording_->bytes_written();
  return console::swarm_metrics_text(console_->state(), c);
}

void GroundApp::log_command(const std::string& who, const std::string& what, const Answer& a) {
  const bool ok = a.status == 200;
  (ok ? commands_ok_ : commands_refused_)++;
  const double t = seconds_since(console_t0_);
  if (ok) {
    log_->info("console command from {}: {} -> {}", who, what, a.message);
  } else {
    log_refusals();  // an ended window's summary before this one
    if (!refusal_log_.admit(t)) return;
    log_->warn("console command from {}: {} refused ({}): {}", who, what, a.status, a.message);
  }
  command_log_.push_back({0, t, who, what, ok, a.message});
}

void GroundApp::log_refusals() {
  const double t = seconds_since(console_t0_);
  uint64_t overflowed = 0;
  for (const auto& r : console_->take_refused(overflowed)) {
    if (!refusal_log_.admit(t)) continue;
    const std::string message =
        std::string("refused (") + std::to_string(r.status) + "): " + console::refusal_name(r.reason);
    log_->warn("console request from {}: {} {}", r.who, r.what, message);
    command_log_.push_back({0, t, r.who, r.what, false, message});
  }
  if (overflowed > 0) refusal_log_.suppress(overflowed, t);
  if (const auto k = refusal_log_.take_suppressed(t)) {
    const std::string what = "suppressed " + std::to_string(*k) + " refused requests";
    log_->warn("console: {} in the last {} s (at most {} are logged per window; all are counted in /metrics)", what,
               kRefusalWindowS, kRefusalsLogged);
    command_log_.push_back({0, t, "http", what, false, "not logged one by one; counted in /metrics"});
  }
}

Answer GroundApp::publish_swarm_command(core::CommandMsg c) {
  if (!control_key_) {
    return {409, std::string("this ground station has no control key ($") + auth::kControlKeyEnv +
                     "); start the swarm with pheromesh run"};
  }
  c.issuer = core::process_key(core::kRoleGround, 0);
  c.seq = ++command_seq_;
  c.issued_ms = wall_ms();
  auth::sign(c, *control_key_);
  if (!bus_->publish_command(c)) return {500, "the DDS write failed"};
  return {200, auth::describe(c) + " sent to the swarm (seq " + std::to_string(c.seq) + ")"};
}

Answer GroundApp::execute(const nlohmann::json& body, const std::string& who) {
  console::CommandContext ctx;
  ctx.uavs = cfg_.expect_uavs;
  ctx.regions = geo_.region_count();
  ctx.width = geo_.width();
  ctx.height = geo_.height();
  ctx.lockstep = cfg_.common.lockstep();
  ctx.uav_under = [this](const core::Rect& r) -> std::optional<uint32_t> {
    std::optional<uint32_t> covered;
    for (const auto& [id, u] : rec_.uavs()) {
      if (u.alive && !u.finished && r.contains(core::state_cell(u.last))) covered = id;
    }
    return covered;
  };
  ctx.is_obstacle = [this](core::Cell c) { return world_.is_obstacle(c); };
  const console::ParsedCommand p = console::parse_command(body, ctx);
  const Answer a = p.command ? apply(*p.command) : p.refusal;
  log_command(who, p.what, a);
  return a;
}

Answer GroundApp::apply(const console::ConsoleCommand& c) {
  using K = console::ConsoleCommand::Kind;
  switch (c.kind) {
    case K::Pause:
    case K::Resume: {
      const bool pause = c.kind == K::Pause;
      Answer a;
      if (cfg_.common.lockstep()) {
        paused_ = pause;  // the conductor holds the clock
        a = {200, pause ? "lockstep clock held" : "lockstep clock goes on"};
      } else {
        a = publish_swarm_command(*console::swarm_command(c));
        if (a.status == 200) paused_ = pause;
      }
      if (a.status == 200 && launcher_.connected())
        launcher_.ask(pause ? "pause" : "resume");  // the launcher extends its deadline
      return a;
    }
    case K::KillUav: {
      auto a = launcher_.ask("kill uav " + std::to_string(c.id));
      // Lockstep: the conductor knows it is gone and does not wait for it.
      if (a.status == 200 && cfg_.common.lockstep()) drop_uav(c.id, rec_.max_tick());
      return a;
    }
    case K::RestartUav:
      return launcher_.ask("restart uav " + std::to_string(c.id));
    case K::KillPlace: {
      auto a = launcher_.ask("kill place " + std::to_string(c.id));
      if (a.status == 200 && cfg_.common.lockstep()) drop_region(c.id, rec_.max_tick());
      return a;
    }
    case K::Obstacle: {
      const Answer a = publish_swarm_command(*console::swarm_command(c));
      if (a.status == 200) {
        world_.add_obstacle(c.rect);
        popup_obstacles_.push_back(c.rect);
      }
      return a;
    }
    case K::Target: {
      const Answer a = publish_swarm_command(*console::swarm_command(c));
      if (a.status == 200) {
        world_.add_target(c.cell);
        rec_.add_target();
      }
      return a;
    }
  }
  return {500, "unhandled command"};
}

}  // namespace pheromesh::groundstation
