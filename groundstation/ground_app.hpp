// pheromesh-ground (headless): subscribes to everything, prints progress,
// computes the run metrics and writes metrics.json at the end.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/core/marks.hpp"
#include "pheromesh/core/metrics.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/world.hpp"
#include "pheromesh/runtime/process.hpp"

namespace spdlog {
class logger;
}

namespace pheromesh::groundstation {

struct GroundConfig {
  runtime::CommonOptions common;
  std::string out_dir = ".";
  uint32_t expect_uavs = 0;      // 0: the scenario's swarm.uavs
  double progress_period_s = 1.0;
};

class GroundApp {
 public:
  GroundApp(GroundConfig cfg, core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus);
  int run();
  [[nodiscard]] nlohmann::json metrics() const;

 private:
  void poll();
  void print_progress();

  struct UavInfo {
    core::UavStateMsg last{};
    bool alive = true;
    bool finished = false;
  };

  GroundConfig cfg_;
  core::ScenarioConfig scenario_;
  core::MapGeometry geo_;
  core::World world_;
  std::unique_ptr<bus::Bus> bus_;
  std::shared_ptr<spdlog::logger> log_;
  core::CoverageTracker coverage_;
  core::AcquisitionTracker acquisitions_;
  std::vector<uint32_t> revisit_response_;
  std::map<uint32_t, UavInfo> uavs_;
  std::map<core::RegionId, core::HealthMsg> health_;
  std::map<core::RegionId, bool> region_departed_;
  uint32_t max_tick_ = 0;
  uint64_t samples_rejected_ = 0;
  std::vector<std::pair<uint32_t, double>> coverage_series_;  // (tick, coverage)
  // reusable inboxes
  std::vector<core::UavStateMsg> states_;
  std::vector<core::DetectionMsg> detections_;
  std::vector<core::TargetEventMsg> events_;
  std::vector<core::HealthMsg> healths_;
  std::vector<core::TileMsg> tiles_;
};

}  // namespace pheromesh::groundstation
