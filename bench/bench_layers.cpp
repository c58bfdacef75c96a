// Pheromone layer step throughput and the simulator's cost against the map
// (issue 44), each beside a baseline measured in the same run:
//   * the region field (padded buffers, precomputed 1/|N| weights, vector
//     rows, chunks whose neighbourhood is all +0 skipped) against the naive
//     whole-map reference and a memcpy of the field's three float layers;
//     once on a dense field (every switch on: every cell computed, the worst
//     case) and once on the field of the scale maps (their obstacles and
//     targets switched on, stepped until the obstacle layer has spread);
//   * the simulator flying the same 50 UAVs over scale-100x100 and
//     scale-400x400 (UAV-steps per second, construction and the final
//     accounting not timed).
// After the table it prints the ratios: field step / memcpy of the same
// layers (cells per second) and simulator 400x400 / 100x100.
//
// items_per_second = map cells advanced by one full step (target, obstacle and
// path layers) per second for the field, UAV-steps per second for the
// simulator.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/layers.hpp"
#include "pheromesh/core/rng.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"

namespace {

using pheromesh::core::Cell;
using pheromesh::core::Layer;
using pheromesh::core::MapGeometry;
using pheromesh::core::Rect;
using pheromesh::core::RegionField;
using pheromesh::core::Rng;
using pheromesh::core::ScenarioConfig;
using pheromesh::core::ShaoLayerParams;
using pheromesh::core::Simulator;

constexpr int kUavs = 4;           // path visits per field step
constexpr uint32_t kSimUavs = 50;  // the same swarm on both maps
constexpr uint32_t kSimTicks = 100;
constexpr int kSpreadSteps = 100;  // steps before the scale field is timed

std::vector<Cell> uav_cells(int32_t side) {
  Rng rng(7);
  std::vector<Cell> out;
  for (int i = 0; i < kUavs; ++i) {
    out.push_back({static_cast<int32_t>(rng.uniform_below(static_cast<uint32_t>(side))),
                   static_cast<int32_t>(rng.uniform_below(static_cast<uint32_t>(side)))});
  }
  return out;
}

ScenarioConfig scale_scenario(int32_t side) {
  const std::string path = std::string(PHEROMESH_SOURCE_DIR) + "/scenarios/scale-" + std::to_string(side) + "x" +
                           std::to_string(side) + ".textproto";
  auto s = pheromesh::core::load_scenario(path);
  if (!s) {
    std::fprintf(stderr, "%s: %s\n", path.c_str(), s.error().message.c_str());
    std::exit(1);
  }
  return s.value();
}

void step_field(RegionField& field, const std::vector<Cell>& uavs) {
  for (const Cell& u : uavs) field.add_path_visit(u);
  benchmark::DoNotOptimize(field.begin_step());
  field.finish_step();
}

void time_field(benchmark::State& state, RegionField& field, int32_t side) {
  const std::vector<Cell> uavs = uav_cells(side);
  for (auto _ : state) {
    step_field(field, uavs);
    benchmark::DoNotOptimize(field.layer(Layer::Target).data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * int64_t{side} * side);
}

// Every cell switched on in both layers: every value stays a normal float
// above d, every chunk is computed at every step.
void BM_FieldStepDense(benchmark::State& state) {
  const auto side = static_cast<int32_t>(state.range(0));
  const MapGeometry geo(side, side, 10, 1, 1);
  RegionField field(geo, 0, ShaoLayerParams{});
  Rng rng(1);
  for (float& v : field.mutable_layer(Layer::Target)) v = static_cast<float>(rng.uniform01());
  for (float& v : field.mutable_layer(Layer::Obstacle)) v = static_cast<float>(rng.uniform01());
  for (int32_t y = 0; y < side; ++y) {
    for (int32_t x = 0; x < side; ++x) {
      field.set_target_switch({x, y}, true);
      field.set_obstacle_switch({x, y});
    }
  }
  time_field(state, field, side);
}

// The scale map's field once its UAVs have marked every obstacle and target:
// kε on every obstacle cell, kτ on every target, with the scenario's layer
// parameters, stepped kSpreadSteps times (the obstacle layer then reaches
// tens of cells around the obstacles, its edge in denormal floats).
void BM_FieldStepScaleMap(benchmark::State& state) {
  const auto side = static_cast<int32_t>(state.range(0));
  const ScenarioConfig s = scale_scenario(side);
  const MapGeometry geo(side, side, 10, 1, 1);
  RegionField field(geo, 0, s.layers);
  for (const Rect& o : s.obstacles) {
    for (int32_t y = o.y0; y < o.y0 + o.h; ++y) {
      for (int32_t x = o.x0; x < o.x0 + o.w; ++x) field.set_obstacle_switch({x, y});
    }
  }
  for (const Cell& t : s.targets) field.set_target_switch(t, true);
  const std::vector<Cell> uavs = uav_cells(side);
  for (int i = 0; i < kSpreadSteps; ++i) step_field(field, uavs);
  time_field(state, field, side);
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

// The simulator's ticks (kSimUavs UAVs, kSimTicks ticks) on a scale map.
void BM_Simulator(benchmark::State& state) {
  const auto side = static_cast<int32_t>(state.range(0));
  ScenarioConfig s = scale_scenario(side);
  s.uavs = kSimUavs;
  s.ticks = kSimTicks;
  int64_t steps = 0;
  for (auto _ : state) {
    state.PauseTiming();
    auto sim = std::make_unique<Simulator>(s);
    state.ResumeTiming();
    while (sim->advance()) {
    }
    steps += static_cast<int64_t>(sim->uav_steps());
    state.PauseTiming();
    sim.reset();
    state.ResumeTiming();
  }
  state.SetItemsProcessed(steps);
}

BENCHMARK(BM_FieldStepDense)->Arg(100)->Arg(400);
BENCHMARK(BM_FieldStepScaleMap)->Arg(100)->Arg(400);
BENCHMARK(BM_NaiveStep)->Arg(100)->Arg(400);
BENCHMARK(BM_MemcpyLayers)->Arg(100)->Arg(400);
BENCHMARK(BM_Simulator)->Arg(100)->Arg(400)->Unit(benchmark::kMillisecond);

// The console table, and each run's rate kept for the ratios.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& r : runs) {
      if (r.run_type != Run::RT_Iteration || r.error_occurred) continue;
      for (const char* counter : {"items_per_second", "bytes_per_second"}) {
        auto it = r.counters.find(counter);
        if (it != r.counters.end()) rate_[r.benchmark_name()] = it->second.value;
      }
    }
  }
  [[nodiscard]] double rate(const std::string& name) const {
    auto it = rate_.find(name);
    return it == rate_.end() ? 0.0 : it->second;
  }

 private:
  std::map<std::string, double> rate_;
};

void print_ratios(const RatioReporter& r) {
  std::printf("\nRatios (issue 44), each against a baseline of this run:\n");
  for (const int side : {100, 400}) {
    const std::string n = "/" + std::to_string(side);
    // A step rewrites three float layers: memcpy's bytes/s over 12 B per cell.
    const double memcpy_cells = r.rate("BM_MemcpyLayers" + n) / (3.0 * sizeof(float));
    if (memcpy_cells <= 0.0) continue;
    for (const char* bm : {"BM_FieldStepDense", "BM_FieldStepScaleMap"}) {
      const double cells = r.rate(bm + n);
      if (cells > 0.0) {
        std::printf("  %-22s %dx%d: %6.1f %% of memcpy of its three layers (cells/s)\n", bm, side, side,
                    100.0 * cells / memcpy_cells);
      }
    }
  }
  const double small = r.rate("BM_Simulator/100");
  const double large = r.rate("BM_Simulator/400");
  if (small > 0.0 && large > 0.0) {
    std::printf("  simulator, %u UAVs: %.0f UAV-steps/s at 100x100, %.0f at 400x400: 400x400 / 100x100 = %.2f\n",
                kSimUavs, small, large, large / small);
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  print_ratios(reporter);
  benchmark::Shutdown();
  return 0;
}
