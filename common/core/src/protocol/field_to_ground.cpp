#include "pheromesh/core/field_to_ground.hpp"

#include <algorithm>
#include <cmath>

namespace pheromesh::core {

FieldToGround::FieldToGround(uint32_t every, uint32_t full_every)
    : every_(std::max<uint32_t>(1, every)), full_every_(std::max<uint32_t>(1, full_every)) {}

FieldToGround FieldToGround::at_rate(double tick_rate_hz, double field_hz) {
  const double per = field_hz > 0 ? tick_rate_hz / field_hz : 1.0;
  const auto every = static_cast<uint32_t>(std::max(1.0, std::round(per)));
  // Sends per 2 s, at least one.
  const double sends_hz = tick_rate_hz / every;
  const auto full_every = static_cast<uint32_t>(std::max(1.0, std::round(2.0 * sends_hz)));
  return {every, full_every};
}

bool FieldToGround::due(uint32_t tick, bool last) const { return last || tick % every_ == 0; }

void FieldToGround::select(const std::vector<TileMsg>& all, bool last, std::vector<TileMsg>& out) {
  const bool full = last || sends_ % full_every_ == 0;
  ++sends_;
  for (const auto& t : all) {
    auto& before = sent_[{t.tile.tx, t.tile.ty, t.layer}];
    if (!full && before == t.values) continue;
    before = t.values;
    out.push_back(t);
  }
}

}  // namespace pheromesh::core
