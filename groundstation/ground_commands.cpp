// The ground station's commands from the web console (docs/console.md):
// executing one (signed swarm commands, kills and restarts through the
// launcher, pop-ups), and logging what was done and refused.
#include <spdlog/spdlog.h>

#include <chrono>

#include "ground_app.hpp"
#include "pheromesh/console/commands.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/uav_core.hpp"

namespace pheromesh::groundstation {

using Clock = std::chrono::steady_clock;
using Answer = console::ConsoleSource::Answer;

namespace {

uint64_t wall_ms() {
  return static_cast<uint64_t>(
      std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
          .count());
}
}  // namespace

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
      // Realtime: --until-done does not wait for it (until it is restarted).
      if (a.status == 200 && cfg_.common.lockstep()) drop_uav(c.id, rec_.max_tick());
      if (a.status == 200 && !cfg_.common.lockstep()) book_.note_uav_killed(c.id, Clock::now());
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
