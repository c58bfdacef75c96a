// pheromesh-place: owns the pheromone tiles of one region (the software twin
// of an RFID tag / unattended ground sensor).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/core/layers.hpp"
#include "pheromesh/core/marks.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/runtime/process.hpp"

namespace spdlog {
class logger;
}

namespace pheromesh::placeagent {

struct PlaceConfig {
  runtime::CommonOptions common;
  core::RegionId region = 0;
  uint32_t max_ticks = 0;  // 0: run until SIGINT/SIGTERM
};

// Accounting of deposits, with the reason of every rejection.
struct DepositLedger {
  uint64_t received = 0;
  uint64_t applied = 0;
  std::map<std::string, uint64_t> rejected_by_reason;
  [[nodiscard]] uint64_t rejected() const;
};

class PlaceApp {
 public:
  PlaceApp(PlaceConfig cfg, core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus);
  int run();

  // One tick, exposed for tests: apply deposits, advance timers, exchange
  // halos, update the layers, publish.
  void step();

 private:
  void apply_deposits();
  void exchange_halos(const core::HaloRing& own);
  void publish_tiles(bool force);
  void publish_health(bool finished);

  PlaceConfig cfg_;
  core::ScenarioConfig scenario_;
  core::MapGeometry geo_;
  std::unique_ptr<bus::Bus> bus_;
  std::shared_ptr<spdlog::logger> log_;
  core::RegionField field_;
  core::TargetMarks marks_;
  std::vector<core::TileCoord> tiles_;
  std::vector<core::RegionId> neighbours_;
  std::map<core::RegionId, uint32_t> halo_seen_tick_;
  std::map<uint32_t, uint32_t> last_seq_;  // per UAV: highest applied deposit seq
  std::map<std::pair<int, int>, std::vector<float>> published_;  // (tile index, layer) -> values last sent
  DepositLedger ledger_;
  uint64_t halos_missing_ = 0;
  uint32_t tick_ = 0;
  double rate_ = 0.0;
  std::vector<core::DepositMsg> inbox_;
  std::vector<core::HaloMsg> halo_inbox_;
};

}  // namespace pheromesh::placeagent
