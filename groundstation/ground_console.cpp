// The ground station's web console, recording and commands (docs/console.md).
#include <poll.h>
#include <spdlog/spdlog.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <limits>

#include "ground_app.hpp"
#include "pheromesh/console/commands.hpp"
#include "pheromesh/console/prometheus.hpp"
#include "pheromesh/console/view.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/uav_core.hpp"

namespace pheromesh::groundstation {

using Clock = std::chrono::steady_clock;
using Answer = console::ConsoleSource::Answer;

namespace {
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

uint64_t wall_ms() {
  return static_cast<uint64_t>(
      std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch()).count());
}
}  // namespace

void GroundApp::start_console() {
  console_t0_ = Clock::now();
  next_frame_ = console_t0_;
  next_series_ = console_t0_;
  auto key = auth::control_key_from_env();
  if (!key) {
    log_->error("{}; console commands to the swarm are disabled", key.error().message);
  } else {
    control_key_ = key.value();
  }
  if (!cfg_.http_port && cfg_.record_path.empty()) return;

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

  ControlStatus control;
  control.enabled = cfg_.http_port.has_value();
  control.process_control = cfg_.launcher_fd >= 0;
  if (!control.process_control) control.reason = "kill and restart need the launcher: start the swarm with `pheromesh run --http PORT`";
  if (!control_key_) {
    control.reason += std::string(control.reason.empty() ? "" : "; ") + "pause and pop-ups need $" + auth::kControlKeyEnv +
                      " (set by pheromesh run)";
  }
  uncertainty_ = std::make_unique<console::UncertaintyTracker>(
      geo_, world_.reachable_from(core::all_starts(scenario_)), info.sensor_radius, std::max(1.0, scenario_.ticks / 10.0));
  console_ = std::make_unique<LiveConsole>(info, control);
  if (!cfg_.record_path.empty()) {
    auto w = console::RecordingWriter::open(cfg_.record_path, info);
    if (!w) {
      log_->error("cannot record the console: {}", w.error().message);
    } else {
      recording_ = std::move(w).value();
      log_->info("recording the console to {}", cfg_.record_path);
    }
  }
  if (cfg_.http_port) {
    console::ServerOptions o;
    o.bind = cfg_.http_bind;
    o.port = *cfg_.http_port;
    const char* token = std::getenv("PHEROMESH_CONSOLE_TOKEN");
    o.token = token != nullptr && *token != '\0' ? token : console::random_token();
    server_ = std::make_unique<console::ConsoleServer>(*console_, o);
    auto port = server_->start();
    if (!port) {
      log_->error("web console: {}", port.error().message);
      server_.reset();
    } else {
      log_->info("web console at {}", server_->url());
    }
  }
  build_frame();
}

void GroundApp::service() {
  if (!console_) return;
  for (auto& p : console_->take_pending()) p->done.set_value(execute(p->body, p->who));
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
      tiles_latest_, rec_, world_, scenario_.targets.size(), scenario_.obstacles, popup_obstacles_, paused_};
  console::Frame f = frame_builder_.build(console_->state(), sources, now, seconds_since(console_t0_));
  if (now >= next_series_ && uncertainty_) {
    f.series = console::SeriesPoint{0, f.t_s, f.tick, rec_.coverage().coverage(),
                                    static_cast<uint32_t>(rec_.acquisitions().found()), uncertainty_->mean(f.tick)};
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
  console::Exposition e;
  const console::ConsoleState& st = console_->state();
  std::map<std::string, int> uavs{{"alive", 0}, {"stale", 0}, {"dead", 0}, {"finished", 0}};
  for (const auto& [id, u] : st.uavs) ++uavs[console::to_string(u.liveness)];
  e.family("pheromesh_uavs", "gauge", "UAVs by liveness as the ground station sees them.");
  for (const auto& [k, n] : uavs) e.sample("pheromesh_uavs", {{"state", k}}, n);
  std::map<std::string, int> places{{"alive", 0}, {"stale", 0}, {"dead", 0}, {"finished", 0}};
  for (const auto& r : st.regions) ++places[console::to_string(r.liveness)];
  e.family("pheromesh_place_agents", "gauge", "Place agents by liveness.");
  for (const auto& [k, n] : places) e.sample("pheromesh_place_agents", {{"state", k}}, n);
  e.family("pheromesh_tick", "gauge", "Highest UAV tick seen.");
  e.sample("pheromesh_tick", st.tick);
  e.family("pheromesh_paused", "gauge", "1 while the swarm is paused from the console.");
  e.sample("pheromesh_paused", st.paused ? 1 : 0);
  e.family("pheromesh_coverage_ratio", "gauge", "Reachable cells seen at least once, 0..1.");
  e.sample("pheromesh_coverage_ratio", rec_.coverage().coverage());
  e.family("pheromesh_uncertainty_ratio", "gauge", "Mean environmental uncertainty over reachable cells, 0..1 (docs/console.md).");
  e.sample("pheromesh_uncertainty_ratio", uncertainty_ ? uncertainty_->mean(rec_.max_tick()) : 1.0);
  e.family("pheromesh_targets", "gauge", "Targets by status.");
  e.sample("pheromesh_targets", {{"status", "found"}}, static_cast<double>(rec_.acquisitions().found()));
  e.sample("pheromesh_targets", {{"status", "total"}}, static_cast<double>(world_.targets().size()));
  e.family("pheromesh_deposits_sent_total", "counter", "Deposits the UAVs report having sent.");
  e.sample("pheromesh_deposits_sent_total", static_cast<double>(rec_.deposits_sent()));
  e.family("pheromesh_region_deposits_applied_total", "counter", "Deposits a place agent applied to its layers.");
  for (const auto& r : st.regions) {
    e.sample("pheromesh_region_deposits_applied_total", {{"region", std::to_string(r.id)}}, static_cast<double>(r.deposits_applied));
  }
  e.family("pheromesh_region_deposits_rejected_total", "counter", "Deposits a place agent rejected.");
  for (const auto& r : st.regions) {
    e.sample("pheromesh_region_deposits_rejected_total", {{"region", std::to_string(r.id)}}, static_cast<double>(r.deposits_rejected));
  }
  e.family("pheromesh_region_tick_rate_hz", "gauge", "Measured tick rate of a place agent.");
  for (const auto& r : st.regions) e.sample("pheromesh_region_tick_rate_hz", {{"region", std::to_string(r.id)}}, r.tick_rate_hz);
  e.family("pheromesh_region_up", "gauge", "1 if the place agent is alive.");
  for (const auto& r : st.regions) {
    e.sample("pheromesh_region_up", {{"region", std::to_string(r.id)}}, r.liveness == console::Liveness::Alive ? 1 : 0);
  }
  e.family("pheromesh_samples_rejected_total", "counter", "Malformed samples the ground station dropped.");
  e.sample("pheromesh_samples_rejected_total", static_cast<double>(rec_.samples_rejected() + bus_->stats().samples_dropped));
  e.family("pheromesh_console_frames_total", "counter", "Console frames built.");
  e.sample("pheromesh_console_frames_total", static_cast<double>(frames_));
  e.family("pheromesh_console_commands_total", "counter", "Console commands by result.");
  e.sample("pheromesh_console_commands_total", {{"result", "ok"}}, static_cast<double>(commands_ok_));
  e.sample("pheromesh_console_commands_total", {{"result", "refused"}}, static_cast<double>(commands_refused_));
  if (server_) {
    const auto s = server_->stats();
    e.family("pheromesh_console_http_requests_total", "counter", "HTTP requests served by the console.");
    e.sample("pheromesh_console_http_requests_total", static_cast<double>(s.requests));
    e.family("pheromesh_console_http_body_bytes_total", "counter", "Response body bytes before compression.");
    e.sample("pheromesh_console_http_body_bytes_total", static_cast<double>(s.body_bytes));
  }
  if (recording_) {
    e.family("pheromesh_recording_bytes_total", "counter", "Bytes written to the console recording.");
    e.sample("pheromesh_recording_bytes_total", static_cast<double>(recording_->bytes_written()));
  }
  return e.text();
}

void GroundApp::log_command(const std::string& who, const std::string& what, const Answer& a) {
  const bool ok = a.status == 200;
  (ok ? commands_ok_ : commands_refused_)++;
  if (ok) {
    log_->info("console command from {}: {} -> {}", who, what, a.message);
  } else {
    log_->warn("console command from {}: {} refused ({}): {}", who, what, a.status, a.message);
  }
  command_log_.push_back({0, seconds_since(console_t0_), who, what, ok, a.message});
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

Answer GroundApp::ask_launcher(const std::string& line) {
  if (cfg_.launcher_fd < 0) return {409, "kill and restart need the launcher: start the swarm with pheromesh run"};
  const std::string out = line + "\n";
  if (::send(cfg_.launcher_fd, out.data(), out.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(out.size())) {
    return {409, "the launcher is gone"};
  }
  std::string reply;
  const auto deadline = Clock::now() + std::chrono::seconds(5);
  while (reply.empty() || reply.back() != '\n') {
    pollfd p{cfg_.launcher_fd, POLLIN, 0};
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0 || ::poll(&p, 1, static_cast<int>(left)) <= 0) return {504, "the launcher did not answer within 5 s"};
    char buf[512];
    const ssize_t n = ::recv(cfg_.launcher_fd, buf, sizeof buf, 0);
    if (n <= 0) return {409, "the launcher is gone"};
    reply.append(buf, static_cast<std::size_t>(n));
  }
  reply.pop_back();
  if (reply.rfind("ok ", 0) == 0) return {200, reply.substr(3)};
  return {409, reply.rfind("error ", 0) == 0 ? reply.substr(6) : reply};
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
      if (a.status == 200 && cfg_.launcher_fd >= 0) ask_launcher(pause ? "pause" : "resume");  // the launcher extends its deadline
      return a;
    }
    case K::KillUav: return ask_launcher("kill uav " + std::to_string(c.id));
    case K::RestartUav: return ask_launcher("restart uav " + std::to_string(c.id));
    case K::KillPlace: return ask_launcher("kill place " + std::to_string(c.id));
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
