// What the two vendor buses share beyond the Bus interface: the departure
// lists, the statistics, refusing over-bound samples, a UAV's home, and the
// pace of keeping manual-by-topic writers alive.
#pragma once

#include <spdlog/spdlog.h>

#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "pheromesh/bus/bus.hpp"

namespace pheromesh::bus {

class VendorBus : public Bus {
 public:
  void take_departed_uavs(std::vector<uint32_t>& out) final;
  void take_departed_regions(std::vector<uint32_t>& out) final;
  [[nodiscard]] BusStats stats() const final { return stats_; }

 protected:
  explicit VendorBus(const BusOptions& o) : opt_(o), log_(spdlog::default_logger()) {}

  // Counts and logs a sample not written because it is over an IDL bound.
  bool refuse(const char* what, std::size_t n);
  // Refuses (counts, logs) a view or field over an IDL bound; true if within.
  bool view_fits(const core::ViewMsg& m);
  bool field_fits(const core::FieldMsg& m);
  // True at most four times per liveliness lease (see qos.hpp).
  bool keep_alive_due();

  BusOptions opt_;
  std::shared_ptr<spdlog::logger> log_;
  std::vector<uint32_t> departed_uavs_;
  std::vector<uint32_t> departed_regions_;  // core::place_id
  BusStats stats_;
  std::optional<core::RegionId> home_;  // a UAV's home place agent (join_uav)

 private:
  std::chrono::steady_clock::time_point last_keep_alive_{};
};

}  // namespace pheromesh::bus
