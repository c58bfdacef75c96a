// Overrides (`--set PATH=VALUE`, `--uavs N`, ...): one field of the parsed
// scenario changed by its textproto path, then validated like the file
// (core::load_scenario with overrides; the generic setter of
// common/core/src/scenario/field_override.hpp; the CLI's flags in
// cli/scenario_overrides.hpp).
#include <google/protobuf/descriptor.pb.h>
#include <google/protobuf/wrappers.pb.h>
#include <gtest/gtest.h>

#include <string>

#include "../../common/core/src/scenario/field_override.hpp"
#include "cli/scenario_overrides.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/scenario_limits.hpp"
#include "pheromesh/liu/policy.hpp"
#include "pheromesh/shao/policy.hpp"

namespace pheromesh {
namespace {

using core::ScenarioOverrides;

std::string scenario_file(const std::string& name) {
  return std::string(PHEROMESH_SOURCE_DIR) + "/scenarios/" + name + ".textproto";
}

// The overrides of `--set` arguments.
ScenarioOverrides sets(std::initializer_list<const char*> args) {
  ScenarioOverrides out;
  for (const char* a : args) {
    auto o = core::parse_override(a);
    EXPECT_TRUE(o.ok()) << o.error().message;
    if (o) out.push_back(o.value());
  }
  return out;
}

core::Result<core::ScenarioConfig> small_test(std::initializer_list<const char*> args) {
  return core::load_scenario(scenario_file("small-test"), core::ScenarioLimits{}, sets(args));
}

std::string error_of(const core::Result<core::ScenarioConfig>& r) {
  EXPECT_FALSE(r.ok()) << "accepted";
  return r.ok() ? std::string() : r.error().message;
}

TEST(ScenarioOverrides, ANestedRealAndAnIntegerAreSetAndRecorded) {
  auto s = small_test({"shao.aco.alpha=2", "swarm.uavs=2"});
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(s->aco.alpha, 2.0);
  EXPECT_EQ(s->uavs, 2U);
  EXPECT_EQ(s->aco.beta, 1.0);  // the file's, untouched
  ASSERT_EQ(s->overrides.size(), 2U);
  EXPECT_EQ(s->overrides[0].source, "--set shao.aco.alpha=2");
  // The text handed to processes and to patch_scenario is the changed one.
  auto again = core::parse_scenario(s->source_text, "again", core::ScenarioLimits{});
  ASSERT_TRUE(again.ok()) << again.error().message << "\n" << s->source_text;
  EXPECT_EQ(again->uavs, 2U);
  EXPECT_EQ(again->aco.alpha, 2.0);
  EXPECT_EQ(s->source_text.rfind("# ", 0), 0U) << s->source_text;
}

TEST(ScenarioOverrides, AnOmittedMessageIsCreatedAndTheLastOverrideOfAFieldWins) {
  auto s = small_test({"run.seed=9", "run.seed=11", "run.standby=true"});
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(s->seed, 11U);
  EXPECT_TRUE(s->standby);
}

TEST(ScenarioOverrides, ABoolTakesTheTextFormatSpellingsAndRefusesOthers) {
  EXPECT_TRUE(small_test({"run.standby=1"})->standby);
  EXPECT_FALSE(small_test({"run.standby=false"})->standby);
  EXPECT_EQ(error_of(small_test({"run.standby=yes"})),
            "--set run.standby=yes: 'yes' is not true or false (run.standby is bool)");
}

TEST(ScenarioOverrides, AMemberOfThePolicyOneofIsSetAndAnotherMemberIsRefused) {
  auto nav = small_test({"policy.shao_search.search=frontier"});
  ASSERT_TRUE(nav.ok()) << nav.error().message;
  EXPECT_EQ(nav->config_of<core::ShaoSearchConfig>().route, core::ShaoRoute::Frontier);

  // Without a policy block the scenario runs the Shao search: not switched
  // to another policy by an override either.
  EXPECT_EQ(error_of(small_test({"policy.liu.p_detection=0.5"})),
            "--set policy.liu.p_detection=0.5: the scenario's policy is shao_search (the file chooses none: the "
            "default); an override does not switch the policy to liu (change it in the file)");

  auto liu = core::load_scenario(scenario_file("liu2022-small"), core::ScenarioLimits{},
                                 sets({"policy.liu.p_detection=0.5", "policy.liu.release_confirmed_cells=false"}));
  ASSERT_TRUE(liu.ok()) << liu.error().message;
  EXPECT_EQ(liu->config_of<core::LiuConfig>().params.p_detection, 0.5);
  EXPECT_FALSE(liu->config_of<core::LiuConfig>().release_confirmed_cells);

  const std::string e = error_of(
      core::load_scenario(scenario_file("liu2022-small"), core::ScenarioLimits{}, sets({"policy.duan.alpha=2"})));
  EXPECT_EQ(e,
            "--set policy.duan.alpha=2: policy.duan: policy.duan and policy.liu are members of the oneof "
            "policy.kind, and policy.liu is set; an override does not switch a oneof to another member (change it "
            "in the file)");
}

TEST(ScenarioOverrides, AnUnknownComponentNamesItAndTheFieldsAtItsLevel) {
  EXPECT_EQ(error_of(small_test({"swarm.uav=20"})),
            "--set swarm.uav=20: 'uav' is not a field of swarm (Swarm); its fields: uavs, start_area");
  EXPECT_EQ(error_of(small_test({"swarms.uavs=20"})),
            "--set swarms.uavs=20: 'swarms' is not a field of the scenario; its fields: name, map, swarm, run, shao, "
            "policy, fault, geo");
  EXPECT_NE(error_of(small_test({"swarm..uavs=2"})).find("is not a field path"), std::string::npos);
}

TEST(ScenarioOverrides, AValueThatDoesNotParseForTheFieldsTypeSaysSo) {
  EXPECT_EQ(error_of(small_test({"swarm.uavs=abc"})),
            "--set swarm.uavs=abc: 'abc' is not an integer (swarm.uavs is int32)");
  EXPECT_EQ(error_of(small_test({"swarm.uavs=2.5"})),
            "--set swarm.uavs=2.5: '2.5' is not an integer (swarm.uavs is int32)");
  EXPECT_EQ(error_of(small_test({"swarm.uavs=3000000000"})),
            "--set swarm.uavs=3000000000: '3000000000' is out of range (swarm.uavs is int32)");
  EXPECT_EQ(error_of(small_test({"run.seed=-1"})),
            "--set run.seed=-1: '-1' is not a non-negative integer (run.seed is uint64)");
  EXPECT_EQ(error_of(small_test({"shao.aco.alpha=two"})),
            "--set shao.aco.alpha=two: 'two' is not a number (shao.aco.alpha is double)");
}

TEST(ScenarioOverrides, APathThatTreatsAValueAsAMessageOrAMessageAsAValueIsRefused) {
  EXPECT_EQ(error_of(small_test({"swarm.uavs.x=1"})),
            "--set swarm.uavs.x=1: swarm.uavs is int32, not a message: nothing inside it to set ('x')");
  EXPECT_EQ(error_of(small_test({"swarm.start_area=3"})),
            "--set swarm.start_area=3: swarm.start_area is a message (Rect), not a value: set one of its fields, "
            "e.g. swarm.start_area.x; its fields: x, y, w, h");
}

TEST(ScenarioOverrides, ARepeatedFieldNeedsTheIndexOfAnEntryThatExists) {
  EXPECT_EQ(error_of(small_test({"map.targets.x=3"})),
            "--set map.targets.x=3: map.targets is a repeated field (3 entries): name one entry by its index, e.g. "
            "map.targets[0].x; an override changes an entry, it does not add or remove one");
  EXPECT_EQ(error_of(small_test({"map.targets[3].x=3"})),
            "--set map.targets[3].x=3: map.targets[3]: no such entry, map.targets has 3 entries (0..2); an override "
            "changes an entry, it does not add one");
  EXPECT_EQ(error_of(small_test({"swarm[0].uavs=3"})),
            "--set swarm[0].uavs=3: swarm is not a repeated field: leave out [0]");
  auto s = small_test({"map.targets[2].x=20"});
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(s->targets[2].x, 20);
}

TEST(ScenarioOverrides, AnOverriddenValueIsValidatedLikeTheFileAndTheErrorNamesTheOverride) {
  EXPECT_EQ(error_of(small_test({"swarm.uavs=0"})),
            "--set swarm.uavs=0: field 'swarm.uavs': must be between 1 and 5000 (got 0)");
  // A check of a whole entry (not the field set) is reported at the entry's
  // line in the file, and the overrides are named after it.
  const std::string on_obstacle = error_of(small_test({"map.targets[0].x=10", "map.targets[0].y=6"}));
  EXPECT_NE(on_obstacle.find("small-test.textproto:16:3: field 'map.targets[0]': lies on obstacle map.obstacles[0]"),
            std::string::npos)
      << on_obstacle;
  // 50 UAVs do not fit small-test's 4 x 4 start area: the override asked for
  // them, so the error names it (and the start area's line in the file).
  EXPECT_EQ(error_of(small_test({"swarm.uavs=50"})),
            "--set swarm.uavs=50: field 'swarm.uavs': the start area holds 16 UAVs (its free, non-obstacle cells; "
            "swarm.start_area at " + scenario_file("small-test") + ":22), fewer than 50: give at most 16 or a larger "
            "swarm.start_area");
  // Both changed: the start area's own check, at the file's line, with the
  // overrides named after it.
  const std::string both = error_of(small_test({"swarm.uavs=50", "swarm.start_area.w=5"}));
  EXPECT_NE(both.find("field 'swarm.start_area': has 20 free (non-obstacle) cells, fewer than swarm.uavs = 50"),
            std::string::npos)
      << both;
  // The limits of scenario_limits.hpp too.
  core::ScenarioLimits few;
  few.max_processes = 10;
  const auto over = core::load_scenario(scenario_file("small-test"), few, sets({"swarm.uavs=6"}));
  EXPECT_NE(error_of(over).find("--set swarm.uavs=6: field 'swarm.uavs': the swarm needs 11 processes"),
            std::string::npos)
      << error_of(over);
}

TEST(ScenarioOverrides, APatchOfTheProgramDoesNotUndoTheUsersOverride) {
  auto s = small_test({"shao.aco.alpha=2"});
  ASSERT_TRUE(s.ok()) << s.error().message;
  auto patched = core::patch_scenario(s.value(), "shao { aco { alpha: 3 beta: 2 } }", "patched");
  ASSERT_TRUE(patched.ok()) << patched.error().message;
  EXPECT_EQ(patched->aco.alpha, 2.0);
  EXPECT_EQ(patched->aco.beta, 2.0);
  EXPECT_EQ(patched->overrides.size(), 1U);
}

TEST(ScenarioOverrides, ASetWithoutPathOrEqualsSignShowsTheForm) {
  EXPECT_EQ(core::parse_override("swarm.uavs").error().message,
            "--set swarm.uavs: expected PATH=VALUE, a field path of the scenario and its value, e.g. --set "
            "swarm.uavs=20 or --set shao.aco.alpha=2");
  EXPECT_FALSE(core::parse_override("=3").ok());
  const auto o = core::parse_override("name=a=b");
  ASSERT_TRUE(o.ok());
  EXPECT_EQ(o->path, "name");
  EXPECT_EQ(o->value, "a=b");
}

// The setter is generic: fields scenario.proto does not have (an enum, a
// float) work the same way.
TEST(FieldOverride, AnEnumIsSetByNameOrNumberAndAnUnknownNameListsTheValues) {
  google::protobuf::FieldDescriptorProto m;
  auto by_name = core::field_override::set_field(m, "type", "TYPE_STRING", "the message");
  ASSERT_TRUE(by_name.ok()) << by_name.error().message;
  EXPECT_EQ(m.type(), google::protobuf::FieldDescriptorProto::TYPE_STRING);
  ASSERT_TRUE(core::field_override::set_field(m, "label", "3", "the message").ok());
  EXPECT_EQ(m.label(), google::protobuf::FieldDescriptorProto::LABEL_REPEATED);
  const auto bad = core::field_override::set_field(m, "label", "LABEL_MAYBE", "the message");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message,
            "'LABEL_MAYBE' is not a value of enum Label (label is enum Label); its values: LABEL_OPTIONAL, "
            "LABEL_REQUIRED, LABEL_REPEATED");
  ASSERT_TRUE(core::field_override::set_field(m, "options.packed", "true", "the message").ok());
  EXPECT_TRUE(m.options().packed());
}

TEST(FieldOverride, AFloatIsSetAndOneBeyondItsRangeIsRefused) {
  google::protobuf::FloatValue f;
  ASSERT_TRUE(core::field_override::set_field(f, "value", "2.5", "the message").ok());
  EXPECT_EQ(f.value(), 2.5F);
  const auto big = core::field_override::set_field(f, "value", "1e39", "the message");
  ASSERT_FALSE(big.ok());
  EXPECT_EQ(big.error().message, "'1e39' is out of range (value is float)");
}

// --- the CLI's flags ---------------------------------------------------------

TEST(OverrideFlags, FieldFlagsAreOverridesOfTheirFieldsAndAreValidatedLikeTheFile) {
  cli::OverrideFlags f;
  f.ticks = "0";
  EXPECT_EQ(error_of(cli::load_overridden(scenario_file("small-test"), f)),
            "--ticks 0: field 'run.ticks': must be between 1 and 4294967295 (got 0)");
  f.ticks.reset();
  f.uavs = "0";
  EXPECT_EQ(error_of(cli::load_overridden(scenario_file("small-test"), f)),
            "--uavs 0: field 'swarm.uavs': must be between 1 and 5000 (got 0)");
  f.uavs = "50";
  EXPECT_NE(error_of(cli::load_overridden(scenario_file("small-test"), f))
                .find("--uavs 50: field 'swarm.uavs': the start area holds 16 UAVs"),
            std::string::npos);
  f.uavs = "3";
  f.seed = "0";
  f.standby = true;
  auto s = cli::load_overridden(scenario_file("small-test"), f);
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(s->uavs, 3U);
  EXPECT_EQ(s->seed, 0U);  // as given: 0 no longer means "the scenario's"
  EXPECT_TRUE(s->standby);
  EXPECT_EQ(cli::describe_override(s->overrides[0]), "--uavs 3 (swarm.uavs=3)");
}

TEST(OverrideFlags, AFieldSetByAFlagAndBySetIsRefused) {
  cli::OverrideFlags f;
  f.uavs = "3";
  f.set = {"swarm.uavs=4"};
  EXPECT_EQ(cli::overrides_of(f).error().message,
            "--uavs 3 and --set swarm.uavs=4 both set swarm.uavs; give one of them");
}

TEST(OverrideFlags, DurationBecomesTicksAtTheRateTheOverridesLeave) {
  cli::OverrideFlags f;
  f.duration_s = 2.01;
  auto s = cli::load_overridden(scenario_file("small-test"), f);
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(s->ticks, 101U);  // ceil(2.01 s x 50 Hz)
  f.rate = "10";
  EXPECT_EQ(cli::load_overridden(scenario_file("small-test"), f)->ticks, 21U);
  f.duration_s = 0;
  EXPECT_EQ(error_of(cli::load_overridden(scenario_file("small-test"), f)),
            "--duration 0: must be a number of seconds > 0");
}

}  // namespace
}  // namespace pheromesh
