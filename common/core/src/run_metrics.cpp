#include "pheromesh/core/run_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "pheromesh/core/policy.hpp"

namespace pheromesh::core {

std::vector<Cell> all_starts(const ScenarioConfig& s) {
  std::vector<Cell> out;
  for (uint32_t i = 0; i < s.uavs; ++i) out.push_back(start_cell(s, i));
  return out;
}

RunRecorder::RunRecorder(const ScenarioConfig& scenario, const World& world)
    : scenario_(&scenario),
      world_(&world),
      geo_(scenario.geometry()),
      coverage_(world, all_starts(scenario), policy_traits(scenario).sensor_radius),
      acquisitions_(scenario.targets.size()) {}

bool RunRecorder::on_uav_state(const UavStateMsg& s) {
  if (check_uav_state(s, geo_)) {
    ++samples_rejected_;
    return false;
  }
  auto& u = uavs_[s.uav];
  // Shao 2020 Sec. 5: the leader hands over to the search at the target region.
  if (!leader_arrival_ && u.last.role == static_cast<uint8_t>(Role::Leader) &&
      s.role == static_cast<uint8_t>(Role::Searcher)) {
    leader_arrival_ = s.tick;
  }
  // A UAV back after it was lost with a lower count is a restarted process:
  // its earlier life's deposits still count.
  if (!u.alive && s.deposits_sent < u.last.deposits_sent) u.earlier_lives_deposits += u.last.deposits_sent;
  u.last = s;
  u.alive = true;
  u.finished = u.finished || s.finished;
  max_tick_ = std::max(max_tick_, s.tick);
  coverage_.observe({static_cast<int32_t>(std::lround(s.x)), static_cast<int32_t>(std::lround(s.y))});
  return true;
}

bool RunRecorder::on_detection(const DetectionMsg& d) {
  last_was_first_ = false;
  if (d.target < 0 || static_cast<std::size_t>(d.target) >= acquisitions_.size()) {
    ++samples_rejected_;
    return false;
  }
  last_was_first_ = acquisitions_.acquire(d.target, d.tick);
  return true;
}

void RunRecorder::on_target_event(const TargetEventMsg& e) {
  if (e.kind == static_cast<uint8_t>(MarkEvent::Kind::Revisited)) revisits_.push_back(e);
}

void RunRecorder::on_health(const HealthMsg& h) { health_[h.region] = h; }

void RunRecorder::on_uav_departed(uint32_t uav) { uavs_[uav].alive = false; }

void RunRecorder::on_region_departed(RegionId r) { departed_regions_[r] = true; }

void RunRecorder::sample_coverage() { coverage_series_.emplace_back(max_tick_, coverage_.coverage()); }

std::vector<TargetEventMsg> RunRecorder::revisit_events() const {
  std::vector<TargetEventMsg> sorted = revisits_;
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) {
    return std::tie(a.tick, a.region, a.cell.y, a.cell.x) < std::tie(b.tick, b.region, b.cell.y, b.cell.x);
  });
  return sorted;
}

std::vector<uint32_t> RunRecorder::revisit_response_ticks() const {
  const std::vector<TargetEventMsg> sorted = revisit_events();
  std::vector<uint32_t> out;
  out.reserve(sorted.size());
  for (const auto& e : sorted) out.push_back(e.response_ticks);
  return out;
}

uint64_t RunRecorder::deposits_sent() const {
  uint64_t sent = 0;
  for (const auto& [id, u] : uavs_) sent += u.last.deposits_sent + u.earlier_lives_deposits;
  return sent;
}

uint64_t RunRecorder::deposits_lost() const {
  uint64_t received = 0;
  for (const auto& [r, h] : health_) received += h.deposits_received;
  const uint64_t sent = deposits_sent();
  return sent > received ? sent - received : 0;
}

}  // namespace pheromesh::core
