#include "pheromesh/console/commands.hpp"

#include <limits>

namespace pheromesh::console {

namespace {
using Answer = ConsoleSource::Answer;

// The value as a 64-bit integer, range-checked by the caller before any
// narrowing. JSON keeps integers above 2^63 - 1 as unsigned; read as int64
// they would wrap to negative numbers (2^64 - 3 -> -3, a valid x0), so they
// are refused here.
std::optional<int64_t> integer(const nlohmann::json& body, const char* name) {
  if (!body.contains(name) || !body[name].is_number_integer()) return std::nullopt;
  const auto& v = body[name];
  if (v.is_number_unsigned() && v.get<uint64_t>() > static_cast<uint64_t>(std::numeric_limits<int64_t>::max())) {
    return std::nullopt;
  }
  return v.get<int64_t>();
}

std::string range(uint32_t n) { return "0.." + std::to_string(n == 0 ? 0 : n - 1); }
}  // namespace

ParsedCommand parse_command(const nlohmann::json& body, const CommandContext& ctx) {
  using K = ConsoleCommand::Kind;
  const std::string kind =
      body.is_object() && body.contains("kind") && body["kind"].is_string() ? body["kind"].get<std::string>() : "";
  ParsedCommand p;
  p.what = kind.empty() ? "(no kind)" : kind;
  const auto refuse = [&p](int status, std::string message) {
    p.refusal = {status, std::move(message)};
    return p;
  };
  const auto accept = [&p](ConsoleCommand c) {
    p.command = c;
    return p;
  };
  if (kind == "unauthorised") {
    p.what = "command without a valid token";
    return refuse(401, "refused: no or wrong token");
  }
  if (kind == "pause") return accept({K::Pause});
  if (kind == "resume") return accept({K::Resume});
  if (kind == "kill_uav" || kind == "restart_uav") {
    const bool kill = kind == "kill_uav";
    p.what = kill ? "kill uav " : "restart uav ";
    const auto id = integer(body, "uav");
    if (!id || *id < 0 || *id >= ctx.uavs) return refuse(400, "\"uav\" must be an integer " + range(ctx.uavs));
    p.what += std::to_string(*id);
    if (!kill && ctx.lockstep) return refuse(409, "restarting a UAV is supported with the realtime clock only");
    ConsoleCommand c{kill ? K::KillUav : K::RestartUav};
    c.id = static_cast<uint32_t>(*id);
    return accept(c);
  }
  if (kind == "kill_place") {
    p.what = "kill place agent ";
    const auto r = integer(body, "region");
    if (!r || *r < 0 || *r >= ctx.regions) return refuse(400, "\"region\" must be an integer " + range(ctx.regions));
    p.what += std::to_string(*r);
    ConsoleCommand c{K::KillPlace};
    c.id = static_cast<uint32_t>(*r);
    return accept(c);
  }
  if (kind == "obstacle") {
    const auto x0 = integer(body, "x0"), y0 = integer(body, "y0"), w = integer(body, "w"), h = integer(body, "h");
    if (!x0 || !y0 || !w || !h || *w < 1 || *h < 1 || *w > ctx.width || *h > ctx.height ||
        *x0 < -ctx.width || *x0 > ctx.width || *y0 < -ctx.height || *y0 > ctx.height) {
      return refuse(400, "an obstacle needs integers x0, y0, w >= 1, h >= 1 (w, h at most the map's size)");
    }
    const core::Rect r{static_cast<int32_t>(*x0), static_cast<int32_t>(*y0), static_cast<int32_t>(*w), static_cast<int32_t>(*h)};
    p.what = "obstacle at (" + std::to_string(r.x0) + "," + std::to_string(r.y0) + ") " + std::to_string(r.w) + "x" +
             std::to_string(r.h);
    const bool inside = r.x0 < ctx.width && r.y0 < ctx.height && r.x0 + r.w > 0 && r.y0 + r.h > 0;
    if (!inside) return refuse(400, "the obstacle lies outside the map");
    if (ctx.uav_under) {
      if (auto u = ctx.uav_under(r)) return refuse(400, "the obstacle would cover uav " + std::to_string(*u) + "; place it beside the UAV");
    }
    ConsoleCommand c{K::Obstacle};
    c.rect = r;
    return accept(c);
  }
  if (kind == "target") {
    const auto x = integer(body, "x"), y = integer(body, "y");
    if (!x || !y || *x < 0 || *y < 0 || *x >= ctx.width || *y >= ctx.height) {
      return refuse(400, "a target needs integers x, y inside the map");
    }
    const core::Cell cell{static_cast<int32_t>(*x), static_cast<int32_t>(*y)};
    p.what = "target at (" + std::to_string(cell.x) + "," + std::to_string(cell.y) + ")";
    if (ctx.is_obstacle && ctx.is_obstacle(cell)) return refuse(400, "that cell is an obstacle");
    ConsoleCommand c{K::Target};
    c.cell = cell;
    return accept(c);
  }
  return refuse(400, "unknown kind '" + kind + "'; one of pause, resume, kill_uav, restart_uav, kill_place, obstacle, target");
}

std::optional<core::CommandMsg> swarm_command(const ConsoleCommand& c) {
  using K = ConsoleCommand::Kind;
  core::CommandMsg m;
  switch (c.kind) {
    case K::Pause: m.kind = static_cast<uint8_t>(core::CommandKind::Pause); return m;
    case K::Resume: m.kind = static_cast<uint8_t>(core::CommandKind::Resume); return m;
    case K::Obstacle:
      m.kind = static_cast<uint8_t>(core::CommandKind::Obstacle);
      m.x = c.rect.x0;
      m.y = c.rect.y0;
      m.w = c.rect.w;
      m.h = c.rect.h;
      return m;
    case K::Target:
      m.kind = static_cast<uint8_t>(core::CommandKind::Target);
      m.x = c.cell.x;
      m.y = c.cell.y;
      return m;
    case K::KillUav:
    case K::RestartUav:
    case K::KillPlace: return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace pheromesh::console
