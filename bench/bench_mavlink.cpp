// What --mavlink costs the ground station (docs/mavlink.md), beside what it
// already does: one round of console::MavlinkFeed (every UAV's
// GLOBAL_POSITION_INT, ATTITUDE and ADSB_VEHICLE, the first 250's
// HEARTBEATs, packed into datagrams; no socket) against the run recorder
// taking one state of every UAV (core::RunRecorder::on_uav_state, what the
// intake does every tick), for swarms of 100 and 1000 UAVs.
//
// items_per_second = UAVs per second. After the table it prints the ratio
// feed round / recorder round and the share of one core the feed takes at
// the default 4 Hz with a 10 Hz swarm.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>
#include <map>
#include <string>

#include "pheromesh/console/mavlink_feed.hpp"
#include "pheromesh/core/run_metrics.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/world.hpp"

namespace {

using namespace pheromesh;

core::ScenarioConfig swarm(int uavs) {
  auto r = core::parse_scenario("map { width: 200 height: 200 }\nswarm { uavs: " + std::to_string(uavs) +
                                    " }\ngeo { origin_lat_deg: 47.4 origin_lon_deg: 8.5 cell_size_m: 2 }\n",
                                "bench.textproto");
  if (!r.ok()) {
    std::fprintf(stderr, "%s\n", r.error().message.c_str());
    std::abort();
  }
  return r.value();
}

core::UavStateMsg state(uint32_t id, uint32_t tick) {
  core::UavStateMsg s;
  s.uav = id;
  s.tick = tick;
  s.x = static_cast<double>((id * 7 + tick) % 200);
  s.y = static_cast<double>((id * 3) % 200);
  s.vx = 1.0;
  return s;
}

std::map<std::string, double> g_ns_per_round;

void BM_RecorderRound(benchmark::State& st) {
  const auto n = static_cast<uint32_t>(st.range(0));
  const core::ScenarioConfig s = swarm(static_cast<int>(n));
  const core::MapGeometry geo = s.geometry();  // World keeps a pointer to it
  const core::World world(geo, s.obstacles, s.targets);
  core::RunRecorder rec(s, world);
  uint32_t tick = 1000;
  for (auto _ : st) {
    ++tick;
    for (uint32_t id = 0; id < n; ++id) benchmark::DoNotOptimize(rec.on_uav_state(state(id, tick)));
  }
  st.SetItemsProcessed(static_cast<int64_t>(st.iterations()) * n);
}

void BM_FeedRound(benchmark::State& st) {
  const auto n = static_cast<uint32_t>(st.range(0));
  const core::ScenarioConfig s = swarm(static_cast<int>(n));
  const core::MapGeometry geo = s.geometry();  // World keeps a pointer to it
  const core::World world(geo, s.obstacles, s.targets);
  core::RunRecorder rec(s, world);
  for (uint32_t id = 0; id < n; ++id) rec.on_uav_state(state(id, 1000));
  const auto t0 = std::chrono::steady_clock::now();
  console::MavlinkFeed feed(s, 4.0, t0);
  auto now = t0;
  std::size_t bytes = 0;
  for (auto _ : st) {
    now += std::chrono::milliseconds(250);  // every call is a position round; every fourth has heartbeats too
    for (const auto& d : feed.due(rec, now)) bytes += d.size();
  }
  st.SetItemsProcessed(static_cast<int64_t>(st.iterations()) * n);
  st.counters["bytes_per_round"] = static_cast<double>(bytes) / static_cast<double>(st.iterations());
}

BENCHMARK(BM_RecorderRound)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FeedRound)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);

class Keep : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      if (r.iterations > 0 && r.run_type == Run::RT_Iteration) {
        const double ns_per_iter = r.GetAdjustedCPUTime() * 1e3;  // CPU time: the machine may be shared; the unit is µs
        g_ns_per_round[r.benchmark_name()] = ns_per_iter;
      }
    }
    ConsoleReporter::ReportRuns(runs);
  }
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  Keep reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  for (const int n : {100, 1000}) {
    const std::string arg = "/" + std::to_string(n);
    const double feed = g_ns_per_round["BM_FeedRound" + arg], rec = g_ns_per_round["BM_RecorderRound" + arg];
    if (feed <= 0 || rec <= 0) continue;
    // A 10 Hz swarm: the recorder takes 10 rounds a second, the feed 4.
    std::printf(
        "%4d UAVs: feed round / recorder round %.2f; at 4 Hz the feed takes %.2f %% of a core (the recorder "
        "at 10 Hz %.2f %%)\n",
        n, feed / rec, 4 * feed / 1e7, 10 * rec / 1e7);
  }
  benchmark::Shutdown();
  return 0;
}
