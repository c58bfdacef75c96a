// The console's pure parts: quantisation, JSON deltas, frames, Prometheus
// text, uncertainty (numbers worked by hand).
#include <gtest/gtest.h>

#include <cmath>

#include "pheromesh/console/prometheus.hpp"
#include "pheromesh/console/state.hpp"
#include "pheromesh/console/uncertainty.hpp"
#include "pheromesh/console/view.hpp"
#include "pheromesh/core/world.hpp"

namespace pheromesh::console {
namespace {

TEST(ConsoleScale, GrowsToThePowerOfTwoAboveTheMaximum) {
  EXPECT_FLOAT_EQ(next_scale(1.0F, 0.7F), 1.0F);
  EXPECT_FLOAT_EQ(next_scale(1.0F, 1.0F), 1.0F);
  EXPECT_FLOAT_EQ(next_scale(1.0F, 1.5F), 2.0F);
  EXPECT_FLOAT_EQ(next_scale(1.0F, 5.0F), 8.0F);
}

TEST(ConsoleScale, ShrinksOnlyBelowAQuarter) {
  EXPECT_FLOAT_EQ(next_scale(8.0F, 2.5F), 8.0F);   // 2.5 >= 8/4: kept
  EXPECT_FLOAT_EQ(next_scale(8.0F, 1.9F), 4.0F);   // 1.9 < 2 -> 4; 1.9 >= 4/4 -> stays 4
  EXPECT_FLOAT_EQ(next_scale(8.0F, 0.1F), 0.25F);  // 8 -> 4 -> 2 -> 1 -> 0.5 -> 0.25 (0.1 >= 0.0625)
  EXPECT_FLOAT_EQ(next_scale(1.0F, 0.0F), kMinScale);
  EXPECT_FLOAT_EQ(next_scale(1.0F, std::nanf("")), kMinScale);
}

TEST(ConsoleQuantise, MapsZeroToScaleOnto0To255) {
  std::vector<uint8_t> q;
  const std::vector<float> v{0.0F, 1.0F, 2.0F, 4.0F, 8.0F, -1.0F, std::nanf(""), 0.5F};
  quantise(v, 4.0F, q);
  // 255 * v / 4: 0, 63.75 -> 64, 127.5 -> 128 (round half away), 255, clamp 255, 0, 0, 31.875 -> 32
  EXPECT_EQ(q, (std::vector<uint8_t>{0, 64, 128, 255, 255, 0, 0, 32}));
}

TEST(ConsoleBase64, Rfc4648Vectors) {
  const auto b = [](const std::string& s) {
    return base64(std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(s.data()), s.size()));
  };
  EXPECT_EQ(b(""), "");
  EXPECT_EQ(b("f"), "Zg==");
  EXPECT_EQ(b("fo"), "Zm8=");
  EXPECT_EQ(b("foo"), "Zm9v");
  EXPECT_EQ(b("foob"), "Zm9vYg==");
  EXPECT_EQ(b("fooba"), "Zm9vYmE=");
  EXPECT_EQ(b("foobar"), "Zm9vYmFy");
}

ConsoleInfo two_layer_info() {
  ConsoleInfo i;
  i.width = 4;
  i.height = 2;
  i.tile_size = 2;
  i.layers = {"a", "b"};
  i.regions = {{0, 0, 4, 2}};
  return i;
}

Frame frame_with_tile(uint64_t version, uint8_t value, double x) {
  Frame f;
  f.version = version;
  f.t_s = 0.2 * static_cast<double>(version);
  f.tick = static_cast<uint32_t>(version);
  f.tiles.push_back({0, 1, 0, {2, 0, 2, 2}, f.tick, std::vector<uint8_t>(4, value)});
  UavView u;
  u.id = 7;
  u.x = x;
  u.y = 1.0;
  f.uavs.push_back(u);
  f.regions.push_back({});
  return f;
}

TEST(ConsoleFrames, JsonSendsOnlyWhatChangedAfterSince) {
  const ConsoleInfo info = two_layer_info();
  ConsoleState s = initial_state(info);
  apply(s, frame_with_tile(1, 10, 0.0));
  Frame f2;
  f2.version = 2;
  f2.uavs.push_back(s.uavs.at(7));
  f2.uavs.back().x = 0.5;  // moved less than a cell: no track point
  f2.regions.push_back({});
  apply(s, f2);
  apply(s, frame_with_tile(3, 20, 2.0));
  ASSERT_EQ(s.uavs.at(7).track.size(), 2U);  // x = 0 and x = 2

  const auto full = frame_json(s, info, 0, 0);
  EXPECT_TRUE(full["full"].get<bool>());
  ASSERT_EQ(full["layer"]["tiles"].size(), 1U);
  EXPECT_EQ(full["layer"]["tiles"][0]["q"], "FBQUFA==");  // four bytes of 20
  EXPECT_EQ(full["uavs"][0]["track"].size(), 2U);

  const auto after2 = frame_json(s, info, 0, 2);
  EXPECT_FALSE(after2["full"].get<bool>());
  EXPECT_EQ(after2["layer"]["tiles"].size(), 1U);     // changed in 3
  EXPECT_EQ(after2["uavs"][0]["track"].size(), 1U);   // the point of frame 3

  const auto after3 = frame_json(s, info, 0, 3);
  EXPECT_EQ(after3["layer"]["tiles"].size(), 0U);
  EXPECT_EQ(after3["uavs"][0]["track"].size(), 0U);

  // A client from an earlier console (since newer than the state) gets everything.
  EXPECT_TRUE(frame_json(s, info, 0, 99)["full"].get<bool>());
  // The other layer has no tiles yet.
  EXPECT_EQ(frame_json(s, info, 1, 0)["layer"]["tiles"].size(), 0U);
}

TEST(ConsoleFrames, TracksKeepTheLatestPointsOnly) {
  ConsoleState s = initial_state(two_layer_info());
  for (uint64_t v = 1; v <= kTrackPoints + 10; ++v) apply(s, frame_with_tile(v, 1, static_cast<double>(v)));
  const auto& track = s.uavs.at(7).track;
  ASSERT_EQ(track.size(), kTrackPoints);
  EXPECT_FLOAT_EQ(track.back().x, static_cast<float>(kTrackPoints + 10));
  EXPECT_FLOAT_EQ(track.front().x, 11.0F);
}

TEST(ConsolePrometheus, FamiliesSamplesAndEscaping) {
  Exposition e;
  e.family("pheromesh_x_total", "counter", "Line one\nback\\slash");
  e.sample("pheromesh_x_total", {{"region", "a\"b\\c\nd"}}, 3);
  e.sample("pheromesh_x_total", 0.25);
  EXPECT_EQ(e.text(),
            "# HELP pheromesh_x_total Line one\\nback\\\\slash\n"
            "# TYPE pheromesh_x_total counter\n"
            "pheromesh_x_total{region=\"a\\\"b\\\\c\\nd\"} 3\n"
            "pheromesh_x_total 0.25\n");
  EXPECT_EQ(Exposition::format_value(std::nan("")), "NaN");
  EXPECT_EQ(Exposition::format_value(-INFINITY), "-Inf");
}

TEST(ConsoleUncertainty, MeanOfDecayedAges) {
  // 3x1 map, all reachable, sensor radius 0 (a UAV sees its own cell), tau 10.
  const core::MapGeometry geo(3, 1, 1, 1, 1);
  UncertaintyTracker u(geo, {1, 1, 1}, 0.0, 10.0);
  EXPECT_DOUBLE_EQ(u.mean(0), 1.0);  // nothing seen
  u.observe({0, 0}, 5);
  u.observe({1, 0}, 10);
  // at tick 10: cell 0 age 5 -> 1 - e^-0.5 = 0.393469; cell 1 age 0 -> 0; cell 2 never -> 1.
  EXPECT_NEAR(u.mean(10), (0.39346934028736658 + 0.0 + 1.0) / 3.0, 1e-12);
  // Unreachable cells do not count.
  UncertaintyTracker v(geo, {1, 0, 0}, 0.0, 10.0);
  v.observe({0, 0}, 10);
  EXPECT_DOUBLE_EQ(v.mean(10), 0.0);
}

TEST(ConsoleWorld, PopUpObstaclesAndTargets) {
  const core::MapGeometry geo(10, 10, 5, 1, 1);
  core::World w(geo, {}, {{1, 1}});
  EXPECT_EQ(w.add_obstacle({8, 8, 4, 4}), 4);  // clipped to the map: 2x2
  EXPECT_EQ(w.add_obstacle({9, 9, 1, 1}), 0);  // already an obstacle
  EXPECT_TRUE(w.is_obstacle({9, 9}));
  EXPECT_FALSE(w.is_obstacle({7, 7}));
  EXPECT_EQ(w.add_target({4, 4}), 1);
  EXPECT_EQ(w.target_at({4, 4}), 1);
  EXPECT_EQ(w.targets().size(), 2U);
}

}  // namespace
}  // namespace pheromesh::console

namespace pheromesh::console {
namespace {
TEST(ConsoleFrames, ARestartedUavStartsANewTrack) {
  ConsoleState s = initial_state(two_layer_info());
  apply(s, frame_with_tile(1, 1, 0.0));
  apply(s, frame_with_tile(2, 1, 3.0));
  Frame dead = frame_with_tile(3, 1, 3.0);
  dead.uavs[0].liveness = Liveness::Dead;
  apply(s, dead);
  EXPECT_EQ(s.uavs.at(7).track.size(), 2U);
  apply(s, frame_with_tile(4, 1, 9.0));  // alive again, elsewhere
  ASSERT_EQ(s.uavs.at(7).track.size(), 1U);
  EXPECT_FLOAT_EQ(s.uavs.at(7).track.front().x, 9.0F);
}
}  // namespace
}  // namespace pheromesh::console
