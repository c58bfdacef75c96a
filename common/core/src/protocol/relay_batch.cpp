#include "pheromesh/core/relay_batch.hpp"

#include <algorithm>

namespace pheromesh::core {

void RelayBatch::add_report(uint32_t uav, uint32_t tick, Clock::time_point now) {
  auto [it, fresh] = last_.try_emplace(uav, tick);
  if (!fresh) it->second = std::max(it->second, tick);
  if (since_ && tick < newest_) older_ = true;
  newest_ = since_ ? std::max(newest_, tick) : tick;
  if (!since_) since_ = now;
}

bool RelayBatch::due(std::span<const uint32_t> gateway, Clock::time_point now) const {
  if (!since_ || departure_ || older_ || now - *since_ >= bound_) return true;
  return std::all_of(gateway.begin(), gateway.end(), [&](uint32_t u) {
    const auto it = last_.find(u);
    if (it == last_.end() || it->second + 1 < newest_) return true;  // not expected in this phase
    return it->second >= newest_;
  });
}

void RelayBatch::sent() {
  since_.reset();
  newest_ = 0;
  departure_ = false;
  older_ = false;
}

}  // namespace pheromesh::core
