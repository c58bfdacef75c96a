// The web console's commands (POST /api/command, docs/console.md): the JSON
// body parsed and checked against the map and the swarm. Pure: what a valid
// command does (a signed swarm command, a request to the launcher, the
// lockstep clock held) is the ground station's.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "pheromesh/console/server.hpp"
#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/messages.hpp"

namespace pheromesh::console {

struct ConsoleCommand {
  enum class Kind : uint8_t { Pause, Resume, KillUav, RestartUav, KillPlace, Obstacle, Target };
  Kind kind = Kind::Pause;
  uint32_t id = 0;    // KillUav, RestartUav: the UAV; KillPlace: the region
  core::Rect rect{};  // Obstacle
  core::Cell cell{};  // Target
};

// What a command is checked against.
struct CommandContext {
  uint32_t uavs = 0;
  uint32_t regions = 0;
  int32_t width = 0, height = 0;  // [cell]
  bool lockstep = false;          // a UAV cannot be restarted into a lockstep run
  // A live UAV inside the rectangle (an obstacle must not cover one), if any.
  std::function<std::optional<uint32_t>(const core::Rect&)> uav_under;
  // The cell is an obstacle (a target cannot be put there).
  std::function<bool(core::Cell)> is_obstacle;
};

struct ParsedCommand {
  std::string what;                       // for the command log, refused or not ("kill uav 3")
  std::optional<ConsoleCommand> command;  // set if valid
  ConsoleSource::Answer refusal;          // status (400, 401, 409) and message if not
};

// Kind "unauthorised" is refused with 401 (the server itself refuses a
// request without the token on its headers, before reading its body, and
// reports it through ConsoleSource::refused). Integers are range-checked as
// 64-bit values before they are narrowed.
ParsedCommand parse_command(const nlohmann::json& body, const CommandContext& ctx);

// The idl Command of a swarm-wide console command (pause, resume, obstacle,
// target), unsigned; nullopt for those the launcher carries out.
std::optional<core::CommandMsg> swarm_command(const ConsoleCommand& c);

}  // namespace pheromesh::console
