#include "pheromesh/core/lockstep_follower.hpp"

#include <algorithm>
#include <map>
#include <optional>

namespace pheromesh::core {

std::vector<ClockMsg> LockstepFollower::offer(std::vector<ClockMsg>& taken, Clock::time_point now,
                                              std::vector<ClockMsg>* accepted_out) {
  std::vector<ClockMsg> refused;
  bool accepted = false;
  for (auto& c : taken) {
    if (std::find(latched_.begin(), latched_.end(), c.writer) == latched_.end()) {
      // A Stop latches nobody: the conductor (and every relay of it) sends
      // the Ready clock first and re-sends it until every process has
      // answered, so its Stop comes from a writer already heard. A forged
      // Stop written before the conductor's first clock was latched and
      // ended the run at tick 0 (issue 28).
      if (latched_.size() >= sources_ || c.phase == static_cast<uint8_t>(ClockPhase::Stop)) {
        refused.push_back(std::move(c));
        continue;
      }
      latched_.push_back(c.writer);
    }
    accepted = true;
    newest_tick_ = std::max(newest_tick_, c.tick);
    for (RegionId r : c.absent) absent_.emplace(r, c.tick);
    if (accepted_out != nullptr) accepted_out->push_back(c);
    pending_.push_back(std::move(c));
  }
  taken.clear();
  if (accepted) watch_.on_clock(now);
  return refused;
}

std::optional<ClockMsg> LockstepFollower::next_phase() {
  while (!pending_.empty() && !stopped_) {
    ClockMsg c = std::move(pending_.front());
    pending_.pop_front();
    if (c.phase == static_cast<uint8_t>(ClockPhase::Stop)) {
      stopped_ = true;
      break;
    }
    if (c.phase != static_cast<uint8_t>(mine_) || (done_ && c.tick <= *done_)) continue;
    return c;
  }
  return std::nullopt;
}

std::optional<uint32_t> LockstepFollower::absent_since(RegionId r) const {
  auto it = absent_.find(r);
  if (it == absent_.end()) return std::nullopt;
  return it->second;
}

std::optional<ClockMsg> uav_clock_begun_by(const ClockMsg& c) {
  if (!c.next_uav_phase || c.phase != static_cast<uint8_t>(ClockPhase::Place)) return std::nullopt;
  ClockMsg u;
  u.tick = c.tick + 1;
  u.phase = static_cast<uint8_t>(ClockPhase::Uav);
  u.broadcasts = c.broadcasts;
  u.occupancy = c.occupancy;
  u.absent = c.absent;
  u.writer = c.writer;
  return u;
}

UavClockRelay::To UavClockRelay::relays(const ClockMsg& c) {
  bool new_absent = false;
  for (RegionId r : c.absent) {
    if (std::find(absent_.begin(), absent_.end(), r) == absent_.end()) {
      absent_.push_back(r);
      new_absent = true;
    }
  }
  const auto newest = newest_.find(c.phase);
  const bool resent = newest != newest_.end() && c.tick <= newest->second;
  if (!resent) newest_[c.phase] = c.tick;
  const bool needed = resent || new_absent;
  switch (static_cast<ClockPhase>(c.phase)) {
    case ClockPhase::Uav:
      return {true, needed || !absent_.empty()};
    case ClockPhase::Place:
      return {needed, needed};
    case ClockPhase::Ready:
    case ClockPhase::Stop:
      break;
  }
  return {true, true};
}

}  // namespace pheromesh::core
