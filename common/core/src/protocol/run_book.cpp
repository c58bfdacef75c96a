#include "pheromesh/core/run_book.hpp"

#include <algorithm>
#include <limits>
#include <vector>

#include "pheromesh/core/plausibility.hpp"

namespace pheromesh::core {

std::chrono::milliseconds RunBook::start_bound() const {
  return std::chrono::milliseconds(static_cast<int64_t>(1000.0 * (30.0 + 0.1 * o_.uavs)));
}

RunBook::Discovery RunBook::note_discovery(Heard heard, Clock::time_point now) {
  Discovery d;
  const bool all = heard.uavs >= o_.uavs && heard.regions >= o_.regions && linked_.size() >= o_.regions;
  if (all && !discovery_s_) {
    discovery_s_ = seconds_since_launch(now);
    d.complete_s = discovery_s_;
  }
  if (start_sent_ || o_.role != Role::Starter) return d;
  if (!all && now - o_.started < start_bound()) return d;
  start_sent_ = true;
  d.start = all ? StartNow::EveryoneHeard : StartNow::WithoutSomeAfterBound;
  if (!all) {
    d.uavs_missing = o_.uavs - std::min<std::size_t>(o_.uavs, heard.uavs);
    d.regions_missing = o_.regions - std::min<std::size_t>(o_.regions, heard.regions);
    const std::size_t heard_regions = std::min<std::size_t>(o_.regions, heard.regions);
    d.regions_unlinked = heard_regions - std::min(heard_regions, linked_.size());
  }
  return d;
}

void RunBook::note_linked(RegionId r) {
  if (r < o_.regions) linked_.insert(r);
}

void RunBook::on_field_chunk(RegionId r, uint32_t tick, uint16_t chunk, uint16_t chunks) {
  if (r >= o_.regions) return;
  auto& [newest, seen] = field_ticks_[r];
  if (tick > newest || seen.empty()) {
    newest = tick;
    seen.clear();
  }
  if (tick == newest) seen.insert(chunk);
  field_chunks_[r] = chunks;
}

bool RunBook::holds_last_fields(uint32_t tick, const LockstepConductor& conductor) const {
  for (RegionId r = 0; r < o_.regions; ++r) {
    if (conductor.absent(r)) continue;
    auto it = field_ticks_.find(r);
    auto n = field_chunks_.find(r);
    if (it == field_ticks_.end() || n == field_chunks_.end() || it->second.first != tick ||
        it->second.second.size() < n->second) {
      return false;
    }
  }
  return true;
}

bool RunBook::uavs_done(const RunRecorder& rec, const LockstepConductor& conductor, Clock::time_point now) const {
  const auto& uavs = rec.uavs();
  if (uavs.size() < o_.uavs && !start_sent_) return false;
  if (uavs.empty()) return false;
  const auto done = [&](const auto& kv) {
    const auto& [id, u] = kv;
    if (u.finished || conductor.dropped(id)) return true;
    auto k = killed_.find(id);
    if (k != killed_.end()) {
      const auto heard = conductor.last_heard(id);
      if (!heard || *heard <= k->second) return true;  // not heard since the kill: no restart flies
    }
    // Lapsed liveliness alone is no end: a stopped process keeps its place
    // until the grace is over (as the lockstep conductor waits for it).
    return !u.alive && conductor.gone_for_good(id, now);
  };
  return std::all_of(uavs.begin(), uavs.end(), done);
}

bool RunBook::places_finished(const RunRecorder& rec) const {
  std::vector<uint8_t> heard(o_.regions, 0);
  for (const auto& [id, h] : rec.replica_health()) {
    const RegionId r = place_id_region(id);
    if (r >= heard.size()) continue;
    heard[r] = 1;
    if (!h.finished && !rec.place_departed(id)) return false;
  }
  for (RegionId r = 0; r < o_.regions; ++r) {
    if (heard[r] == 0 && !rec.region_departed(r)) return false;
  }
  return true;
}

std::optional<double> RunBook::note_full_state(Heard heard, Clock::time_point now) {
  if (full_state_noted_) return std::nullopt;
  if (heard.uavs < o_.uavs || heard.regions < o_.regions || field_ticks_.size() < o_.regions) return std::nullopt;
  full_state_noted_ = true;
  return seconds_since_launch(now);
}

uint32_t RunBook::tick_ceiling(Clock::time_point now) const {
  if (o_.role == Role::Conductor) return lockstep_tick_ceiling(conducted_tick_);
  if (o_.role == Role::Monitor || !o_.launched) return std::numeric_limits<uint32_t>::max();
  return realtime_tick_ceiling(seconds_since_launch(now), o_.tick_rate_hz, o_.launch_slack);
}

double RunBook::seconds_since_launch(Clock::time_point now) const {
  // Whole milliseconds, as the launch time is given.
  const auto elapsed = std::chrono::duration_cast<std::chrono::milliseconds>(now - o_.launched.value_or(o_.started));
  return static_cast<double>(elapsed.count()) / 1000.0;
}

}  // namespace pheromesh::core
