// Lockstep: when a place agent relays its gateway UAVs' states and the
// reports it made of them (core::UplinkReports) to the ground station. A
// place agent that answers in its receive thread takes one state a round,
// and relayed each in a sample of its own: one sample per UAV tick to the
// conductor. The conductor's UAV phase ends with the last report of all, so
// the reports of one UAV phase lose nothing by going together: the batch
// goes once every gateway UAV that reported the phase before has reported
// this one (the newest held), and at once on a departure or after `bound`
// (a UAV that stopped answering; the conductor waits for it anyway, until
// its departure). Time is passed in.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <span>

namespace pheromesh::core {

class RelayBatch {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr std::chrono::milliseconds kDefaultBound{200};

  explicit RelayBatch(std::chrono::milliseconds bound = kDefaultBound) : bound_(bound) {}

  // The report of `uav`'s UAV phase `tick` joined the batch at `now`.
  void add_report(uint32_t uav, uint32_t tick, Clock::time_point now);
  // A departure joined the batch: it goes at once.
  void add_departure() { departure_ = true; }
  // Whether the batch goes now, of a place agent whose gateway UAVs are
  // `gateway`: yes when it holds no report (states alone wait for nothing),
  // a departure, a report of an older phase than the newest (the conductor
  // may wait for it), a report held for `bound`, or when every gateway UAV
  // that reported the phase before the newest held has reported that one.
  // A UAV that never reported, or not since two phases, is not waited for.
  [[nodiscard]] bool due(std::span<const uint32_t> gateway, Clock::time_point now) const;
  // The batch went: it holds nothing (the UAVs' last reports are kept).
  void sent();

 private:
  std::chrono::milliseconds bound_;
  std::map<uint32_t, uint32_t> last_;  // UAV -> the newest tick it reported
  std::optional<Clock::time_point> since_;
  uint32_t newest_ = 0;  // of the reports held
  bool departure_ = false;
  bool older_ = false;  // a report of an older phase than the newest held
};

}  // namespace pheromesh::core
