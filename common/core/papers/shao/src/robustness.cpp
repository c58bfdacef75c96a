// Shao 2020 Sec. 4.3.3 robustness runs: UAVs killed mid-search, pheromone search
// against the fixed-route lawnmower (robustness.hpp has the reading).
#include "pheromesh/shao/robustness.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include "pheromesh/core/rng.hpp"
#include "pheromesh/core/simulator.hpp"

namespace pheromesh::core {

uint32_t kill_count(double share, uint32_t uavs) {
  if (!(share > 0)) return 0;
  const double n = std::round(std::min(share, 1.0) * static_cast<double>(uavs));
  return static_cast<uint32_t>(std::min<double>(n, uavs));
}

std::vector<uint32_t> draw_killed_uavs(uint64_t seed, uint32_t uavs, uint32_t count) {
  std::vector<uint32_t> ids(uavs);
  std::iota(ids.begin(), ids.end(), 0U);
  count = std::min(count, uavs);
  Rng rng(stream_seed(seed, "faults", 0));
  for (uint32_t j = 0; j < count; ++j) {
    const uint32_t pick = j + rng.uniform_below(uavs - j);
    std::swap(ids[j], ids[pick]);
  }
  ids.resize(count);
  std::sort(ids.begin(), ids.end());
  return ids;
}

FaultSchedule uav_kill_schedule(const std::vector<uint32_t>& uavs, uint32_t tick) {
  FaultSchedule s;
  for (uint32_t u : uavs) {
    FaultEvent e;
    e.action = FaultAction::Kill;
    e.targets = {{"uav", u}};
    e.at_tick = tick;
    e.text = "kill uav:" + std::to_string(u) + " @" + std::to_string(tick) + "t";
    s.events.push_back(std::move(e));
  }
  return s;
}

RobustnessRun run_robustness(const ScenarioConfig& base, ShaoRoute route, double share, uint64_t seed,
                             uint32_t kill_tick, double goal) {
  if (base.policy != ShaoSearchConfig::kPolicy) {
    throw std::invalid_argument("scenario '" + base.name + "' does not run the Shao search");
  }
  ScenarioConfig s = base;
  s.seed = seed;
  ShaoSearchConfig cfg;
  cfg.route = route;
  s.set_policy_config(cfg);
  RobustnessRun out;
  out.route = route;
  out.kill_share = share;
  out.seed = seed;
  out.kill_tick = kill_tick;
  out.killed = draw_killed_uavs(seed, s.uavs, kill_count(share, s.uavs));
  Simulator sim(s);
  if (!out.killed.empty()) {
    auto set = sim.set_faults(uav_kill_schedule(out.killed, kill_tick), false);
    if (!set) throw std::invalid_argument(set.error().message);
  }
  out.coverage.reserve(s.ticks + 1);
  sim.run([&](uint32_t t) {
    const double c = sim.recorder().coverage().coverage();
    out.coverage.push_back(c);
    if (!out.reached && c >= goal) out.reached = t;
  });
  out.targets_found = static_cast<uint32_t>(sim.recorder().acquisitions().found());
  out.deposits_sent = sim.recorder().deposits_sent();
  out.deposits_lost = sim.recorder().deposits_lost();
  return out;
}

}  // namespace pheromesh::core
