// The Shostak GPS-denied stigmergy policy behind the policy interface: the
// place model (Shostak 2024 eq. (1), Shostak 2024 eq. (2) as the place agents run them), the UAV policy
// (frames, dispersal, deposits, detection and broadcast, decisions by
// Shostak 2024 eq. (3), Shostak 2024 eq. (4), Shostak 2024 eq. (5), Shostak 2024 eq. (6), convergence), the field summary, the scenario parser, and a
// run of the Shostak 2024 Sec. 5 scenario measured over seeds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/rng.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"
#include "pheromesh/core/world.hpp"
#include "pheromesh/shostak/model.hpp"
#include "pheromesh/shostak/policy.hpp"
#include "unit_support.hpp"

namespace pheromesh::core {
namespace {

using test::kPi;
constexpr auto kExplored = static_cast<uint8_t>(ShostakLayer::Explored);
constexpr auto kHazard = static_cast<uint8_t>(ShostakLayer::Hazard);
constexpr auto kTarget = static_cast<uint8_t>(ShostakLayer::Target);

// A Shostak scenario of `side` x `side` cells (tiles of 5, 2 x 2 regions)
// with `uavs` UAVs taking off from the row of cells starting at `start`.
ScenarioConfig scenario(int side, uint32_t uavs, Cell start, const std::string& map_extra = "",
                        const std::string& policy = "") {
  const std::string text = "map { width: " + std::to_string(side) + " height: " + std::to_string(side) +
                           " tile_size: 5 regions_x: 2 regions_y: 2 " + map_extra + " }\n" +
                           "swarm { uavs: " + std::to_string(uavs) + " start_area { x: " + std::to_string(start.x) +
                           " y: " + std::to_string(start.y) + " w: " + std::to_string(uavs) + " h: 1 } }\n" +
                           "policy { shostak { " + policy + " } }\n";
  auto r = parse_scenario(text, "t.textproto");
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
  return r.value();
}

// Every tile of every layer, all cells `value`.
void fill_tiles(TileCache& cache, const MapGeometry& geo, float value) {
  for (int32_t ty = 0; ty * geo.tile_size() < geo.height(); ++ty) {
    for (int32_t tx = 0; tx * geo.tile_size() < geo.width(); ++tx) {
      const Rect r = geo.tile_rect({tx, ty});
      for (uint8_t l = 0; l < kShostakLayerCount; ++l) {
        TileMsg m;
        m.layer = l;
        m.tile = {tx, ty};
        m.width = static_cast<uint16_t>(r.w);
        m.height = static_cast<uint16_t>(r.h);
        m.values.assign(static_cast<std::size_t>(r.area()), value);
        cache.update(m);
      }
    }
  }
}

// One UAV policy with its own world and (static) tiles.
struct OneUav {
  ScenarioConfig s;
  MapGeometry geo;
  World world;
  TileCache cache;
  std::unique_ptr<UavPolicy> uav;
  OneUav(ScenarioConfig sc, uint32_t id)
      : s(std::move(sc)), geo(s.geometry()), world(geo, s.obstacles, s.targets), cache(geo, kShostakLayerCount) {
    uav = make_shostak_uav(s, geo, world, id);
    fill_tiles(cache, geo, 0.0F);
  }
  UavActions step(uint32_t tick, std::span<const BroadcastMsg> broadcasts = {}) {
    UavActions out;
    uav->step(UavView{tick, &cache, {}, broadcasts}, out);
    return out;
  }
};

std::vector<DepositMsg> of_layer(const UavActions& a, uint8_t layer) {
  std::vector<DepositMsg> out;
  for (const auto& d : a.deposits) {
    if (d.kind == static_cast<uint8_t>(DepositKind::LayerAdd) && d.layer == layer) out.push_back(d);
  }
  return out;
}

DepositMsg layer_add(uint8_t layer, Cell c, float amount, RegionId region = 0) {
  DepositMsg d;
  d.kind = static_cast<uint8_t>(DepositKind::LayerAdd);
  d.layer = layer;
  d.cell = c;
  d.amount = amount;
  d.region = region;
  return d;
}

// --- place model ---------------------------------------------------------------

TEST(ShostakPlace, DepositsAreCappedAtTenTenAndAHundred) {
  const ScenarioConfig s = scenario(20, 1, {1, 1});
  const MapGeometry geo = s.geometry();
  auto place = make_shostak_place(s, geo, 0);
  std::vector<TargetEventMsg> events;
  // Shostak 2024 eq. (1): min(τ + Δτ, τmax). 12 explored deposits of 1 -> 10.
  for (int k = 0; k < 12; ++k) EXPECT_FALSE(place->apply(layer_add(kExplored, {2, 3}, 1.0F), 0, events));
  EXPECT_FLOAT_EQ(place->value(kExplored, {2, 3}), 10.0F);
  // Shostak 2024 Sec. 4.2: +5 hazard per detection, capped at 10.
  EXPECT_FALSE(place->apply(layer_add(kHazard, {2, 3}, 5.0F), 0, events));
  EXPECT_FLOAT_EQ(place->value(kHazard, {2, 3}), 5.0F);
  for (int k = 0; k < 2; ++k) EXPECT_FALSE(place->apply(layer_add(kHazard, {2, 3}, 5.0F), 0, events));
  EXPECT_FLOAT_EQ(place->value(kHazard, {2, 3}), 10.0F);
  // Shostak 2024 Sec. 5: +100 target, capped at 100.
  EXPECT_FALSE(place->apply(layer_add(kTarget, {4, 4}, 100.0F), 0, events));
  EXPECT_FALSE(place->apply(layer_add(kTarget, {4, 4}, 100.0F), 0, events));
  EXPECT_FLOAT_EQ(place->value(kTarget, {4, 4}), 100.0F);
  EXPECT_FLOAT_EQ(place->value(kExplored, {4, 4}), 0.0F);
  EXPECT_TRUE(events.empty());
}

TEST(ShostakPlace, EachTickEvaporatesByNinetyFivePercentToTheFifthRoot) {
  const ScenarioConfig s = scenario(20, 1, {1, 1});
  const MapGeometry geo = s.geometry();
  auto place = make_shostak_place(s, geo, 3);  // region 3 = cells [10, 20) x [10, 20)
  std::vector<TargetEventMsg> events;
  ASSERT_FALSE(place->apply(layer_add(kExplored, {15, 12}, 10.0F, 3), 0, events));
  ASSERT_FALSE(place->apply(layer_add(kTarget, {15, 12}, 100.0F, 3), 0, events));
  place->begin_step(0, events);
  place->finish_step();
  // Shostak 2024 eq. (2) over dt = 0.2 s: 10·0.95^0.2 = 9.8979378..., 100·0.95^0.2 = 98.979378...
  EXPECT_NEAR(place->value(kExplored, {15, 12}), 9.897937816869885, 1e-5);
  EXPECT_NEAR(place->value(kTarget, {15, 12}), 98.97937816869885, 1e-4);
  for (uint32_t k = 1; k < 70; ++k) {
    place->begin_step(k, events);
    place->finish_step();
  }
  // 70 ticks = 14 s: 10·0.95^14 = 4.8767 (Shostak 2024 Sec. 5: "10 -> 5 in about 14 s").
  EXPECT_NEAR(place->value(kExplored, {15, 12}), 4.876749791155295, 1e-4);
}

TEST(ShostakPlace, HasNoDiffusionAndRefusesOtherDepositKinds) {
  const ScenarioConfig s = scenario(20, 1, {1, 1});
  const MapGeometry geo = s.geometry();
  auto place = make_shostak_place(s, geo, 0);
  std::vector<TargetEventMsg> events;
  const HaloRing ring = place->begin_step(0, events);
  EXPECT_TRUE(ring.target.empty());
  EXPECT_TRUE(ring.obstacle.empty());
  DepositMsg d = layer_add(kExplored, {1, 1}, 1.0F);
  d.kind = static_cast<uint8_t>(DepositKind::PathVisit);
  const auto reason = place->apply(d, 0, events);
  ASSERT_TRUE(reason);
  EXPECT_NE(reason->find("not used by the shostak policy"), std::string::npos) << *reason;
  EXPECT_FLOAT_EQ(place->value(kExplored, {1, 1}), 0.0F);
}

// --- traits and field summary ----------------------------------------------------

TEST(ShostakTraits, ThreeLayersDetectionRadiusAndTheCandidateRingPlusACell) {
  const PolicyTraits t = policy_traits(scenario(20, 1, {1, 1}));
  EXPECT_EQ(t.layers, (std::vector<std::string>{"explored", "hazard", "target"}));
  EXPECT_DOUBLE_EQ(t.sensor_radius, 2.0);  // 10 m / 5 m
  EXPECT_DOUBLE_EQ(t.view_radius, 4.0);    // ceil(15 m / 5 m) + 1
}

TEST(ShostakFieldSummary, CountsExploredHazardAndTargetCells) {
  ScenarioConfig s;  // the summary reads only the map size
  s.policy = "shostak";
  s.width = 4;
  s.height = 4;  // 16 cells
  const FieldLookup value = [](int layer, Cell c) -> float {
    if (layer == kExplored) return c.y == 0 ? static_cast<float>(c.x) : 0.0F;  // 0, 1, 2, 3 on row 0
    if (layer == kHazard) return c.x == 3 && c.y == 3 ? 5.0F : 0.0F;
    return c.x == 1 && c.y == 2 ? 50.0F : 0.0F;
  };
  const auto f = field_summary(s, value);
  EXPECT_DOUBLE_EQ(f.at("explored_cells"), 3.0);
  EXPECT_DOUBLE_EQ(f.at("explored_fraction"), 3.0 / 16.0);
  EXPECT_DOUBLE_EQ(f.at("explored_mean"), 6.0 / 16.0);
  EXPECT_DOUBLE_EQ(f.at("explored_max"), 3.0);
  EXPECT_DOUBLE_EQ(f.at("hazard_cells"), 1.0);
  EXPECT_DOUBLE_EQ(f.at("target_cells"), 1.0);
  EXPECT_DOUBLE_EQ(f.at("target_max"), 50.0);
}

// --- UAV -----------------------------------------------------------------------------

TEST(ShostakUav, TickZeroDepositsOneExploredAtTheTakeOffCell) {
  OneUav u(scenario(20, 1, {12, 3}), 0);
  EXPECT_EQ(u.uav->cell(), (Cell{12, 3}));
  const UavActions a = u.step(0);
  const auto e = of_layer(a, kExplored);
  ASSERT_EQ(e.size(), 1U);
  EXPECT_EQ(e[0].cell, (Cell{12, 3}));
  EXPECT_EQ(e[0].region, 1U);  // cells x >= 10, y < 10
  EXPECT_FLOAT_EQ(e[0].amount, 1.0F);
  EXPECT_EQ(a.deposits.size(), 1U);
  EXPECT_DOUBLE_EQ(a.state.x, 12.0);
  EXPECT_DOUBLE_EQ(a.state.y, 3.0);
  EXPECT_EQ(a.state.role, static_cast<uint8_t>(Role::Searcher));
  EXPECT_FALSE(a.broadcast);
}

TEST(ShostakUav, ThreeUavsDisperseAtZeroOneTwentyAndTwoFortyDegreesAtFiveMetresPerSecond) {
  const ScenarioConfig s = scenario(40, 3, {19, 20});
  for (uint32_t id = 0; id < 3; ++id) {
    OneUav u(s, id);
    UavActions a = u.step(0);
    for (uint32_t k = 1; k <= 10; ++k) {
      a = u.step(k);
      // One explored deposit per 0.2 s tick, Shostak 2024 eq. (1).
      ASSERT_EQ(of_layer(a, kExplored).size(), 1U) << "tick " << k;
    }
    // 10 ticks · 0.2 s · 5 m/s = 10 m = 2 cells along 2π·id/3.
    const double h = 2.0 * kPi * id / 3.0;
    EXPECT_NEAR(a.state.x, 19.0 + id + 2.0 * std::cos(h), 1e-9) << id;
    EXPECT_NEAR(a.state.y, 20.0 + 2.0 * std::sin(h), 1e-9) << id;
    EXPECT_NEAR(a.state.vx, 0.2 * std::cos(h), 1e-9);  // [cell/tick]
    EXPECT_NEAR(a.state.vy, 0.2 * std::sin(h), 1e-9);
    EXPECT_EQ(a.state.heading, heading_of_velocity(a.state.vx, a.state.vy, 0));
  }
}

TEST(ShostakUav, FrameYawTurnsTheLocalDispersalLegAndDepositsFollowInTheMapFrame) {
  // UAV 0 of 1 leaves along local x; its frame is turned by 90°, so it flies
  // along map +y, and it deposits explored at the map cells under it.
  OneUav u(scenario(20, 1, {5, 5}, "", "frame_yaw_deg: 90"), 0);
  UavActions a = u.step(0);
  for (uint32_t k = 1; k <= 15; ++k) a = u.step(k);
  EXPECT_NEAR(a.state.x, 5.0, 1e-9);
  EXPECT_NEAR(a.state.y, 8.0, 1e-9);  // 15 m = 3 cells
  const auto e = of_layer(a, kExplored);
  ASSERT_EQ(e.size(), 1U);
  EXPECT_EQ(e[0].cell, (Cell{5, 8}));
}

TEST(ShostakUav, ObstacleWithinLidarRangeAddsFiveHazardAtTheCurrentCell) {
  // Take-off at the centre of cell (5,5): x = 27.5 m. The obstacle cell (8,5)
  // starts at x = 40 m: 12.5 m away, beyond the 10 m lidar range; flying +x at
  // 1 m per tick the UAV is 10.5 m away at tick 2 and 9.5 m at tick 3, at
  // x = 30.5 m, over cell (6,5).
  OneUav u(scenario(20, 1, {5, 5}, "obstacles { x: 8 y: 5 w: 1 h: 1 }"), 0);
  for (uint32_t k = 0; k <= 2; ++k) EXPECT_TRUE(of_layer(u.step(k), kHazard).empty()) << "tick " << k;
  const UavActions a = u.step(3);
  const auto h = of_layer(a, kHazard);
  ASSERT_EQ(h.size(), 1U);
  EXPECT_EQ(h[0].cell, (Cell{6, 5}));
  EXPECT_FLOAT_EQ(h[0].amount, 5.0F);
}

TEST(ShostakUav, TargetInTheCameraFootprintIsMarkedAndBroadcastOnce) {
  // Target (8,6): centre (42.5, 32.5) m. The UAV flies y = 27.5 m from
  // x = 27.5 m at 1 m per tick: 10.30 m away at tick 6 (x = 33.5), 9.43 m at
  // tick 7 (x = 34.5), within the 10 m radius.
  OneUav u(scenario(20, 1, {5, 5}, "targets { x: 8 y: 6 }"), 0);
  for (uint32_t k = 0; k <= 6; ++k) {
    const UavActions a = u.step(k);
    EXPECT_TRUE(a.detections.empty()) << "tick " << k;
    EXPECT_FALSE(a.broadcast) << "tick " << k;
  }
  const UavActions a = u.step(7);
  ASSERT_EQ(a.detections.size(), 1U);
  EXPECT_EQ(a.detections[0].target, 0);
  EXPECT_EQ(a.detections[0].cell, (Cell{8, 6}));
  const auto t = of_layer(a, kTarget);
  ASSERT_EQ(t.size(), 1U);
  EXPECT_EQ(t[0].cell, (Cell{8, 6}));
  EXPECT_EQ(t[0].region, 0U);
  EXPECT_FLOAT_EQ(t[0].amount, 100.0F);
  ASSERT_TRUE(a.broadcast);
  EXPECT_EQ(a.broadcast->kind, static_cast<uint8_t>(BroadcastKind::TargetFound));
  EXPECT_EQ(a.broadcast->values, (std::vector<double>{8.0, 6.0}));  // map cells
  // Still in view: no second detection, mark or broadcast.
  const UavActions b = u.step(8);
  EXPECT_TRUE(b.detections.empty());
  EXPECT_TRUE(of_layer(b, kTarget).empty());
  EXPECT_FALSE(b.broadcast);
}

TEST(ShostakUav, DecisionIsTheCoresRouletteOverCandidatesAroundTheEstimate) {
  // Without a dispersal leg the UAV decides at tick 1. Its frame is the map
  // frame shifted to its take-off point, so its draw equals shostak_choose at
  // the same position with the same random stream (uniform tiles, preferred
  // azimuth = its initial heading 0).
  const ScenarioConfig s = scenario(20, 1, {9, 9}, "", "dispersal_m: 0");
  OneUav u(s, 0);
  u.step(0);
  const UavActions a = u.step(1);

  const auto& c = s.config_of<ShostakConfig>();
  Rng rng(stream_seed(s.seed, "shostak-uav", 0));
  const Eigen::Vector3d p(9.5 * 5.0, 9.5 * 5.0, c.altitude_m);
  const ShostakLookup lookup = [](Cell) { return std::optional<ShostakCellValues>(ShostakCellValues{}); };
  const auto choice = shostak_choose(p, 0.0, lookup, 5.0, c.aco, c.attractiveness, rng);
  ASSERT_TRUE(choice);
  Eigen::Vector3d w = choice->candidate.position;
  w.z() = std::clamp(w.z(), c.min_altitude_m, c.max_altitude_m);
  const Eigen::Vector3d step = (w - p).normalized() * 1.0;  // 5 m/s · 0.2 s
  EXPECT_NEAR(a.state.x, 9.0 + step.x() / 5.0, 1e-9);
  EXPECT_NEAR(a.state.y, 9.0 + step.y() / 5.0, 1e-9);
}

TEST(ShostakUav, CandidatesOnCellsWithTargetPheromoneWin) {
  // Shostak 2024 eq. (3): b_t = τ_t·10 dwarfs b_e·b_h <= 1. With target pheromone 50 on
  // every cell east of the UAV, and none west, its waypoints lie east.
  const ScenarioConfig s = scenario(20, 1, {9, 9}, "", "dispersal_m: 0");
  const MapGeometry geo = s.geometry();
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    ScenarioConfig sc = s;
    sc.seed = seed;
    OneUav u(sc, 0);
    for (int32_t y = 0; y < 20; y += 5) {
      TileMsg m;
      m.layer = kTarget;
      m.tile = geo.tile_of({10, y});  // tile x 2: cells 10..14
      m.width = 5;
      m.height = 5;
      m.values.assign(25, 50.0F);
      u.cache.update(m);
      m.tile = geo.tile_of({15, y});
      u.cache.update(m);
    }
    u.step(0);
    const UavActions a = u.step(1);
    EXPECT_GT(a.state.vx, 0.0) << "seed " << seed;
  }
}

TEST(ShostakUav, ATargetFoundBroadcastTurnsTheUavFromItsLegAndBringsItToTheTarget) {
  // UAV 0 of 1 starts a 50 m eastward leg; at tick 1 it hears that a target
  // is at cell (2, 9), 35 m to its west. It drops the leg and, η preferring
  // the bearing to the target, reaches it (within one 15 m step) by tick 300.
  const ScenarioConfig s = scenario(20, 1, {9, 9});
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    ScenarioConfig sc = s;
    sc.seed = seed;
    OneUav u(sc, 0);
    BroadcastMsg b;
    b.uav = 7;
    b.kind = static_cast<uint8_t>(BroadcastKind::TargetFound);
    b.values = {2.0, 9.0};
    const std::vector<BroadcastMsg> heard{b};
    UavActions a = u.step(0);
    a = u.step(1, heard);
    double min_x = a.state.x;
    double closest = 1e9;
    for (uint32_t k = 2; k <= 300; ++k) {
      a = u.step(k);
      min_x = std::min(min_x, a.state.x);
      closest = std::min(closest, std::hypot(a.state.x - 2.0, a.state.y - 9.0));
    }
    EXPECT_LT(min_x, 9.0) << "seed " << seed;   // it did not keep to the eastward leg
    EXPECT_LE(closest, 3.0) << "seed " << seed;  // 15 m = 3 cells
  }
}

// --- the shostak_beeline variant (ours, converge: "beeline") ---------------------------

TEST(ShostakBeeline, WaypointIsOneStepOfDStraightTowardTheTargetAtTheUavsAltitude) {
  // From (0, 0, 10) to (30, 40, 0): 50 m away, so one step of 15 m along
  // (0.6, 0.8) = (9, 12), altitude kept at 10.
  const auto w = shostak_beeline_waypoint({0.0, 0.0, 10.0}, {30.0, 40.0, 0.0}, 15.0);
  ASSERT_TRUE(w.has_value());
  EXPECT_NEAR(w->x(), 9.0, 1e-12);
  EXPECT_NEAR(w->y(), 12.0, 1e-12);
  EXPECT_DOUBLE_EQ(w->z(), 10.0);
  // 10 m away (6, 8): the target itself, not beyond it.
  const auto near = shostak_beeline_waypoint({0.0, 0.0, 10.0}, {6.0, 8.0, 0.0}, 15.0);
  ASSERT_TRUE(near.has_value());
  EXPECT_NEAR(near->x(), 6.0, 1e-12);
  EXPECT_NEAR(near->y(), 8.0, 1e-12);
  // Over the target: no waypoint (the UAV hovers).
  EXPECT_FALSE(shostak_beeline_waypoint({6.0, 8.0, 10.0}, {6.0, 8.0, 0.0}, 15.0).has_value());
}

TEST(ShostakBeeline, ABroadcastTargetIsFlownToInAStraightLineAtOneMetrePerTick) {
  // UAV 0 of 1 at cell (9, 9) starts its eastward leg; at tick 1 it hears of a
  // target at cell (2, 9), 35 m west. Beeline: 1 m = 0.2 cell west every tick
  // from tick 1, y unchanged, over the target at tick 35, hovering after.
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    ScenarioConfig sc = scenario(20, 1, {9, 9}, "", "converge: \"beeline\"");
    sc.seed = seed;
    OneUav u(sc, 0);
    BroadcastMsg b;
    b.uav = 7;
    b.kind = static_cast<uint8_t>(BroadcastKind::TargetFound);
    b.values = {2.0, 9.0};
    const std::vector<BroadcastMsg> heard{b};
    u.step(0);
    UavActions a = u.step(1, heard);
    EXPECT_NEAR(a.state.x, 8.8, 1e-9);
    for (uint32_t k = 2; k <= 40; ++k) {
      a = u.step(k);
      EXPECT_NEAR(a.state.y, 9.0, 1e-9) << "tick " << k;
      EXPECT_NEAR(a.state.x, std::max(2.0, 9.0 - 0.2 * k), 1e-9) << "tick " << k << " seed " << seed;
    }
  }
}

TEST(ShostakBeeline, TheDefaultIsThePapersRouletteAndOnlyTwoNamesParse) {
  EXPECT_EQ(scenario(20, 1, {9, 9}).config_of<ShostakConfig>().converge, ShostakConfig::Converge::Roulette);
  EXPECT_EQ(scenario(20, 1, {9, 9}, "", "converge: \"roulette\"").config_of<ShostakConfig>().converge,
            ShostakConfig::Converge::Roulette);
  EXPECT_EQ(scenario(20, 1, {9, 9}, "", "converge: \"beeline\"").config_of<ShostakConfig>().converge,
            ShostakConfig::Converge::Beeline);
  const auto r = parse_scenario("map { width: 20 height: 20 }\nswarm { uavs: 1 }\npolicy {\n  shostak {\n"
                                "    converge: \"straight\"\n  }\n}\n",
                                "bad.textproto");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("bad.textproto:5:"), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find("policy.shostak.converge"), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find("must be \"roulette\" or \"beeline\""), std::string::npos) << r.error().message;
}

TEST(ShostakBeeline, BeforeAnyBroadcastTheSwarmFliesExactlyThePapersSearch) {
  // The variant changes nothing before a target is known: on the 40 x 40
  // scenario both find the target at the same tick with the same coverage.
  auto r = load_scenario(std::string(PHEROMESH_SOURCE_DIR) + "/scenarios/shostak-40x40.textproto");
  ASSERT_TRUE(r.ok()) << r.error().message;
  auto b = patch_scenario(r.value(), "policy { shostak { converge: \"beeline\" } }", "beeline");
  ASSERT_TRUE(b.ok()) << b.error().message;
  for (uint64_t seed = 1; seed <= 2; ++seed) {
    ScenarioConfig sp = r.value(), sb = b.value();
    sp.seed = sb.seed = seed;
    Simulator p(sp), v(sb);
    p.run();
    v.run();
    ASSERT_EQ(p.recorder().acquisitions().acquisition_ticks().size(), 1U) << seed;
    EXPECT_EQ(p.recorder().acquisitions().acquisition_ticks(), v.recorder().acquisitions().acquisition_ticks()) << seed;
  }
}

TEST(ShostakUav, DriftPutsExploredDepositsUnderTheEstimateNotTheTrueCell) {
  // With ideal pose (the default) every deposit lands on the true cell; with
  // odometry noise of 1 m²/m (σ = 1 m per axis per 1 m step) the estimate
  // wanders and deposits land elsewhere.
  for (const char* policy : {"", "position_noise_m2_per_m: 1"}) {
    OneUav u(scenario(20, 1, {9, 9}, "", policy), 0);
    int elsewhere = 0;
    for (uint32_t k = 0; k <= 60; ++k) {
      const UavActions a = u.step(k);
      const auto e = of_layer(a, kExplored);
      const Cell truth{static_cast<int32_t>(std::lround(a.state.x)), static_cast<int32_t>(std::lround(a.state.y))};
      if (e.empty() || !(e[0].cell == truth)) ++elsewhere;
    }
    if (std::string(policy).empty()) {
      EXPECT_EQ(elsewhere, 0);
    } else {
      EXPECT_GT(elsewhere, 0);
    }
  }
}

// --- scenario -----------------------------------------------------------------------

TEST(ShostakScenario, PaperScenarioHasTheParametersOfSectionsTwoToFive) {
  auto r = load_scenario(std::string(PHEROMESH_SOURCE_DIR) + "/scenarios/shostak-40x40.textproto");
  ASSERT_TRUE(r.ok()) << r.error().message;
  const ScenarioConfig& s = r.value();
  EXPECT_EQ(s.policy, "shostak");
  EXPECT_EQ(s.width, 40);
  EXPECT_EQ(s.uavs, 3U);
  ASSERT_EQ(s.targets.size(), 1U);
  const ShostakConfig& c = s.config_of<ShostakConfig>();
  EXPECT_DOUBLE_EQ(c.dt_s, 0.2);
  EXPECT_DOUBLE_EQ(c.layers.cell_size_m, 5.0);
  EXPECT_DOUBLE_EQ(c.layers.evaporation_rate, 0.05);
  EXPECT_DOUBLE_EQ(c.layers.explored_max, 10.0);
  EXPECT_DOUBLE_EQ(c.layers.target_increment, 100.0);
  EXPECT_EQ(c.aco.candidate_count, 20U);
  EXPECT_DOUBLE_EQ(c.aco.step_m, 15.0);
  EXPECT_NEAR(c.aco.pitch_max_rad, kPi / 6.0, 1e-15);
  EXPECT_DOUBLE_EQ(c.aco.alpha, 1.5);
  EXPECT_DOUBLE_EQ(c.aco.beta, 3.0);
  EXPECT_TRUE(load_scenario(std::string(PHEROMESH_SOURCE_DIR) + "/scenarios/shostak-small.textproto").ok());
}

void expect_error(const std::string& policy, int line, const std::string& field, const std::string& what) {
  const std::string text = "map { width: 20 height: 20 }\nswarm { uavs: 2 }\npolicy {\n  shostak {\n" + policy + "\n  }\n}\n";
  const auto r = parse_scenario(text, "bad.textproto");
  ASSERT_FALSE(r.ok()) << policy;
  const std::string& msg = r.error().message;
  EXPECT_NE(msg.find("bad.textproto:" + std::to_string(line) + ":"), std::string::npos) << msg;
  EXPECT_NE(msg.find("field 'policy.shostak." + field + "'"), std::string::npos) << msg;
  EXPECT_NE(msg.find(what), std::string::npos) << msg;
}

TEST(ShostakScenario, BadValuesNameTheLineAndTheField) {
  expect_error("    dt_s: 0", 5, "dt_s", "must be in (0, 1] (got 0)");
  expect_error("    rho: 1", 5, "rho", "must be in [0, 1) (got 1)");
  expect_error("    cell_size_m: 5\n    candidates: 0", 6, "candidates", "must be between 1 and 64");
  expect_error("    step_m: 400", 5, "step_m", "must be at most 63 cells = 315 m");
  expect_error("    pitch_max_deg: 90", 5, "pitch_max_deg", "must be in [0, 90)");
  expect_error("    min_altitude_m: 20\n    max_altitude_m: 10", 6, "max_altitude_m", "must be >= min_altitude_m = 20");
  expect_error("    altitude_m: 40", 5, "altitude_m", "must be in [5, 30] (got 40)");
  expect_error("    detect_radius_m: nan", 5, "detect_radius_m", "a finite number");
  expect_error("    frame_yaw_deg: 0\n    frame_yaw_deg: 400", 6, "frame_yaw_deg[1]", "must be in (-360, 360)");
  expect_error("    frame_yaw_deg: [0, 10, 20]", 5, "frame_yaw_deg[2]", "more entries than swarm.uavs = 2");
  expect_error("    yaw_noise_rad2_per_m: -1", 5, "yaw_noise_rad2_per_m", "must be >= 0");
}

// --- the Shostak 2024 Sec. 5 scenario in the simulator ---------------------------------------------

// Seeds 1..10 of scenarios/shostak-40x40.textproto: the tick of the first
// detection (the TargetFound broadcast) and the ticks until every other UAV
// has come within one step d = 15 m (3 cells) of the target, as the
// shostak-convergence experiment measures it. Shostak 2024 Sec. 5 gives no number
// ("rapid convergence of all drones"); printed for docs/policies/shostak.md.
TEST(ShostakSimulator, PaperScenarioFindsTheTargetAndTheOthersConverge) {
  auto r = load_scenario(std::string(PHEROMESH_SOURCE_DIR) + "/scenarios/shostak-40x40.textproto");
  ASSERT_TRUE(r.ok()) << r.error().message;
  const Cell target = r.value().targets[0];
  const double detect_cells = r.value().config_of<ShostakConfig>().detect_radius_m / r.value().config_of<ShostakConfig>().layers.cell_size_m;
  const double step_cells = r.value().config_of<ShostakConfig>().aco.step_m / r.value().config_of<ShostakConfig>().layers.cell_size_m;
  int detected = 0;
  int converged = 0;
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    ScenarioConfig s = r.value();
    s.seed = seed;
    Simulator sim(s);
    std::optional<uint32_t> detect_tick;
    std::optional<uint32_t> converge_tick;
    std::vector<std::optional<uint32_t>> arrived(s.uavs);
    std::optional<uint32_t> detector;
    // Search for the scenario's 3000 ticks (600 s); once found, allow 1500
    // more (300 s) to converge, as the experiment does.
    for (uint32_t k = 0; k <= (detect_tick ? *detect_tick + 1500 : s.ticks) && !converge_tick; ++k) {
      sim.step(k);
      const auto& acq = sim.recorder().acquisitions().acquisition_ticks();
      if (!detect_tick && !acq.empty()) detect_tick = acq.front();
      if (!detect_tick) continue;
      bool all = true;
      for (const auto& [id, st] : sim.recorder().uavs()) {
        const double d = std::hypot(st.last.x - target.x, st.last.y - target.y);
        if (!detector && d <= detect_cells + 1e-9) detector = id;  // the one that saw it
        if (detector && id == *detector) continue;
        if (!arrived[id] && d <= step_cells) arrived[id] = k;
        all = all && arrived[id].has_value();
      }
      if (all && detector) converge_tick = k;
    }
    if (converge_tick) ++converged;
    const double dt = s.config_of<ShostakConfig>().dt_s;
    std::printf("shostak-40x40 seed %2llu: first detection at tick %5lld (%6.1f s); others within 15 m after %5lld ticks (%6.1f s)\n",
                static_cast<unsigned long long>(seed), detect_tick ? static_cast<long long>(*detect_tick) : -1LL,
                detect_tick ? *detect_tick * dt : -1.0,
                converge_tick ? static_cast<long long>(*converge_tick - *detect_tick) : -1LL,
                converge_tick ? (*converge_tick - *detect_tick) * dt : -1.0);
    if (detect_tick) ++detected;
    EXPECT_EQ(converge_tick.has_value(), detect_tick.has_value()) << "seed " << seed;
  }
  // A random search of 600 s does not always find the target (seed 4 does
  // not); whenever it is found, the others converge.
  EXPECT_GE(detected, 8);
  EXPECT_EQ(converged, detected);
}

}  // namespace
}  // namespace pheromesh::core
