// What a lockstep place agent's view service (core::ViewServer) costs per
// tick (issue 44): the place agent of region 5 of scale-100x100 (16 regions
// of 3x3 or 2x2 tiles of 10x10 cells, 3 layers, view radius 5) with 100 or
// 1000 UAVs spread over the map, every UAV moving one cell a tick. One
// iteration is the view work of one place phase, in the order PlaceApp runs
// it:
//   * the served UAVs of the 15 other regions as the place clock lists them
//     (update_served of the whole list);
//   * its own tiles of the tick (update_tile);
//   * to each other region the tiles of this one its UAVs' views need
//     (tiles_for);
//   * the regions whose tiles its own UAVs' views need (owners_for), and
//     those tiles (update_tiles, one chunk per owner);
//   * the view of each of its home UAVs (compose).
// Once with a policy that reads no neighbours (the scale scenarios' Shao
// search) and once with one that does. items_per_second = place ticks.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/rng.hpp"
#include "pheromesh/core/view_server.hpp"

namespace {

using namespace pheromesh::core;

constexpr int kLayers = 3;
constexpr double kViewRadius = 5.0;
constexpr RegionId kSelf = 5;

struct Swarm {
  MapGeometry geo{100, 100, 10, 4, 4};
  std::vector<ServedUav> uavs;
  std::vector<int32_t> dx, dy;
  std::vector<RegionId> others;

  explicit Swarm(uint32_t n) {
    Rng rng(11);
    for (uint32_t u = 0; u < n; ++u) {
      ServedUav s;
      s.uav = u;
      s.region = home_region(u, geo.region_count());
      s.x = rng.uniform_below(100);
      s.y = rng.uniform_below(100);
      s.view = {static_cast<int32_t>(s.x), static_cast<int32_t>(s.y)};
      uavs.push_back(s);
      dx.push_back(static_cast<int32_t>(rng.uniform_below(3)) - 1);
      dy.push_back(static_cast<int32_t>(rng.uniform_below(3)) - 1);
    }
    for (RegionId r = 0; r < geo.region_count(); ++r) {
      if (r != kSelf) others.push_back(r);
    }
  }

  // Every UAV one cell on, turning back at the map's edge.
  void move() {
    for (std::size_t i = 0; i < uavs.size(); ++i) {
      auto& s = uavs[i];
      if (s.x + dx[i] < 0 || s.x + dx[i] > 99) dx[i] = -dx[i];
      if (s.y + dy[i] < 0 || s.y + dy[i] > 99) dy[i] = -dy[i];
      s.x += dx[i];
      s.y += dy[i];
      s.view = {static_cast<int32_t>(s.x), static_cast<int32_t>(s.y)};
    }
  }

  // The tiles of region `r` at `tick`, every layer.
  [[nodiscard]] std::vector<TileMsg> tiles_of(RegionId r, uint32_t tick) const {
    std::vector<TileMsg> out;
    for (const TileCoord t : geo.region_tiles(r)) {
      for (int l = 0; l < kLayers; ++l) {
        TileMsg m;
        m.layer = static_cast<uint8_t>(l);
        m.tile = t;
        m.tick = tick;
        m.region = r;
        m.width = 10;
        m.height = 10;
        m.values.assign(100, 0.25F * static_cast<float>(l + 1));
        out.push_back(std::move(m));
      }
    }
    return out;
  }
};

void BM_PlacePhaseViews(benchmark::State& state) {
  const auto n = static_cast<uint32_t>(state.range(0));
  const bool neighbours = state.range(1) != 0;
  Swarm swarm(n);
  ViewServer views(swarm.geo, kLayers, kViewRadius, neighbours);
  std::vector<std::vector<TileMsg>> region_tiles;
  for (RegionId r = 0; r < swarm.geo.region_count(); ++r) region_tiles.push_back(swarm.tiles_of(r, 0));
  std::vector<std::string> malformed;
  std::vector<TileMsg> own, out;
  std::vector<uint32_t> home;
  ViewMsg view;
  uint64_t composed = 0;
  uint32_t tick = 0;
  for (auto _ : state) {
    state.PauseTiming();
    ++tick;
    swarm.move();
    own = region_tiles[kSelf];
    for (auto& t : own) t.tick = tick;
    home.clear();
    for (const auto& s : swarm.uavs) {
      if (s.region == kSelf) home.push_back(s.uav);
    }
    std::vector<FieldMsg> chunks;  // what each owner would send for the home UAVs' views
    state.ResumeTiming();

    // The home UAVs' states (take_inputs) and every other region's served UAVs (take_served).
    for (const auto& s : swarm.uavs) {
      if (s.region == kSelf) views.update_state(neighbour_state(s, tick));
    }
    views.update_served(swarm.uavs, tick, swarm.others, n, malformed);
    // serve_views: its own tiles, the tiles for the other homes, the owners' tiles, the views.
    for (const auto& t : own) views.update_tile(t, tick);
    for (RegionId h : swarm.others) {
      out.clear();
      views.tiles_for(h, 0, 0, own, out);
      benchmark::DoNotOptimize(out.data());
    }
    const std::vector<RegionId> owners = views.owners_for(home, 0, kSelf);

    state.PauseTiming();
    const std::vector<TileCoord> needed = views.needed_tiles(home);
    for (RegionId o : owners) {
      FieldMsg f;
      f.region = o;
      f.tick = tick;
      for (TileMsg t : region_tiles[o]) {
        if (std::find(needed.begin(), needed.end(), t.tile) == needed.end()) continue;
        t.tick = tick;
        f.tiles.push_back(std::move(t));
      }
      chunks.push_back(std::move(f));
    }
    state.ResumeTiming();

    for (const auto& f : chunks) views.update_tiles(f, tick);
    for (uint32_t u : home) composed += views.compose(u, tick, 0, tick, view) ? 1 : 0;
    benchmark::DoNotOptimize(view.tiles.data());
  }
  if (!malformed.empty()) state.SkipWithError(malformed.front().c_str());
  if (composed == 0) state.SkipWithError("no view composed");
  state.SetItemsProcessed(state.iterations());
  state.counters["views"] = benchmark::Counter(static_cast<double>(composed) / static_cast<double>(state.iterations()));
}

}  // namespace

BENCHMARK(BM_PlacePhaseViews)
    ->ArgNames({"uavs", "neighbours"})
    ->Args({100, 0})
    ->Args({100, 1})
    ->Args({1000, 0})
    ->Args({1000, 1})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
