// Pheromone layer step throughput: the region field (padded buffers,
// precomputed 1/|N| weights, vectorised rows) against the naive whole-map
// reference, with a memcpy of the same bytes for scale.
//
// items_per_second = map cells advanced by one full step (target, obstacle and
// path layers) per second, so the two step benchmarks compare directly.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/layers.hpp"
#include "pheromesh/core/rng.hpp"

namespace {

using pheromesh::core::Cell;
using pheromesh::core::Layer;
using pheromesh::core::MapGeometry;
using pheromesh::core::RegionField;
using pheromesh::core::Rng;
using pheromesh::core::ShaoLayerParams;

constexpr int kUavs = 4;  // path visits per step

std::vector<Cell> uav_cells(int32_t side) {
  Rng rng(7);
  std::vector<Cell> out;
  for (int i = 0; i < kUavs; ++i) {
    out.push_back({static_cast<int32_t>(rng.uniform_below(static_cast<uint32_t>(side))),
                   static_cast<int32_t>(rng.uniform_below(static_cast<uint32_t>(side)))});
  }
  return out;
}

void BM_RegionFieldStep(benchmark::State& state) {
  const auto side = static_cast<int32_t>(state.range(0));
  const MapGeometry geo(side, side, 10, 1, 1);
  const ShaoLayerParams p;
  RegionField field(geo, 0, p);
  Rng rng(1);
  for (float& v : field.mutable_layer(Layer::Target)) v = static_cast<float>(rng.uniform01());
  for (float& v : field.mutable_layer(Layer::Obstacle)) v = static_cast<float>(rng.uniform01());
  for (int i = 0; i < side; ++i) field.set_target_switch({i, i}, true);
  if (state.range(1) != 0) {
    for (int y = 0; y < side; ++y) for (int x = 0; x < side; ++x) { field.set_target_switch({x, y}, true); field.set_obstacle_switch({x, y}); }
  }
  const std::vector<Cell> uavs = uav_cells(side);
  for (auto _ : state) {
    for (const Cell& u : uavs) field.add_path_visit(u);
    benchmark::DoNotOptimize(field.begin_step());
    field.finish_step();
    benchmark::DoNotOptimize(field.layer(Layer::Target).data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * int64_t{side} * side);
}

// Baseline: reference_diffuse for target and obstacle plus a path update that
// visits every cell for every UAV.
void BM_NaiveStep(benchmark::State& state) {
  const auto side = static_cast<int32_t>(state.range(0));
  const MapGeometry geo(side, side, 10, 1, 1);
  const ShaoLayerParams p;
  const auto cells = static_cast<std::size_t>(side) * static_cast<std::size_t>(side);
  std::vector<float> tau(cells), eps(cells), next(cells), sigma(cells, static_cast<float>(p.sigma0));
  std::vector<uint8_t> k_tau(cells, 0), k_eps(cells, 0);
  Rng rng(1);
  for (float& v : tau) v = static_cast<float>(rng.uniform01());
  for (float& v : eps) v = static_cast<float>(rng.uniform01());
  for (int i = 0; i < side; ++i) k_tau[geo.index({i, i})] = 1;
  const std::vector<Cell> uavs = uav_cells(side);
  for (auto _ : state) {
    pheromesh::core::reference_diffuse(geo, tau, k_tau, p.e_tau, p.g_tau, p.d_tau, false, next);
    tau.swap(next);
    pheromesh::core::reference_diffuse(geo, eps, k_eps, p.e_eps, p.g_eps, p.d_eps, true, next);
    eps.swap(next);
    for (int32_t y = 0; y < side; ++y) {
      for (int32_t x = 0; x < side; ++x) {
        double delta = 0.0;
        for (const Cell& u : uavs) {
          const double dx = x - u.x;
          const double dy = y - u.y;
          delta += pheromesh::core::path_decrease(std::sqrt(dx * dx + dy * dy), p);  // Shao 2020 eq. (6), Shao 2020 eq. (7)
        }
        float& s = sigma[geo.index({x, y})];
        s = std::min(std::max(s - static_cast<float>(delta), static_cast<float>(p.sigma_min)),
                     static_cast<float>(p.sigma0));  // Shao 2020 eq. (5), Shao 2020 eq. (8)
      }
    }
    benchmark::DoNotOptimize(tau.data());
    benchmark::DoNotOptimize(eps.data());
    benchmark::DoNotOptimize(sigma.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * int64_t{side} * side);
}

// For scale: copying the three float layers once.
void BM_MemcpyLayers(benchmark::State& state) {
  const auto side = static_cast<std::size_t>(state.range(0));
  const std::size_t bytes = 3 * side * side * sizeof(float);
  std::vector<char> src(bytes, 1), dst(bytes, 0);
  for (auto _ : state) {
    std::memcpy(dst.data(), src.data(), bytes);
    benchmark::DoNotOptimize(dst.data());
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(state.iterations() * static_cast<int64_t>(bytes));
}

BENCHMARK(BM_RegionFieldStep)->Args({100, 0})->Args({400, 0})->Args({100, 1})->Args({400, 1});
BENCHMARK(BM_NaiveStep)->Arg(100)->Arg(400);
BENCHMARK(BM_MemcpyLayers)->Arg(100)->Arg(400);

}  // namespace

BENCHMARK_MAIN();
