// The web console's command parser (console/commands.hpp): each kind, each
// refusal with its status, and the idl command a valid one becomes.
#include <gtest/gtest.h>

#include "pheromesh/console/commands.hpp"

namespace pheromesh::console {
namespace {

using K = ConsoleCommand::Kind;
using nlohmann::json;

CommandContext ctx20x10() {
  CommandContext c;
  c.uavs = 4;
  c.regions = 2;
  c.width = 20;
  c.height = 10;
  c.uav_under = [](const core::Rect& r) -> std::optional<uint32_t> {
    if (r.contains({3, 3})) return 2U;  // UAV 2 flies over (3,3)
    return std::nullopt;
  };
  c.is_obstacle = [](core::Cell x) { return x.x == 7 && x.y == 7; };
  return c;
}

TEST(ConsoleCommands, PauseResumeAndTheLauncherKindsParseWithTheirIds) {
  const auto ctx = ctx20x10();
  auto p = parse_command(json{{"kind", "pause"}}, ctx);
  ASSERT_TRUE(p.command);
  EXPECT_EQ(p.command->kind, K::Pause);
  EXPECT_EQ(p.what, "pause");
  p = parse_command(json{{"kind", "kill_uav"}, {"uav", 3}}, ctx);
  ASSERT_TRUE(p.command);
  EXPECT_EQ(p.command->kind, K::KillUav);
  EXPECT_EQ(p.command->id, 3U);
  EXPECT_EQ(p.what, "kill uav 3");
  p = parse_command(json{{"kind", "restart_uav"}, {"uav", 0}}, ctx);
  ASSERT_TRUE(p.command);
  EXPECT_EQ(p.command->kind, K::RestartUav);
  p = parse_command(json{{"kind", "kill_place"}, {"region", 1}}, ctx);
  ASSERT_TRUE(p.command);
  EXPECT_EQ(p.command->id, 1U);
  EXPECT_EQ(p.what, "kill place agent 1");
  EXPECT_FALSE(swarm_command(*p.command)) << "the launcher carries it out";
}

TEST(ConsoleCommands, IdsOutOfRangeOrNotIntegersAreRefusedWithTheRange) {
  const auto ctx = ctx20x10();
  for (const json& body : {json{{"kind", "kill_uav"}, {"uav", 4}}, json{{"kind", "kill_uav"}, {"uav", -1}},
                           json{{"kind", "kill_uav"}, {"uav", "1"}}, json{{"kind", "kill_uav"}}}) {
    const auto p = parse_command(body, ctx);
    EXPECT_FALSE(p.command) << body;
    EXPECT_EQ(p.refusal.status, 400);
    EXPECT_EQ(p.refusal.message, "\"uav\" must be an integer 0..3");
  }
  const auto r = parse_command(json{{"kind", "kill_place"}, {"region", 2}}, ctx);
  EXPECT_EQ(r.refusal.status, 400);
  EXPECT_EQ(r.refusal.message, "\"region\" must be an integer 0..1");
  auto lock = ctx;
  lock.lockstep = true;
  const auto p = parse_command(json{{"kind", "restart_uav"}, {"uav", 1}}, lock);
  EXPECT_FALSE(p.command);
  EXPECT_EQ(p.refusal.status, 409);
  EXPECT_EQ(p.what, "restart uav 1");
}

TEST(ConsoleCommands, ObstaclesMustFitTheMapAndCoverNoUav) {
  const auto ctx = ctx20x10();
  auto p = parse_command(json{{"kind", "obstacle"}, {"x0", 10}, {"y0", 5}, {"w", 3}, {"h", 2}}, ctx);
  ASSERT_TRUE(p.command);
  EXPECT_EQ(p.what, "obstacle at (10,5) 3x2");
  const auto m = swarm_command(*p.command);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->kind, static_cast<uint8_t>(core::CommandKind::Obstacle));
  EXPECT_EQ(m->x, 10);
  EXPECT_EQ(m->w, 3);
  EXPECT_EQ(m->h, 2);
  // Partly outside is allowed (clipped by the map), wholly outside is not.
  EXPECT_TRUE(parse_command(json{{"kind", "obstacle"}, {"x0", -2}, {"y0", 8}, {"w", 3}, {"h", 3}}, ctx).command);
  p = parse_command(json{{"kind", "obstacle"}, {"x0", 20}, {"y0", 0}, {"w", 1}, {"h", 1}}, ctx);
  EXPECT_EQ(p.refusal.message, "the obstacle lies outside the map");
  // Too large, empty, missing a field, or a huge coordinate.
  for (const json& body : {json{{"kind", "obstacle"}, {"x0", 0}, {"y0", 0}, {"w", 21}, {"h", 1}},
                           json{{"kind", "obstacle"}, {"x0", 0}, {"y0", 0}, {"w", 0}, {"h", 1}},
                           json{{"kind", "obstacle"}, {"x0", 0}, {"w", 1}, {"h", 1}},
                           json{{"kind", "obstacle"}, {"x0", int64_t{1} << 40}, {"y0", 0}, {"w", 1}, {"h", 1}}}) {
    const auto q = parse_command(body, ctx);
    EXPECT_FALSE(q.command) << body;
    EXPECT_EQ(q.refusal.status, 400) << body;
  }
  p = parse_command(json{{"kind", "obstacle"}, {"x0", 2}, {"y0", 2}, {"w", 3}, {"h", 3}}, ctx);
  EXPECT_FALSE(p.command);
  EXPECT_EQ(p.refusal.message, "the obstacle would cover uav 2; place it beside the UAV");
}

TEST(ConsoleCommands, TargetsMustBeFreeCellsInsideTheMap) {
  const auto ctx = ctx20x10();
  auto p = parse_command(json{{"kind", "target"}, {"x", 19}, {"y", 9}}, ctx);
  ASSERT_TRUE(p.command);
  EXPECT_EQ(p.command->cell.x, 19);
  EXPECT_EQ(p.what, "target at (19,9)");
  EXPECT_EQ(swarm_command(*p.command)->kind, static_cast<uint8_t>(core::CommandKind::Target));
  EXPECT_EQ(parse_command(json{{"kind", "target"}, {"x", 20}, {"y", 0}}, ctx).refusal.status, 400);
  EXPECT_EQ(parse_command(json{{"kind", "target"}, {"x", 1.5}, {"y", 0}}, ctx).refusal.status, 400);
  p = parse_command(json{{"kind", "target"}, {"x", 7}, {"y", 7}}, ctx);
  EXPECT_EQ(p.refusal.message, "that cell is an obstacle");
}

TEST(ConsoleCommands, NumbersBeyond32BitsAreRefusedNotWrapped) {
  const auto ctx = ctx20x10();
  // 2^32 + 3 narrowed to 32 bits would be 3, a cell inside the map.
  const auto big = json::parse(R"({"kind":"target","x":4294967299,"y":1})");
  auto p = parse_command(big, ctx);
  EXPECT_FALSE(p.command);
  EXPECT_EQ(p.refusal.status, 400);
  p = parse_command(json::parse(R"({"kind":"kill_uav","uav":4294967297})"), ctx);
  EXPECT_FALSE(p.command);
  EXPECT_EQ(p.refusal.status, 400);
  // Above 2^63 - 1 JSON keeps the number unsigned; read as int64 it would be
  // -1, and an obstacle at x0 = -1, 3 wide, lies partly inside the map (the
  // guard: that is what the wrap gives, and such an obstacle is accepted).
  const auto huge = json::parse(R"({"kind":"obstacle","x0":18446744073709551615,"y0":0,"w":3,"h":1})");
  ASSERT_EQ(huge["x0"].get<int64_t>(), -1);
  ASSERT_TRUE(parse_command(json{{"kind", "obstacle"}, {"x0", -1}, {"y0", 0}, {"w", 3}, {"h", 1}}, ctx).command);
  p = parse_command(huge, ctx);
  EXPECT_FALSE(p.command);
  EXPECT_EQ(p.refusal.status, 400);
  EXPECT_FALSE(parse_command(json::parse(R"({"kind":"target","x":9223372036854775808,"y":0})"), ctx).command);
  EXPECT_FALSE(parse_command(json::parse(R"({"kind":"kill_place","region":18446744073709551616})"), ctx).command);
}

TEST(ConsoleCommands, UnknownKindsAndMissingTokensAreRefusedAndNamed) {
  const auto ctx = ctx20x10();
  auto p = parse_command(json{{"kind", "unauthorised"}}, ctx);
  EXPECT_EQ(p.refusal.status, 401);
  EXPECT_EQ(p.what, "command without a valid token");
  p = parse_command(json{{"kind", "fly_home"}}, ctx);
  EXPECT_EQ(p.refusal.status, 400);
  EXPECT_NE(p.refusal.message.find("unknown kind 'fly_home'"), std::string::npos);
  p = parse_command(json::array({1, 2}), ctx);
  EXPECT_EQ(p.refusal.status, 400);
  EXPECT_EQ(p.what, "(no kind)");
}

}  // namespace
}  // namespace pheromesh::console
