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

bool SeenDeposits::seen_before(uint32_t uav, uint32_t seq) {
  auto& seen = seen_[uav];
  if (!seen.insert(seq).second) return true;
  if (seen.size() > window_) seen.erase(seen.begin());
  return false;
}

DepositRoute DepositDesk::take(const DepositMsg& d, uint32_t tick) {
  const bool home =
      (home_region(d.uav, regions_) == region_ || served_.contains(d.uav)) && !check_uav_id(d.uav, swarm_);
  // What this replica received from its own UAVs, confirmed in their views.
  if (home) acks_.received(d.uav, d.seq, tick);
  const bool copy = seen_.seen_before(d.uav, d.seq);
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
