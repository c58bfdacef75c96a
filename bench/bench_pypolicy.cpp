// What a Python step costs per UAV tick against the same policy in C++
// (docs/python.md, "What a Python step costs"): examples/python's
// repulsive_coverage.py and the C++ plugin examples/repulsive_coverage, the
// same algorithm, measured in the same run.
//
//   pheromesh-bench-pypolicy [--steps N] [--ticks T]
//
// 1. step: one UAV's policy stepped N times over a full view of the map (every
//    tile arrived, the same value everywhere: the policy weighs all 8
//    neighbours each tick); the time per step() call.
// 2. sim: the example scenario in the simulator (6 UAVs, 4 place agents,
//    T ticks); the time per UAV tick, place agents included (their work is the
//    same for both).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <regex>
#include <string>
#include <vector>
#include <fstream>
#include <sstream>
#include <filesystem>

#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"
#include "pheromesh/pypolicy/enable.hpp"

using namespace pheromesh;
namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

core::ScenarioConfig load(const std::string& path) {
  auto s = core::load_scenario(path);
  if (!s) {
    std::fprintf(stderr, "%s\n", s.error().message.c_str());
    std::exit(2);
  }
  return std::move(s).value();
}

// Each figure is the median of this many timings: a shared machine's
// scheduler moves single ones by a factor of two and more.
constexpr int kRepeats = 5;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Nanoseconds per step() of UAV 0 over a view of every tile of the map (the
// median of kRepeats timings of `steps` steps).
double ns_per_step(const core::ScenarioConfig& s, int steps) {
  const core::MapGeometry geo = s.geometry();
  const core::World world(geo, s.obstacles, s.targets);
  const core::PolicyTraits traits = core::policy_traits(s);
  core::TileCache tiles(geo, static_cast<int>(traits.layers.size()));
  for (int32_t ty = 0; ty < geo.tiles_y(); ++ty) {
    for (int32_t tx = 0; tx < geo.tiles_x(); ++tx) {
      const core::Rect r = geo.tile_rect({tx, ty});
      core::TileMsg m;
      m.layer = 0;
      m.tile = {tx, ty};
      m.region = geo.region_of_tile({tx, ty});
      m.width = static_cast<uint16_t>(r.w);
      m.height = static_cast<uint16_t>(r.h);
      m.values.assign(static_cast<std::size_t>(r.w * r.h), 1.0F);
      tiles.update(m);
    }
  }
  auto uav = core::make_uav_policy(s, geo, world, 0);
  core::UavActions out;
  const auto run = [&](int n, uint32_t first) {
    for (int i = 0; i < n; ++i) {
      out.clear();
      const core::UavView view{first + static_cast<uint32_t>(i), &tiles, {}, {}};
      uav->step(view, out);
    }
  };
  run(steps / 10 + 1, 0);  // warm up (tick 0 starts the policy)
  std::vector<double> ns;
  for (int rep = 0; rep < kRepeats; ++rep) {
    const auto t0 = Clock::now();
    run(steps, 1000 + static_cast<uint32_t>(rep * steps));
    const auto t1 = Clock::now();
    ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / steps);
  }
  return median(ns);
}

// Nanoseconds per UAV tick of a whole simulator run (the median of kRepeats runs).
double ns_per_uav_tick_sim(core::ScenarioConfig s, uint32_t ticks) {
  s.ticks = ticks;
  const uint32_t uavs = s.uavs;
  std::vector<double> ns;
  for (int rep = 0; rep < kRepeats; ++rep) {
    core::Simulator sim(s);
    const auto t0 = Clock::now();
    sim.run();
    const auto t1 = Clock::now();
    ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / (static_cast<double>(uavs) * (ticks + 1)));
  }
  return median(ns);
}

}  // namespace

int main(int argc, char** argv) {
  pypolicy::enable_python_policies();
  int steps = 20000;
  uint32_t ticks = 400;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--steps") {
      steps = std::atoi(argv[i + 1]);
    } else if (a == "--ticks") {
      ticks = static_cast<uint32_t>(std::atoi(argv[i + 1]));
    } else {
      std::fprintf(stderr, "usage: pheromesh-bench-pypolicy [--steps N] [--ticks T]\n");
      return 2;
    }
  }
  if (steps < 10 || ticks < 1) {
    std::fprintf(stderr, "--steps must be >= 10 and --ticks >= 1\n");
    return 2;
  }
  // The C++ plugin's scenario with the library built beside this program.
  const fs::path tmp = fs::temp_directory_path() / ("phm-bench-pypolicy-" + std::to_string(::getpid()));
  fs::create_directories(tmp);
  std::string text = slurp(PHEROMESH_SOURCE_DIR "/examples/repulsive_coverage/repulsive-coverage.textproto");
  text = std::regex_replace(text, std::regex("library: \"[^\"]*\""), "library: \"" PHEROMESH_BENCH_PLUGIN "\"");
  std::ofstream((tmp / "cpp.textproto").string()) << text;
  const core::ScenarioConfig cpp = load((tmp / "cpp.textproto").string());
  fs::remove_all(tmp);
  const core::ScenarioConfig py = load(PHEROMESH_SOURCE_DIR "/examples/python/repulsive-coverage-python.textproto");

  const double step_cpp = ns_per_step(cpp, steps);
  const double step_py = ns_per_step(py, steps);
  const double sim_cpp = ns_per_uav_tick_sim(cpp, ticks);
  const double sim_py = ns_per_uav_tick_sim(py, ticks);
  std::printf("repulsive coverage, one UAV's step() over a full view (median of %d x %d steps each):\n", kRepeats,
              steps);
  std::printf("  C++ plugin  %10.0f ns/step\n  Python      %10.0f ns/step\n  ratio       %10.1f x\n", step_cpp,
              step_py, step_py / step_cpp);
  std::printf("the example scenario in the simulator (%u UAVs, %u ticks, median of %d runs; place agents included):\n",
              cpp.uavs, ticks, kRepeats);
  std::printf("  C++ plugin  %10.0f ns/UAV tick\n  Python      %10.0f ns/UAV tick\n  ratio       %10.1f x\n", sim_cpp,
              sim_py, sim_py / sim_cpp);
  return 0;
}
