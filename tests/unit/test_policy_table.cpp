// The policy table (pheromesh/core/policy_table.hpp, core/src/policy/policy_table.cpp):
// one entry per member of the scenario's policy oneof, and everything that
// differs per policy reached through the entry.
#include "pheromesh/core/policy_table.hpp"

#include <google/protobuf/descriptor.h>
#include <gtest/gtest.h>

#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/world.hpp"
#include "pheromesh/shao/policy.hpp"
#include "unit_support.hpp"

namespace pheromesh::core {
namespace {

using test::source_path;

ScenarioConfig shipped(const std::string& name) {
  auto r = load_scenario(source_path("scenarios/" + name + ".textproto"));
  if (!r) throw std::runtime_error(r.error().message);
  return r.value();
}

// The members of `oneof kind` of pheromesh.scenario.Policy (scenario.proto).
std::set<std::string> policy_members() {
  const auto* policy =
      google::protobuf::DescriptorPool::generated_pool()->FindMessageTypeByName("pheromesh.scenario.Policy");
  if (policy == nullptr || policy->FindOneofByName("kind") == nullptr) return {};
  std::set<std::string> names;
  const auto* kind = policy->FindOneofByName("kind");
  // `plugin` names a library, whose entry the loader adds (test_policy_plugin.cpp);
  // `python` a Python class, whose entry the Python hook adds (tests/pypolicy/).
  for (int i = 0; i < kind->field_count(); ++i) {
    const std::string& name = kind->field(i)->name();
    if (name != "plugin" && name != "python") names.insert(name);
  }
  return names;
}

// One shipped scenario per built-in policy.
const std::vector<std::pair<std::string, std::string>>& scenario_of_each_policy() {
  static const std::vector<std::pair<std::string, std::string>> kScenarios{
      {"shao_search", "small-test"}, {"shao_navigation", "small-navigation"}, {"liu", "liu2022-small"},
      {"shostak", "shostak-small"},  {"ravankar", "ravankar2016-small"},      {"duan", "duan2009-small"},
  };
  return kScenarios;
}

TEST(PolicyTable, HasOneEntryForEachMemberOfTheScenarioPolicyOneof) {
  const std::set<std::string> members = policy_members();
  ASSERT_FALSE(members.empty()) << "pheromesh.scenario.Policy.kind not found in the generated pool";
  std::set<std::string> entries;
  for (const PolicyEntry* e : policy_table()) {
    EXPECT_TRUE(entries.insert(std::string(e->name)).second) << "two entries named " << e->name;
  }
  EXPECT_EQ(entries, members);
  for (const std::string& m : members) EXPECT_NE(find_policy(m), nullptr) << m;
}

TEST(PolicyTable, EveryEntryHasAParserTraitsAndBothFactories) {
  for (const PolicyEntry* e : policy_table()) {
    EXPECT_NE(e->parse, nullptr) << e->name;
    EXPECT_NE(e->traits, nullptr) << e->name;
    EXPECT_NE(e->make_uav, nullptr) << e->name;
    EXPECT_NE(e->make_place, nullptr) << e->name;
  }
}

TEST(PolicyTable, FindsNoEntryForANameThatIsNotInIt) {
  EXPECT_EQ(find_policy("shao"), nullptr);
  EXPECT_EQ(find_policy(""), nullptr);
  EXPECT_EQ(find_policy("liu "), nullptr);
  ASSERT_NE(find_policy("liu"), nullptr);
  EXPECT_EQ(find_policy("liu")->name, "liu");
}

TEST(PolicyTable, AScenarioWithoutAPolicyRunsTheDefaultEntryWithoutAConfig) {
  for (const std::string text : {"map { width: 20 height: 20 }", "map { width: 20 height: 20 } policy { }"}) {
    auto r = parse_scenario(text, "t.textproto");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->policy, kDefaultPolicy) << text;
    EXPECT_EQ(r->policy_config, nullptr) << text;
    ASSERT_NE(find_policy(r->policy), nullptr);
    EXPECT_EQ(&policy_entry(r.value()), find_policy(kDefaultPolicy));
  }
}

TEST(PolicyTable, EachShippedScenarioRunsTheEntryItsPolicyMemberNames) {
  for (const auto& [policy, file] : scenario_of_each_policy()) {
    const ScenarioConfig s = shipped(file);
    EXPECT_EQ(s.policy, policy) << file;
    EXPECT_EQ(policy_entry(s).name, policy) << file;
    if (s.policy_config != nullptr) {
      EXPECT_EQ(s.policy_config->policy(), policy) << file;
    }
  }
}

// The three policies that broadcast before the table (the leader's state,
// Shao 2020 Sec. 5; "target found", Shostak 2024 Sec. 5; the ETA intervals,
// Duan 2009 eq. (4)) still do, and only they.
TEST(PolicyTable, TraitsTakeBroadcastsFromTheEntry) {
  const std::set<std::string> broadcasting{"shao_navigation", "shostak", "duan"};
  for (const auto& [policy, file] : scenario_of_each_policy()) {
    const ScenarioConfig s = shipped(file);
    const PolicyTraits t = policy_traits(s);
    EXPECT_EQ(t.broadcasts, policy_entry(s).broadcasts) << policy;
    EXPECT_EQ(t.broadcasts, broadcasting.count(policy) == 1) << policy;
    EXPECT_EQ(t.layer_ranges.size(), t.layers.size()) << policy;
    EXPECT_FALSE(t.layers.empty()) << policy;
  }
}

TEST(PolicyTable, TheEntryBuildsTheUavPolicyAndPlaceModelOfItsScenario) {
  for (const auto& [policy, file] : scenario_of_each_policy()) {
    const ScenarioConfig s = shipped(file);
    const MapGeometry geo = s.geometry();
    const World world(geo, s.obstacles, s.targets);
    const auto uav = make_uav_policy(s, geo, world, 0);
    ASSERT_NE(uav, nullptr) << policy;
    const PolicyTraits t = policy_traits(s);
    EXPECT_EQ(uav->cell(), uav_start(s, t, 0)) << policy;
    EXPECT_NE(make_place_model(s, geo, 0), nullptr) << policy;
  }
}

TEST(PolicyTable, AProgramThatSetsAPolicyWithoutAnEntryGetsAnErrorNamingTheTable) {
  ScenarioConfig s = shipped("small-test");
  s.policy = "shao_serch";
  try {
    (void)policy_traits(s);
    FAIL() << "policy_traits accepted a policy without an entry";
  } catch (const std::logic_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'shao_serch'"), std::string::npos) << what;
    EXPECT_NE(what.find(policy_names()), std::string::npos) << what;
  }
  EXPECT_THROW((void)field_summary(s, [](int, Cell) { return 0.0F; }), std::logic_error);
}

// Shao's `shao { layers aco }` moved into the Shao room; it is still read and
// checked in every scenario, whatever its policy, and before the policy's
// own fields (Shao navigation copies the λ of shao.aco).
TEST(PolicyTable, ShaoFieldsAreCheckedInAScenarioOfAnotherPolicy) {
  const std::string text =
      "map { width: 20 height: 20 }\n"
      "shao { layers { e_tau: 5 } }\n"
      "policy { liu { } }\n";
  auto r = parse_scenario(text, "liu.textproto");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("liu.textproto:2:17: field 'shao.layers.e_tau': must be in [0, 1)"),
            std::string::npos)
      << r.error().message;
}

TEST(PolicyTable, ShaoNavigationReadsTheLambdasOfShaoAco) {
  const std::string text =
      "map { width: 20 height: 20 }\n"
      "shao { aco { lambda_path: 0.7 } }\n"
      "policy { shao_navigation { region_centre { x: 10 y: 10 } } }\n";
  auto r = parse_scenario(text, "nav.textproto");
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->policy, "shao_navigation");
  EXPECT_DOUBLE_EQ(r->aco.lambda_path, 0.7);
  EXPECT_DOUBLE_EQ(r->config_of<ShaoNavigationConfig>().params.lambda_path, 0.7);
}

TEST(PolicyTable, APolicyThatSaysItReadsNoNeighboursStepsTheSameWithoutThem) {
  // PolicyTraits::reads_neighbours false lets the place agents and the
  // simulator leave the neighbours out of its views: two UAVs of the same
  // policy and id, one shown five neighbours around it every tick and one
  // none, must act the same for 40 ticks.
  std::set<std::string> reading;
  for (const auto& [policy, scenario] : scenario_of_each_policy()) {
    const ScenarioConfig s = shipped(scenario);
    const PolicyTraits traits = policy_traits(s);
    if (traits.reads_neighbours) {
      reading.insert(policy);
      continue;
    }
    const MapGeometry geo = s.geometry();
    const World world(geo, s.obstacles, s.targets);
    const PolicyEntry& entry = policy_entry(s);
    auto shown = entry.make_uav(s, geo, world, 0);
    auto alone = entry.make_uav(s, geo, world, 0);
    const TileCache tiles(geo, static_cast<int>(traits.layers.size()));
    UavActions a, b;
    for (uint32_t tick = 0; tick < 40; ++tick) {
      std::vector<UavStateMsg> around;
      const Cell c = shown->cell();
      for (uint32_t n = 1; n <= 5; ++n) {
        around.push_back(test::state_at(n, tick, std::clamp(c.x + static_cast<int32_t>(n) - 3, 0, s.width - 1),
                                        std::clamp(c.y + 1, 0, s.height - 1)));
      }
      a.clear();
      b.clear();
      shown->step(UavView{tick, &tiles, around, {}}, a);
      alone->step(UavView{tick, &tiles, {}, {}}, b);
      ASSERT_EQ(shown->cell(), alone->cell()) << policy << " tick " << tick;
      EXPECT_EQ(a.state.x, b.state.x) << policy << " tick " << tick;
      EXPECT_EQ(a.state.y, b.state.y) << policy << " tick " << tick;
      EXPECT_EQ(a.deposits.size(), b.deposits.size()) << policy << " tick " << tick;
      EXPECT_EQ(a.broadcast.has_value(), b.broadcast.has_value()) << policy << " tick " << tick;
    }
  }
  // The two that steer by their neighbours (Shao 2020 Sec. 5 followers,
  // Liu 2022's nearest neighbours) keep them.
  EXPECT_EQ(reading, (std::set<std::string>{"shao_navigation", "liu"}));
}

}  // namespace
}  // namespace pheromesh::core
