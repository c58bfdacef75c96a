// The Ravankar 2016 policy (ravankar/src/policy.cpp, ravankar/src/scenario.cpp):
// place model, UAV policy and scenario parsing, against hand-worked numbers.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/world.hpp"
#include "pheromesh/ravankar/policy.hpp"
#include "unit_support.hpp"

namespace pheromesh::core {
namespace {

using test::source_path;

// 24 x 24 cells, tiles of 6, 2 x 2 regions (borders at x = 12 and y = 12).
// UAV 0 (leader) starts at (10, 6), UAV 1 (follower) at (11, 6); the route
// goes due east of both, so they start facing +x.
ScenarioConfig scenario(const std::string& policy_extra) {
  const std::string text =
      "map { width: 24 height: 24 tile_size: 6 regions_x: 2 regions_y: 2 }\n"
      "swarm { uavs: 2 start_area { x: 10 y: 6 w: 2 h: 1 } }\n"
      "policy { ravankar {\n"
      "  route { x: 20 y: 6 }\n" +
      policy_extra + "\n} }\n";
  auto r = parse_scenario(text, "t.textproto");
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
  return r.ok() ? std::move(r).value() : ScenarioConfig{};
}

DepositMsg ellipse(Cell c, float xx, float xy, float yy, RegionId region) {
  DepositMsg d;
  d.kind = static_cast<uint8_t>(DepositKind::Ellipse);
  d.cell = c;
  d.spread = {xx, xy, yy};
  d.region = region;
  return d;
}

// --- place model -------------------------------------------------------------

TEST(RavankarPlace, EllipseDepositFollowsEquations12And14) {
  const ScenarioConfig s = scenario("");
  const MapGeometry geo = s.geometry();
  auto place = make_place_model(s, geo, 0);
  std::vector<TargetEventMsg> events;
  // Σ_xy = diag(2, 1): λ1 = 2, λ2 = 1, γ = τ/(λ1·λ2) = 0.2/2 = 0.1 (Ravankar 2016 eq. (12)).
  ASSERT_FALSE(place->apply(ellipse({5, 5}, 2.0F, 0.0F, 1.0F, 0), 0, events));
  // Ravankar 2016 eq. (14) with a_i = λ_i: γ·exp(-(u²/4 + v²/1)).
  EXPECT_NEAR(place->value(0, {5, 5}), 0.1, 1e-7);
  EXPECT_NEAR(place->value(0, {6, 5}), 0.0778800783, 1e-7);  // 0.1·e^(-1/4)
  EXPECT_NEAR(place->value(0, {7, 5}), 0.0367879441, 1e-7);  // 0.1·e^(-1)
  EXPECT_NEAR(place->value(0, {5, 6}), 0.0367879441, 1e-7);  // 0.1·e^(-1)
  EXPECT_NEAR(place->value(0, {9, 5}), 0.0018315639, 1e-7);  // 0.1·e^(-4), 4 m = z_rng
  EXPECT_EQ(place->value(0, {10, 5}), 0.0F);                  // beyond z_rng
  EXPECT_EQ(place->value(0, {8, 8}), 0.0F);                   // √18 > 4 m
}

TEST(RavankarPlace, ZeroUncertaintyDepositsTheCapOnOneCell) {
  const ScenarioConfig s = scenario("");
  const MapGeometry geo = s.geometry();
  auto place = make_place_model(s, geo, 0);
  std::vector<TargetEventMsg> events;
  ASSERT_FALSE(place->apply(ellipse({3, 3}, 0.0F, 0.0F, 0.0F, 0), 0, events));
  ASSERT_FALSE(place->apply(ellipse({3, 3}, 0.0F, 0.0F, 0.0F, 0), 0, events));
  EXPECT_EQ(place->value(0, {3, 3}), 100.0F);  // γ capped at 100, the total capped too
  EXPECT_EQ(place->value(0, {4, 3}), 0.0F);
}

TEST(RavankarPlace, FootprintAcrossARegionBorderIsSplitBetweenThePlaceAgents) {
  const ScenarioConfig s = scenario("");
  const MapGeometry geo = s.geometry();
  const Cell c{11, 5};  // region 0; region 1 starts at x = 12
  const auto regions = geo.regions_within(c, 4.0);
  ASSERT_EQ(regions, (std::vector<RegionId>{0, 1}));
  std::vector<TargetEventMsg> events;
  auto west = make_place_model(s, geo, 0);
  auto east = make_place_model(s, geo, 1);
  ASSERT_FALSE(west->apply(ellipse(c, 2.0F, 0.0F, 1.0F, 0), 0, events));
  ASSERT_FALSE(east->apply(ellipse(c, 2.0F, 0.0F, 1.0F, 1), 0, events));
  EXPECT_NEAR(west->value(0, {11, 5}), 0.1, 1e-7);
  EXPECT_NEAR(west->value(0, {7, 5}), 0.0018315639, 1e-7);
  EXPECT_NEAR(east->value(0, {12, 5}), 0.0778800783, 1e-7);
  EXPECT_NEAR(east->value(0, {13, 5}), 0.0367879441, 1e-7);
  EXPECT_NEAR(east->value(0, {15, 5}), 0.0018315639, 1e-7);
  EXPECT_EQ(east->value(0, {16, 5}), 0.0F);
}

TEST(RavankarPlace, EvaporatesTowardTheAmbientLevelEachTick) {
  ScenarioConfig s = scenario("ambient: 0.05 dt_s: 1 k_per_s: 0.0057");
  const MapGeometry geo = s.geometry();
  auto place = make_place_model(s, geo, 0);
  std::vector<TargetEventMsg> events;
  ASSERT_FALSE(place->apply(ellipse({5, 5}, 2.0F, 0.0F, 1.0F, 0), 0, events));
  const HaloRing ring = place->begin_step(0, events);
  EXPECT_TRUE(ring.target.empty());  // no diffusion
  EXPECT_TRUE(ring.obstacle.empty());
  place->finish_step();
  // Ravankar 2016 eq. (22): 0.05 + (0.1 - 0.05)·e^(-0.0057·1) = 0.0997158107.
  EXPECT_NEAR(place->value(0, {5, 5}), 0.0997158107, 1e-7);
  // Cells at or below P_a are left alone (0 stays 0; 0.0367879 < 0.05 too).
  EXPECT_EQ(place->value(0, {0, 0}), 0.0F);
  EXPECT_NEAR(place->value(0, {7, 5}), 0.0367879441, 1e-7);
}

TEST(RavankarPlace, HalfSecondTicksEvaporateHalfAsMuch) {
  ScenarioConfig s = scenario("dt_s: 0.5");
  const MapGeometry geo = s.geometry();
  auto place = make_place_model(s, geo, 0);
  std::vector<TargetEventMsg> events;
  ASSERT_FALSE(place->apply(ellipse({3, 3}, 0.0F, 0.0F, 0.0F, 0), 0, events));
  place->begin_step(0, events);
  place->finish_step();
  EXPECT_NEAR(place->value(0, {3, 3}), 99.7154057, 1e-4);  // 100·e^(-0.0057·0.5)
}

TEST(RavankarPlace, OtherDepositKindsAreRejectedWithAReason) {
  const ScenarioConfig s = scenario("");
  const MapGeometry geo = s.geometry();
  auto place = make_place_model(s, geo, 0);
  std::vector<TargetEventMsg> events;
  DepositMsg d = ellipse({3, 3}, 0.0F, 0.0F, 0.0F, 0);
  d.kind = static_cast<uint8_t>(DepositKind::PathVisit);
  const auto reason = place->apply(d, 0, events);
  ASSERT_TRUE(reason);
  EXPECT_NE(reason->find("Ravankar"), std::string::npos);
}

TEST(RavankarPolicyTraits, OneLayerAndAViewThatCoversTheSensorRange) {
  const ScenarioConfig s = scenario("sensor_range_m: 3 cell_size_m: 0.5");
  const PolicyTraits t = policy_traits(s);
  EXPECT_EQ(t.layers, std::vector<std::string>{"pheromone"});
  EXPECT_DOUBLE_EQ(t.sensor_radius, 6.0);  // 3 m / 0.5 m
  EXPECT_DOUBLE_EQ(t.view_radius, 7.0);
}

TEST(RavankarFieldSummary, TotalThresholdCountAndMax) {
  const ScenarioConfig s = scenario("delta: 0.1");  // δ·P0 = 10
  const std::map<std::pair<int, int>, float> v{{{1, 1}, 50.0F}, {{2, 1}, 10.0F}, {{3, 1}, 9.5F}};
  const auto summary = field_summary(s, [&](int, Cell c) {
    auto it = v.find({c.x, c.y});
    return it == v.end() ? 0.0F : it->second;
  });
  EXPECT_DOUBLE_EQ(summary.at("pheromone_total"), 69.5);
  EXPECT_DOUBLE_EQ(summary.at("cells_at_or_above_threshold"), 2.0);
  EXPECT_DOUBLE_EQ(summary.at("pheromone_max"), 50.0);
}

// --- follower rule -------------------------------------------------------------

TEST(RavankarFollowerChoice, KeepsToTheStrongestUnvisitedNeighbourAtOrAboveDeltaP0) {
  const RavankarFollowerParams p;  // δ·P0 = 10
  const std::map<std::pair<int, int>, float> v{{{5, 5}, 40.0F}, {{6, 5}, 11.35F}, {{4, 5}, 90.0F}, {{6, 6}, 20.0F}};
  const auto value = [&](Cell c) -> std::optional<float> {
    auto it = v.find({c.x, c.y});
    return it == v.end() ? std::nullopt : std::optional<float>(it->second);
  };
  // (4, 5) was visited (behind the follower): the best of the rest is (6, 6).
  const auto visited = [](Cell c) { return c.x == 4 && c.y == 5; };
  const RavankarChoice ch = ravankar_follower_choice({5, 5}, value, visited, p);
  EXPECT_EQ(ch.mode, RavankarFollowerMode::Following);
  EXPECT_EQ(ch.target, (Cell{6, 6}));
  EXPECT_FLOAT_EQ(static_cast<float>(ch.sensed), 20.0F);
}

TEST(RavankarFollowerChoice, FindsTheTrailAgainTwoCellsAwayAfterOvershootingABend) {
  const RavankarFollowerParams p;
  // The follower stands on (5, 5); the trail went (6, 6) -> (7, 5), and it
  // already passed (6, 6): ring 1 has nothing unvisited above 10, ring 2 has (7, 5).
  const std::map<std::pair<int, int>, float> v{{{5, 5}, 50.0F}, {{6, 6}, 50.0F}, {{7, 5}, 45.0F}, {{3, 5}, 60.0F}};
  const auto value = [&](Cell c) -> std::optional<float> {
    auto it = v.find({c.x, c.y});
    return it == v.end() ? 0.0F : it->second;
  };
  const auto visited = [](Cell c) { return (c.x == 6 && c.y == 6) || (c.x == 3 && c.y == 5); };
  const RavankarChoice ch = ravankar_follower_choice({5, 5}, value, visited, p);
  EXPECT_EQ(ch.mode, RavankarFollowerMode::Following);
  EXPECT_EQ(ch.target, (Cell{7, 5}));
  EXPECT_FLOAT_EQ(static_cast<float>(ch.sensed), 45.0F);
}

TEST(RavankarFollowerChoice, Fig23L11IsFollowedAndL12Rejected) {
  const RavankarFollowerParams p;
  const auto none = [](Cell) { return false; };
  auto only_east = [](float east) {
    return [east](Cell c) -> std::optional<float> { return c.x == 1 && c.y == 0 ? east : 0.0F; };
  };
  EXPECT_EQ(ravankar_follower_choice({0, 0}, only_east(11.35F), none, p).mode, RavankarFollowerMode::Following);
  EXPECT_EQ(ravankar_follower_choice({0, 0}, only_east(8.15F), none, p).mode, RavankarFollowerMode::Exploring);
}

TEST(RavankarFollowerChoice, HoldsOnAFreshTrailEndAndTreatsUnknownCellsAsZero) {
  const RavankarFollowerParams p;
  const auto value = [](Cell c) -> std::optional<float> {
    if (c.x == 0 && c.y == 0) return 30.0F;
    return std::nullopt;  // tiles not received
  };
  const RavankarChoice ch = ravankar_follower_choice({0, 0}, value, [](Cell) { return false; }, p);
  EXPECT_EQ(ch.mode, RavankarFollowerMode::Holding);
  EXPECT_EQ(ch.target, (Cell{0, 0}));
  EXPECT_DOUBLE_EQ(ch.sensed, 30.0);
}

// --- UAV policy ----------------------------------------------------------------

// A tile cache holding `values` (all other cells 0) in every tile of the map.
TileCache cache_with(const MapGeometry& geo, const std::map<std::pair<int, int>, float>& values) {
  TileCache cache(geo, 1);
  for (int32_t ty = 0; ty < geo.tiles_y(); ++ty) {
    for (int32_t tx = 0; tx < geo.tiles_x(); ++tx) {
      const Rect r = geo.tile_rect({tx, ty});
      TileMsg m;
      m.tile = {tx, ty};
      m.width = static_cast<uint16_t>(r.w);
      m.height = static_cast<uint16_t>(r.h);
      for (int32_t y = r.y0; y < r.y0 + r.h; ++y) {
        for (int32_t x = r.x0; x < r.x0 + r.w; ++x) {
          auto it = values.find({x, y});
          m.values.push_back(it == values.end() ? 0.0F : it->second);
        }
      }
      cache.update(m);
    }
  }
  return cache;
}

struct Harness {
  explicit Harness(const std::string& extra) : s(scenario(extra)), geo(s.geometry()), world(geo, {}, {}) {}
  std::unique_ptr<UavPolicy> uav(uint32_t id) { return make_uav_policy(s, geo, world, id); }
  ScenarioConfig s;
  MapGeometry geo;
  World world;
};

UavActions step(UavPolicy& u, uint32_t tick, const TileCache& cache) {
  UavActions out;
  u.step(UavView{tick, &cache, {}, {}}, out);
  return out;
}

TEST(RavankarUav, LeaderDepositsTheCapAtItsStartWithZeroSpreadToEveryRegionInRange) {
  Harness h("");
  auto leader = h.uav(0);
  const TileCache cache(h.geo, 1);
  const UavActions a = step(*leader, 0, cache);
  EXPECT_EQ(a.state.role, static_cast<uint8_t>(Role::Leader));
  EXPECT_DOUBLE_EQ(a.state.x, 10.0);
  EXPECT_DOUBLE_EQ(a.state.y, 6.0);
  // (10, 6) is 2 cells from region 1 (x >= 12), 6 from the regions below.
  ASSERT_EQ(a.deposits.size(), 2U);
  for (std::size_t i = 0; i < a.deposits.size(); ++i) {
    const DepositMsg& d = a.deposits[i];
    EXPECT_EQ(d.region, static_cast<RegionId>(i));
    EXPECT_EQ(d.kind, static_cast<uint8_t>(DepositKind::Ellipse));
    EXPECT_EQ(d.cell, (Cell{10, 6}));
    EXPECT_EQ(d.spread, (std::array<float, 3>{0.0F, 0.0F, 0.0F}));
    EXPECT_EQ(d.amount, 100.0F);  // γ capped, Ravankar 2016 eq. (12)
  }
}

TEST(RavankarUav, LeaderWithoutWheelNoiseFliesHalfAMetrePerTickAlongTheRoute) {
  Harness h("wheel_noise_m2_per_m: 0 leader_speed_mps: 0.5");
  auto leader = h.uav(0);
  const TileCache cache(h.geo, 1);
  step(*leader, 0, cache);
  UavActions a = step(*leader, 1, cache);
  EXPECT_NEAR(a.state.x, 10.5, 1e-12);
  EXPECT_NEAR(a.state.y, 6.0, 1e-12);
  EXPECT_NEAR(a.state.vx, 0.5, 1e-12);
  for (uint32_t t = 2; t <= 20; ++t) a = step(*leader, t, cache);
  EXPECT_NEAR(a.state.x, 20.0, 1e-9);  // the waypoint, reached at tick 20, then stays
  a = step(*leader, 21, cache);
  EXPECT_NEAR(a.state.x, 20.0, 1e-9);
  EXPECT_EQ(a.deposits.front().cell, (Cell{20, 6}));
}

TEST(RavankarUav, WithoutFixesTheLeadersDepositsShrinkAndDriftFromItsTrueCell) {
  Harness h("fix_every_ticks: 0 route { x: 20 y: 20 } route { x: 2 y: 20 }");
  auto leader = h.uav(0);
  const TileCache cache(h.geo, 1);
  double last = 1e9;
  bool drifted = false;
  bool below_threshold = false;
  for (uint32_t t = 0; t <= 100; ++t) {
    const UavActions a = step(*leader, t, cache);
    if (a.deposits.empty()) continue;  // estimate off the map
    const double gamma = a.deposits.front().amount;
    EXPECT_LE(gamma, last * (1.0 + 1e-6)) << "tick " << t;  // Σ only grows without fixes
    last = gamma;
    below_threshold = below_threshold || gamma < 10.0;
    drifted = drifted || !(a.deposits.front().cell == leader->cell());
  }
  EXPECT_TRUE(below_threshold);
  EXPECT_TRUE(drifted);
}

TEST(RavankarUav, FixesEveryTickKeepTheLeaderAtTheCap) {
  Harness h("fix_every_ticks: 1 fix_sigma_m: 0.05");
  auto leader = h.uav(0);
  const TileCache cache(h.geo, 1);
  for (uint32_t t = 0; t <= 20; ++t) {
    const UavActions a = step(*leader, t, cache);
    ASSERT_FALSE(a.deposits.empty());
    EXPECT_FLOAT_EQ(a.deposits.front().amount, 100.0F) << "tick " << t;
  }
}

TEST(RavankarUav, FollowerMovesAtTheTable2SpeedOfTheTrailAhead) {
  // Follower (UAV 1) at (11, 6) facing +x; the trail cell ahead is (12, 6).
  for (const auto& [sensed, expected_x] : std::vector<std::pair<float, double>>{{70.0F, 12.0}, {40.0F, 11.65},
                                                                                 {20.0F, 11.45}, {12.0F, 11.15}}) {
    Harness h("wheel_noise_m2_per_m: 0");
    auto follower = h.uav(1);
    const TileCache cache = cache_with(h.geo, {{{12, 6}, sensed}});
    const UavActions a0 = step(*follower, 0, cache);
    EXPECT_EQ(a0.state.role, static_cast<uint8_t>(Role::Follower));
    EXPECT_TRUE(a0.deposits.empty());  // followers_deposit defaults to false
    const UavActions a = step(*follower, 1, cache);
    EXPECT_NEAR(a.state.x, expected_x, 1e-9) << "sensed " << sensed;
    EXPECT_NEAR(a.state.y, 6.0, 1e-9);
  }
}

TEST(RavankarUav, FollowerRejectsAWeakTrailAndExploresAtItsOwnSpeed) {
  Harness h("wheel_noise_m2_per_m: 0 explore_speed_mps: 0.5");
  auto follower = h.uav(1);
  const TileCache cache = cache_with(h.geo, {{{12, 6}, 8.15F}, {{11, 6}, 8.15F}});
  step(*follower, 0, cache);
  const UavActions a = step(*follower, 1, cache);
  const double moved = std::hypot(a.state.x - 11.0, a.state.y - 6.0);
  // A turn of at most 45° on an arc: chord 0.5·sinc(β/2) >= 0.5·sinc(π/8).
  EXPECT_LE(moved, 0.5 + 1e-12);
  EXPECT_GE(moved, 0.5 * std::sin(M_PI / 8.0) / (M_PI / 8.0) - 1e-12);
}

TEST(RavankarRetreat, RejectHeadingIsTheTrailHeadingOrItsReverse) {
  using M = RavankarConfig::RejectExplore;
  EXPECT_DOUBLE_EQ(ravankar_reject_heading(0.5, M::Onward), 0.5);
  EXPECT_NEAR(ravankar_reject_heading(0.5, M::Retreat), 0.5 + M_PI, 1e-12);
  EXPECT_NEAR(ravankar_reject_heading(4.0, M::Retreat), 4.0 + M_PI - 2.0 * M_PI, 1e-12);  // wrapped to [0, 2π)
}

TEST(RavankarRetreat, AFollowerThatRejectsTheTrailWalksBackAlongItOnwardWalksOn) {
  // The follower at (11, 6) facing +x follows the trail cell (12, 6) at tick 1
  // (70 → 1 m/s: x = 12). Then the trail is gone (all 0): it rejects it and
  // walks at 0.5 m/s. Retreat starts the walk at heading π: after a turn on
  // the spot it heads west; onward keeps heading east (turns of ≤ 45° a tick).
  for (const bool retreat : {false, true}) {
    for (uint64_t seed = 1; seed <= 5; ++seed) {
      Harness h(std::string("wheel_noise_m2_per_m: 0 explore_speed_mps: 0.5") +
                (retreat ? " reject_explore: \"retreat\"" : ""));
      h.s.seed = seed;
      auto follower = h.uav(1);
      const TileCache trail = cache_with(h.geo, {{{12, 6}, 70.0F}});
      const TileCache gone = cache_with(h.geo, {});
      step(*follower, 0, trail);
      EXPECT_NEAR(step(*follower, 1, trail).state.x, 12.0, 1e-9);
      UavActions a;
      for (uint32_t t = 2; t <= 5; ++t) a = step(*follower, t, gone);
      if (retreat) {
        EXPECT_LT(a.state.x, 12.0) << "seed " << seed;
      } else {
        EXPECT_GT(a.state.x, 12.0) << "seed " << seed;
      }
    }
  }
}

TEST(RavankarRetreat, TheDefaultIsOnwardAndOnlyTwoNamesParse) {
  EXPECT_EQ(scenario("").config_of<RavankarConfig>().reject_explore, RavankarConfig::RejectExplore::Onward);
  EXPECT_EQ(scenario("reject_explore: \"retreat\"").config_of<RavankarConfig>().reject_explore,
            RavankarConfig::RejectExplore::Retreat);
  const auto r = parse_scenario(
      "map { width: 24 height: 24 tile_size: 6 }\nswarm { uavs: 2 }\npolicy { ravankar {\n  route { x: 3 y: 3 }\n"
      "  reject_explore: \"back\"\n} }\n",
      "t.textproto");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("t.textproto:5:3:"), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find("policy.ravankar.reject_explore"), std::string::npos) << r.error().message;
}

TEST(RavankarUav, FollowerHoldsAtAFreshTrailEndAndWaitsForItsStartTick) {
  {
    Harness h("wheel_noise_m2_per_m: 0");
    auto follower = h.uav(1);
    const TileCache cache = cache_with(h.geo, {{{11, 6}, 50.0F}});
    step(*follower, 0, cache);
    const UavActions a = step(*follower, 1, cache);
    EXPECT_DOUBLE_EQ(a.state.x, 11.0);
    EXPECT_DOUBLE_EQ(a.state.y, 6.0);
  }
  {
    Harness h("wheel_noise_m2_per_m: 0 follower_delay_ticks: 3");  // follower 0 starts at tick 3
    auto follower = h.uav(1);
    const TileCache cache = cache_with(h.geo, {{{12, 6}, 70.0F}});
    for (uint32_t t = 0; t <= 2; ++t) EXPECT_DOUBLE_EQ(step(*follower, t, cache).state.x, 11.0) << t;
    EXPECT_NEAR(step(*follower, 3, cache).state.x, 12.0, 1e-9);
  }
}

TEST(RavankarUav, FollowersDepositWhenAsked) {
  Harness h("followers_deposit: true");
  auto follower = h.uav(1);
  const TileCache cache(h.geo, 1);
  EXPECT_EQ(step(*follower, 0, cache).deposits.size(), 2U);
}

// --- scenarios -------------------------------------------------------------------

TEST(RavankarScenario, ShippedScenariosLoad) {
  for (const char* f : {"ravankar2016-small", "ravankar2016-corridor", "ravankar2016-fig6-evaporation",
                        "ravankar2016-fig7-evaporation", "ravankar2016-fig8-evaporation"}) {
    const auto r = load_scenario(source_path(std::string("scenarios/") + f + ".textproto"));
    ASSERT_TRUE(r.ok()) << f << ": " << r.error().message;
    EXPECT_EQ(r.value().policy, "ravankar") << f;
  }
  const auto small = load_scenario(source_path("scenarios/ravankar2016-small.textproto"));
  ASSERT_TRUE(small.ok());
  EXPECT_EQ(small.value().geometry().region_count(), 4U);
  EXPECT_EQ(small.value().config_of<RavankarConfig>().route.size(), 4U);
  ASSERT_TRUE(small.value().config_of<RavankarConfig>().fix_area);
  const auto corridor = load_scenario(source_path("scenarios/ravankar2016-corridor.textproto"));
  ASSERT_TRUE(corridor.ok());
  const RavankarConfig& c = corridor.value().config_of<RavankarConfig>();
  EXPECT_DOUBLE_EQ(c.evaporation.k_per_s, 0.0057);
  EXPECT_DOUBLE_EQ(c.follower.delta * c.follower.reference_deposit, 10.0);
  EXPECT_DOUBLE_EQ(c.deposit.tau, 0.2);
}

TEST(RavankarScenario, DefaultsAreThePapersValues) {
  const ScenarioConfig s = scenario("");
  const RavankarConfig& c = s.config_of<RavankarConfig>();
  EXPECT_DOUBLE_EQ(c.deposit.tau, 0.2);
  EXPECT_DOUBLE_EQ(c.deposit.max_deposit, 100.0);
  EXPECT_DOUBLE_EQ(c.follower.reference_deposit, 100.0);
  EXPECT_DOUBLE_EQ(c.follower.delta, 0.1);
  EXPECT_DOUBLE_EQ(c.evaporation.k_per_s, 0.0057);
  EXPECT_DOUBLE_EQ(c.evaporation.ambient, 0.0);
  EXPECT_EQ(c.deposit.axes, RavankarAxes::Eigenvalue);
  EXPECT_EQ(c.deposit.spread, RavankarSpread::Peak);
  EXPECT_EQ(c.leaders, 1U);
}

void expect_error(const std::string& message, const std::string& where, const std::string& field) {
  EXPECT_NE(message.find(where + " field '" + field + "'"), std::string::npos) << message;
}

TEST(RavankarScenario, BadFieldsNameLineAndField) {
  const std::string text =
      "map { width: 24 height: 24 tile_size: 6 }\n"    // 1
      "swarm { uavs: 2 }\n"                            // 2
      "policy { ravankar {\n"                          // 3
      "  route { x: 3 y: 3 }\n"                        // 4
      "  route { x: 30 y: 3 }\n"                       // 5
      "  delta: 0\n"                                   // 6
      "  axes: \"sigma\"\n"                            // 7
      "  leaders: 3\n"                                 // 8
      "  k_per_s: -1\n"                                // 9
      "  fix_area { x: 20 y: 0 w: 10 h: 4 }\n"         // 10
      "} }\n";
  const auto r = parse_scenario(text, "t.textproto");
  ASSERT_FALSE(r.ok());
  const std::string& m = r.error().message;
  expect_error(m, "t.textproto:5:11:", "policy.ravankar.route[1].x");
  expect_error(m, "t.textproto:6:3:", "policy.ravankar.delta");
  expect_error(m, "t.textproto:7:3:", "policy.ravankar.axes");
  expect_error(m, "t.textproto:8:3:", "policy.ravankar.leaders");
  expect_error(m, "t.textproto:9:3:", "policy.ravankar.k_per_s");
  EXPECT_NE(m.find("t.textproto:10:"), std::string::npos) << m;
  EXPECT_NE(m.find("policy.ravankar.fix_area"), std::string::npos) << m;
}

TEST(RavankarScenario, MissingRouteIsRequired) {
  const auto r = parse_scenario("map { width: 10 height: 10 }\npolicy {\n  ravankar { delta: 0.2 }\n}\n", "t.textproto");
  ASSERT_FALSE(r.ok());
  expect_error(r.error().message, "t.textproto:3:3:", "policy.ravankar.route");
  EXPECT_NE(r.error().message.find("required"), std::string::npos) << r.error().message;
}

TEST(RavankarScenario, BadFixtureNamesItsLine) {
  const auto r = load_scenario(source_path("tests/data/bad-ravankar-spread.textproto"));
  ASSERT_FALSE(r.ok());
  expect_error(r.error().message, "bad-ravankar-spread.textproto:9:5:", "policy.ravankar.spread");
  expect_error(r.error().message, "bad-ravankar-spread.textproto:10:5:", "policy.ravankar.dt_s");
}

}  // namespace
}  // namespace pheromesh::core
