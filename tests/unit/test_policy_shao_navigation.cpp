// Shao 2020 Sec. 5 navigation as a scenario policy: parsing, the leader's
// broadcast, the followers' use of it and of their neighbours, the hold, the
// hand-over to the search, and the beacons of the place agents.
#include <gtest/gtest.h>

#include <string>

#include "pheromesh/core/layers.hpp"
#include "pheromesh/core/place_core.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"
#include "pheromesh/core/uav_core.hpp"
#include "pheromesh/shao/policy.hpp"

using namespace pheromesh::core;

namespace {

const char* kNav = R"(map { width: 20 height: 20 tile_size: 5 regions_x: 2 regions_y: 2
  targets { x: 15 y: 15 } obstacles { x: 2 y: 15 w: 2 h: 2 } }
swarm { uavs: 3 start_area { x: 1 y: 1 w: 2 h: 2 } }
run { ticks: 60 }
shao { layers { e_tau: 0.01 } }
policy { shao_navigation { region_centre { x: 15 y: 15 } hold_ticks: 5 neighbour_gradient: "away" } }
)";

ScenarioConfig nav() {
  auto r = parse_scenario(kNav, "nav.textproto");
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
  return r.value();
}

}  // namespace

TEST(ShaoNavigationPolicy, ParsesTheTable2ParametersAndTheCentre) {
  const ScenarioConfig s = nav();
  EXPECT_EQ(s.policy, "shao_navigation");
  EXPECT_EQ(s.config_of<ShaoNavigationConfig>().region_centre, (Cell{15, 15}));
  EXPECT_EQ(s.config_of<ShaoNavigationConfig>().hold_ticks, 5U);
  EXPECT_EQ(s.config_of<ShaoNavigationConfig>().leader, LeaderPheromones::Vector);
  EXPECT_EQ(s.config_of<ShaoNavigationConfig>().params.neighbour_gradient, NeighbourGradient::AwayFromNeighbour);
  EXPECT_DOUBLE_EQ(s.config_of<ShaoNavigationConfig>().params.rho, 2.0);  // Shao 2020 Table 2
  EXPECT_DOUBLE_EQ(s.config_of<ShaoNavigationConfig>().params.leader_sensor_radius, 5.0);
  EXPECT_EQ(s.policy, ShaoNavigationConfig::kPolicy);
}

TEST(ShaoNavigationPolicy, ReadingsAndTheGradientVariantAreSelectableInTheScenarioFile) {
  const auto r = parse_scenario(
      "map { width: 20 height: 20 }\npolicy { shao_navigation { region_centre { x: 15 y: 15 } leader_pheromones: "
      "\"gradient\" vector_choice: \"projection\" scalar_score: \"max\" scalar_step: \"lattice\" } }\n",
      "r.textproto");
  ASSERT_TRUE(r.ok()) << r.error().message;
  const auto& c = r.value().config_of<ShaoNavigationConfig>();
  EXPECT_EQ(c.leader, LeaderPheromones::Gradient);
  EXPECT_EQ(c.params.vector_choice, VectorSectorChoice::Projection);
  EXPECT_EQ(c.params.scalar_score, ScalarSectorScore::Max);
  EXPECT_EQ(c.params.scalar_step, ScalarLeaderStep::Lattice);
  const auto d = parse_scenario(
      "map { width: 20 height: 20 }\npolicy { shao_navigation { region_centre { x: 15 y: 15 } } }\n", "d.textproto");
  ASSERT_TRUE(d.ok()) << d.error().message;
  const auto& dc = d.value().config_of<ShaoNavigationConfig>();
  EXPECT_EQ(dc.params.vector_choice, VectorSectorChoice::Norm);
  EXPECT_EQ(dc.params.scalar_score, ScalarSectorScore::Mean);
  EXPECT_EQ(dc.params.scalar_step, ScalarLeaderStep::Rho);
  const auto bad = parse_scenario(
      "map { width: 20 height: 20 }\npolicy { shao_navigation { region_centre { x: 15 y: 15 }\n  vector_choice: "
      "\"sum\"\n  scalar_score: \"median\"\n  scalar_step: \"hop\" } }\n",
      "b.textproto");
  ASSERT_FALSE(bad.ok());
  const std::string& e = bad.error().message;
  EXPECT_NE(e.find("b.textproto:3:3: field 'policy.shao_navigation.vector_choice': must be \"norm\" or \"projection\""),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("field 'policy.shao_navigation.scalar_score': must be \"mean\", \"sum\" or \"max\""),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("field 'policy.shao_navigation.scalar_step': must be \"rho\" or \"lattice\""), std::string::npos)
      << e;
}

TEST(ShaoNavigationPolicy, BadValuesNameTheLineAndTheField) {
  const auto r = parse_scenario(
      "map { width: 20 height: 20 }\npolicy { shao_navigation {\n  region_centre { x: 25 y: 3 }\n  leader_pheromones: "
      "\"both\"\n  rho: -1 } }\n",
      "n.textproto");
  ASSERT_FALSE(r.ok());
  const std::string& e = r.error().message;
  EXPECT_NE(e.find("n.textproto:3:19: field 'policy.shao_navigation.region_centre.x': must be between 0 and 19"),
            std::string::npos) << e;
  EXPECT_NE(e.find("n.textproto:4:3: field 'policy.shao_navigation.leader_pheromones': must be \"vector\", \"scalar\", "
                   "\"gradient\" or \"pull\""),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("n.textproto:5:3: field 'policy.shao_navigation.rho': must be > 0"), std::string::npos) << e;
  const auto missing = parse_scenario("map { width: 20 height: 20 }\npolicy { shao_navigation { } }\n", "m.textproto");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find("field 'policy.shao_navigation.region_centre': required field is missing"),
            std::string::npos) << missing.error().message;
}

TEST(ShaoNavigationPolicy, TargetsAndObstaclesEmitFromTheStart) {
  const ScenarioConfig s = nav();
  const MapGeometry geo = s.geometry();
  PlaceCore target_region(s, geo.region_of({15, 15}));
  PlaceCore obstacle_region(s, geo.region_of({2, 15}));
  std::vector<DepositMsg> none;
  std::vector<TargetEventMsg> events;
  for (PlaceCore* p : {&target_region, &obstacle_region}) {
    p->begin_tick(none, 0, events);
    p->finish_tick();
  }
  // Shao 2020 eq. (1) with kτ = 1 and an empty field: τ = (1-Eτ)(1-Gτ)·dτ = 0.99·0.8·1.
  EXPECT_FLOAT_EQ(target_region.value(static_cast<int>(Layer::Target), {15, 15}), 0.99F * 0.8F);
  // Shao 2020 eq. (3) with kε = 1: ε = (1-Eε)(1-Gε)·dε = 0.8·0.8 = 0.64 inside the 2 x 2 block, plus what its
  // three obstacle neighbours diffuse in: (1-Eε)·Gε·Σ s/|N| = 0.8·0.2·3·(1/8).
  EXPECT_FLOAT_EQ(obstacle_region.value(static_cast<int>(Layer::Obstacle), {2, 15}), 0.64F + 0.8F * 0.2F * 3.0F / 8.0F);
  EXPECT_TRUE(events.empty());
}

TEST(ShaoNavigationPolicy, TheLeaderBroadcastsItsStateAndFollowersHoldWithoutIt) {
  const ScenarioConfig s = nav();
  const MapGeometry geo = s.geometry();
  const World world(geo, s.obstacles, s.targets);
  UavCore leader(s, world, 0);
  UavCore follower(s, world, 1);
  UavCore::Output out;
  leader.step(0, out);
  ASSERT_TRUE(out.broadcast.has_value());
  EXPECT_EQ(out.broadcast->kind, static_cast<uint8_t>(BroadcastKind::LeaderState));
  ASSERT_EQ(out.broadcast->values.size(), 5U);
  EXPECT_DOUBLE_EQ(out.broadcast->values[0], leader.cell().x);
  EXPECT_DOUBLE_EQ(out.broadcast->values[4], 0.0);  // not arrived
  EXPECT_EQ(out.state.role, static_cast<uint8_t>(Role::Leader));
  EXPECT_TRUE(out.deposits.empty());  // Shao 2020 Algorithm 2 and Shao 2020 Algorithm 3 deposit nothing
  // A follower that never heard the leader stays where it is, also after the hold.
  const Cell start = follower.cell();
  for (uint32_t k = 0; k <= 8; ++k) follower.step(k, out);
  EXPECT_EQ(follower.cell(), start);
  EXPECT_EQ(out.state.role, static_cast<uint8_t>(Role::Follower));
  EXPECT_FALSE(out.broadcast.has_value());
}

TEST(ShaoNavigationPolicy, SwarmHoldsThenTheLeaderArrivesAndEveryoneSearches) {
  Simulator sim(nav());
  std::vector<double> leader_x;
  sim.run([&](uint32_t) { leader_x.push_back(sim.recorder().uavs().at(0).last.x); });
  // Held during ticks 0..5 (hold_ticks = 5), moving after.
  for (uint32_t k = 1; k <= 5; ++k) EXPECT_EQ(leader_x[k], leader_x[0]) << k;
  ASSERT_TRUE(sim.recorder().leader_arrival_tick().has_value());
  EXPECT_GT(*sim.recorder().leader_arrival_tick(), 5U);
  for (const auto& [id, u] : sim.recorder().uavs()) EXPECT_EQ(u.last.role, static_cast<uint8_t>(Role::Searcher)) << id;
  EXPECT_EQ(sim.recorder().acquisitions().found(), 1U);  // the search found the target after the hand-over
}
