// Fuzz harness: the web console's command parser (POST /api/command,
// docs/console.md). The input is the request body; like the server, the
// harness parses it as JSON without exceptions and hands an object to
// console::parse_command, against a 30 x 30 map with 4 UAVs and 4 regions.
// Then what the ground station does with an accepted command: its swarm
// command. (fuzz_console_http covers the same body through the HTTP server.)
#include <cstddef>
#include <cstdint>
#include <optional>

#include <nlohmann/json.hpp>

#include "pheromesh/console/commands.hpp"

using namespace pheromesh;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const auto* text = reinterpret_cast<const char*>(data);
  nlohmann::json body = nlohmann::json::parse(text, text + size, nullptr, false);
  if (body.is_discarded()) return 0;
  console::CommandContext ctx;
  ctx.uavs = 4;
  ctx.regions = 4;
  ctx.width = 30;
  ctx.height = 30;
  ctx.lockstep = size % 2 == 0;
  ctx.uav_under = [](const core::Rect& r) -> std::optional<uint32_t> {
    // One UAV at (5, 5).
    if (r.x0 <= 5 && 5 < r.x0 + r.w && r.y0 <= 5 && 5 < r.y0 + r.h) return 2;
    return std::nullopt;
  };
  ctx.is_obstacle = [](core::Cell c) { return c.x == 10 && c.y == 10; };
  const console::ParsedCommand p = console::parse_command(body, ctx);
  if (p.command) {
    const console::ConsoleCommand& c = *p.command;
    // An accepted command is inside the map and the swarm.
    switch (c.kind) {
      case console::ConsoleCommand::Kind::KillUav:
      case console::ConsoleCommand::Kind::RestartUav:
        if (c.id >= ctx.uavs) __builtin_trap();
        break;
      case console::ConsoleCommand::Kind::KillPlace:
        if (c.id >= ctx.regions) __builtin_trap();
        break;
      case console::ConsoleCommand::Kind::Target:
        if (c.cell.x < 0 || c.cell.y < 0 || c.cell.x >= ctx.width || c.cell.y >= ctx.height) __builtin_trap();
        break;
      case console::ConsoleCommand::Kind::Obstacle:
        if (c.rect.w < 1 || c.rect.h < 1 || c.rect.w > ctx.width || c.rect.h > ctx.height) __builtin_trap();
        break;
      default:
        break;
    }
    (void)console::swarm_command(c);
  } else if (p.refusal.status < 400 || p.refusal.message.empty()) {
    __builtin_trap();  // a refusal has an error status and says why
  }
  (void)nlohmann::json(p.what).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  return 0;
}
