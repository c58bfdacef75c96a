// The console's frame builder (console/frame_builder.hpp): liveness by the
// stale thresholds, the deposit rate, changed tiles only, target status.
// Time is driven by hand; the scenario is small-test (30x30, 2x2 regions,
// 4 UAVs, 3 targets).
#include <gtest/gtest.h>

#include <string>

#include "pheromesh/console/frame_builder.hpp"
#include "pheromesh/core/scenario.hpp"

namespace pheromesh::console {
namespace {

using namespace std::chrono_literals;
using Clock = FrameBuilder::Clock;

struct FrameRig {
  core::ScenarioConfig scenario;
  core::MapGeometry geo{1, 1, 1, 1, 1};
  std::unique_ptr<core::World> world;
  std::unique_ptr<core::RunRecorder> rec;
  std::map<FrameBuilder::TileKey, core::TileMsg> tiles;
  std::vector<core::Rect> popups;
  ConsoleState last;
  FrameRig() {
    auto s = core::load_scenario(std::string(PHEROMESH_SOURCE_DIR) + "/scenarios/small-test.textproto");
    EXPECT_TRUE(s.ok());
    scenario = s.value();
    geo = scenario.geometry();
    world = std::make_unique<core::World>(geo, scenario.obstacles, scenario.targets);
    rec = std::make_unique<core::RunRecorder>(scenario, *world);
    ConsoleInfo info;
    info.layers = {"path"};
    for (core::RegionId r = 0; r < geo.region_count(); ++r) info.regions.push_back(geo.region_rect(r));
    last = initial_state(info);
  }
  Frame build(FrameBuilder& b, Clock::time_point now, bool paused = false) {
    const FrameBuilder::Sources src{tiles, *rec, *world, scenario.targets.size(), scenario.obstacles, popups, paused};
    Frame f = b.build(last, src, now, 1.0);
    apply(last, f);
    return f;
  }
};

core::UavStateMsg uav_state(uint32_t uav, uint32_t tick, bool finished = false) {
  core::UavStateMsg s;
  s.uav = uav;
  s.tick = tick;
  s.x = 2;
  s.y = 2;
  s.finished = finished;
  return s;
}

const UavView& uav(const Frame& f, uint32_t id) {
  for (const auto& u : f.uavs) {
    if (u.id == id) return u;
  }
  throw std::runtime_error("no uav " + std::to_string(id));
}

TEST(FrameBuilder, AUavIsStaleAfterOneQuietSecondUnlessPausedThenDeadOrFinished) {
  FrameRig rig;
  FrameBuilder b(rig.geo);
  const auto t0 = Clock::time_point{} + 100s;
  ASSERT_TRUE(rig.rec->on_uav_state(uav_state(0, 1)));
  ASSERT_TRUE(rig.rec->on_uav_state(uav_state(1, 1)));
  b.heard_uav(0, t0);
  b.heard_uav(1, t0);
  EXPECT_EQ(b.uavs_heard(), 2U);
  EXPECT_EQ(uav(rig.build(b, t0 + 1s), 0).liveness, Liveness::Alive) << "exactly 1 s quiet is not stale yet";
  EXPECT_EQ(uav(rig.build(b, t0 + 1001ms), 0).liveness, Liveness::Stale);
  EXPECT_EQ(uav(rig.build(b, t0 + 5s, true), 0).liveness, Liveness::Alive) << "a paused swarm is quiet on purpose";
  rig.rec->on_uav_departed(0);
  ASSERT_TRUE(rig.rec->on_uav_state(uav_state(1, 2, true)));
  const Frame f = rig.build(b, t0 + 1500ms);
  EXPECT_EQ(uav(f, 0).liveness, Liveness::Dead);
  EXPECT_EQ(uav(f, 1).liveness, Liveness::Finished);
  EXPECT_EQ(f.version, 4U) << "the fourth frame after the initial state";
}

TEST(FrameBuilder, APlaceAgentIsStaleAfterTwoQuietSecondsAndItsRateIsAppliedDepositsPerSecond) {
  FrameRig rig;
  FrameBuilder b(rig.geo);
  const auto t0 = Clock::time_point{} + 100s;
  core::HealthMsg h;
  h.region = 1;
  h.tick = 4;
  h.deposits_applied = 10;
  rig.rec->on_health(h);
  b.heard_region(1, t0);
  Frame f = rig.build(b, t0);
  ASSERT_EQ(f.regions.size(), 4U);
  EXPECT_EQ(f.regions[1].liveness, Liveness::Alive);
  EXPECT_EQ(f.regions[1].deposits_per_s, 0.0) << "the first frame only sets the baseline";
  h.deposits_applied = 30;
  rig.rec->on_health(h);
  f = rig.build(b, t0 + 2s);
  EXPECT_DOUBLE_EQ(f.regions[1].deposits_per_s, 10.0) << "20 deposits in 2 s";
  EXPECT_EQ(f.regions[1].liveness, Liveness::Alive);
  f = rig.build(b, t0 + 2001ms);
  EXPECT_EQ(f.regions[1].liveness, Liveness::Stale);
  EXPECT_DOUBLE_EQ(f.regions[1].deposits_per_s, 10.0) << "kept until a full period has passed";
  rig.rec->on_place_departed(core::place_id(1, 0));
  EXPECT_EQ(rig.build(b, t0 + 2002ms).regions[1].liveness, Liveness::Dead);
}

TEST(FrameBuilder, ARegionWhosePrimaryDiedIsAliveOnItsStandbyAndShowsWhichReplicaServesIt) {
  FrameRig rig;
  FrameBuilder b(rig.geo);
  const auto t0 = Clock::time_point{} + 100s;
  core::HealthMsg h;
  h.region = 2;
  rig.rec->on_health(h);
  h.replica = 1;
  rig.rec->on_health(h);
  b.heard_region(2, t0);
  Frame f = rig.build(b, t0);
  EXPECT_EQ(f.regions[2].replica, 0U);
  EXPECT_EQ(f.regions[2].replicas_alive, 2U);
  rig.rec->on_place_departed(core::place_id(2, 0));
  f = rig.build(b, t0 + 100ms);
  EXPECT_EQ(f.regions[2].liveness, Liveness::Alive) << "its standby serves it";
  EXPECT_EQ(f.regions[2].replica, 1U) << "shown as replaced by standby 1";
  EXPECT_EQ(f.regions[2].replicas_alive, 1U);
  rig.rec->on_place_departed(core::place_id(2, 1));
  EXPECT_EQ(rig.build(b, t0 + 200ms).regions[2].liveness, Liveness::Dead);
}

TEST(FrameBuilder, OnlyChangedTilesAreSentAndAScaleChangeResendsTheLayer) {
  FrameRig rig;
  FrameBuilder b(rig.geo);
  const auto t0 = Clock::time_point{} + 100s;
  core::TileMsg t;
  t.layer = 0;
  t.tile = {1, 0};
  t.tick = 3;
  t.width = 6;
  t.height = 6;
  t.values.assign(36, 0.5F);
  rig.tiles[{0, {1, 0}}] = t;
  Frame f = rig.build(b, t0);
  ASSERT_EQ(f.tiles.size(), 1U);
  EXPECT_EQ(f.tiles[0].tx, 1);
  EXPECT_EQ(f.tiles[0].rect.x0, 6) << "tile (1,0) of 6 cells starts at x 6";
  EXPECT_TRUE(rig.build(b, t0).tiles.empty()) << "nothing changed";
  rig.tiles[{0, {1, 0}}].values[0] = 3.0F;  // above the scale of 1: the scale grows to 4
  f = rig.build(b, t0);
  ASSERT_EQ(f.scales.size(), 1U);
  EXPECT_FLOAT_EQ(f.scales[0].second, 4.0F);
  EXPECT_EQ(f.tiles.size(), 1U);
  rig.tiles[{7, {0, 0}}] = t;  // a layer the console does not show is ignored
  EXPECT_TRUE(rig.build(b, t0).tiles.empty());
}

TEST(FrameBuilder, TargetsShowWhoFoundThemRevisitsDueAndPopUps) {
  FrameRig rig;
  FrameBuilder b(rig.geo);
  const auto t0 = Clock::time_point{} + 100s;
  // The recorder judges a detection by the UAV's state (core/plausibility.hpp):
  // UAV 2 flew next to target 1.
  core::UavStateMsg near = uav_state(2, 20);
  near.x = rig.scenario.targets[1].x;
  near.y = rig.scenario.targets[1].y - 1;
  ASSERT_TRUE(rig.rec->on_uav_state(near));
  ASSERT_TRUE(rig.rec->on_detection({2, 9, 1, rig.scenario.targets[1]}));
  EXPECT_EQ(rig.rec->take_first_acquisitions().size(), 1U);
  b.target_found(1, 2, 9);
  b.revisit(rig.scenario.targets[2], true);
  rig.world->add_target({1, 28});
  rig.rec->add_target();
  rig.popups.push_back({0, 20, 2, 2});
  Frame f = rig.build(b, t0);
  ASSERT_EQ(f.targets.size(), 4U);
  EXPECT_EQ(f.targets[0].status, TargetStatus::NotFound);
  EXPECT_EQ(f.targets[1].status, TargetStatus::Found);
  EXPECT_EQ(f.targets[1].found_by, 2);
  EXPECT_EQ(f.targets[1].found_tick, 9U);
  EXPECT_EQ(f.targets[2].status, TargetStatus::RevisitDue);
  EXPECT_FALSE(f.targets[2].popup);
  EXPECT_TRUE(f.targets[3].popup);
  ASSERT_EQ(f.obstacles.size(), 3U);
  EXPECT_FALSE(f.obstacles[0].popup);
  EXPECT_TRUE(f.obstacles[2].popup);
  b.revisit(rig.scenario.targets[2], false);
  EXPECT_EQ(rig.build(b, t0).targets[2].status, TargetStatus::NotFound);
}

}  // namespace
}  // namespace pheromesh::console
