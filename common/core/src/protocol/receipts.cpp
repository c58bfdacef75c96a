#include "pheromesh/core/receipts.hpp"

#include <algorithm>

#include "pheromesh/core/plausibility.hpp"

namespace pheromesh::core {

void HomeAcks::received(uint32_t uav, uint32_t seq, uint32_t tick) {
  auto it = last_.find(uav);
  const auto last = it == last_.end() ? std::nullopt : std::optional<uint32_t>(it->second.first);
  const uint32_t since = tick - (it == last_.end() ? 0 : std::min(it->second.second, tick));
  if ((!last || seq > *last) && !check_seq_reachable(seq, last, since)) {
    last_[uav] = {seq, tick};
    first_.try_emplace(uav, seq);
  }
}

uint32_t HomeAcks::ack_from(uint32_t uav) const {
  auto it = first_.find(uav);
  return it == first_.end() ? 0 : it->second;
}

uint32_t HomeAcks::ack(uint32_t uav) const {
  auto it = last_.find(uav);
  return it == last_.end() ? 0 : it->second.first;
}

SeenDeposits::SeenDeposits(uint32_t window) : window_(std::max<uint32_t>(64, (window + 63) / 64 * 64)) {}

bool SeenDeposits::bit(const Window& w, uint32_t seq) const {
  const uint32_t i = seq % window_;
  return (w.bits[i / 64] >> (i % 64) & 1U) != 0;
}

void SeenDeposits::set_bit(Window& w, uint32_t seq, bool on) const {
  const uint32_t i = seq % window_;
  const uint64_t mask = uint64_t{1} << (i % 64);
  w.bits[i / 64] = on ? w.bits[i / 64] | mask : w.bits[i / 64] & ~mask;
}

bool SeenDeposits::seen(uint32_t uav, uint32_t seq) const {
  const auto it = seen_.find(uav);
  if (it == seen_.end()) return false;
  const Window& w = it->second;
  return seq <= w.top && w.top - seq < window_ && bit(w, seq);
}

bool SeenDeposits::seen_before(uint32_t uav, uint32_t seq, uint32_t tick) {
  auto it = seen_.find(uav);
  if (it == seen_.end()) {
    // A seq the UAV cannot have reached yet (check_seq_reachable) moves no
    // window: PlaceCore refuses it (seq_far_ahead). A forged 2^32-1 once
    // moved uav 0's window past every real seq, so a lockstep re-send of a
    // real deposit was not taken for a copy and PlaceCore rejected it as a
    // replay (fresh-clone suite).
    if (check_seq_reachable(seq, std::nullopt, tick)) return false;
    it = seen_.emplace(uav, Window{seq, tick, std::vector<uint64_t>(window_ / 64, 0)}).first;
  }
  Window& w = it->second;
  if (seq > w.top) {
    if (check_seq_reachable(seq, w.top, tick - std::min(w.top_tick, tick))) return false;
    // The window moves up to seq: the slots of (top, seq] are free again.
    if (seq - w.top >= window_) {
      std::fill(w.bits.begin(), w.bits.end(), 0);
    } else {
      for (uint32_t s = w.top + 1; s != seq; ++s) set_bit(w, s, false);
    }
    w.top = seq;
    w.top_tick = tick;
  } else if (w.top - seq >= window_) {
    return false;  // older than the window: too old to tell
  } else if (bit(w, seq)) {
    return true;
  }
  set_bit(w, seq, true);
  return false;
}

std::size_t SeenDeposits::bytes() const {
  std::size_t n = 0;
  for (const auto& [uav, w] : seen_) n += w.bits.capacity() * sizeof(uint64_t);
  return n;
}

DepositRoute DepositDesk::take(const DepositMsg& d, uint32_t tick) {
  const bool home =
      (home_region(d.uav, regions_) == region_ || served_.contains(d.uav)) && !check_uav_id(d.uav, swarm_);
  // What this replica received from its own UAVs, confirmed in their views.
  if (home) acks_.received(d.uav, d.seq, tick);
  const bool copy = seen_.seen_before(d.uav, d.seq, tick);
  if (home && !copy) ++taken_from_[d.uav];
  if (copy && drop_copies_) {
    ++copies_;
    return DepositRoute::Copy;
  }
  return d.region == region_ || d.region >= regions_ ? DepositRoute::Apply : DepositRoute::Forward;
}

uint64_t DepositDesk::taken_from(uint32_t uav) const {
  auto it = taken_from_.find(uav);
  return it == taken_from_.end() ? 0 : it->second;
}

}  // namespace pheromesh::core
