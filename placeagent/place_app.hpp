// pheromesh-place: owns the pheromone tiles of one region (the software twin
// of an RFID tag / unattended ground sensor). The logic is core::PlaceCore;
// this shell wires it to the bus and a clock.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/core/place_core.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/runtime/commands.hpp"
#include "pheromesh/runtime/process.hpp"

namespace spdlog {
class logger;
}

namespace pheromesh::placeagent {

struct PlaceConfig {
  runtime::CommonOptions common;
  core::RegionId region = 0;
  uint32_t max_ticks = 0;  // 0: run until SIGINT/SIGTERM (realtime clock)
};

class PlaceApp {
 public:
  PlaceApp(PlaceConfig cfg, core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus);
  int run();

 private:
  int run_realtime();
  int run_lockstep();
  // One tick. `wait_for_halos`: wait (bounded) for every neighbour's ring of
  // this tick (lockstep); otherwise use the latest ring received.
  // `expected_deposits` (lockstep): wait (bounded) until this many deposits
  // of `tick` have arrived before applying them.
  void step(uint32_t tick, bool wait_for_halos, bool all_tiles, std::optional<uint32_t> expected_deposits = {});
  void publish_health(uint32_t tick, bool finished);
  void log_summary(uint32_t tick);

  PlaceConfig cfg_;
  core::ScenarioConfig scenario_;
  core::MapGeometry geo_;
  std::unique_ptr<bus::Bus> bus_;
  std::shared_ptr<spdlog::logger> log_;
  core::PlaceCore core_;
  uint64_t halos_missing_ = 0;
  double rate_ = 0.0;
  std::vector<core::DepositMsg> inbox_;
  std::vector<core::HaloMsg> halo_inbox_;
  std::vector<core::TargetEventMsg> events_;
  std::vector<core::TileMsg> tiles_out_;
  std::vector<std::string> rejections_;
  std::unique_ptr<runtime::SwarmCommands> commands_;  // pause / resume
};

}  // namespace pheromesh::placeagent
