#include "pheromesh/core/place_vouch.hpp"

namespace pheromesh::core {

bool PlaceVouch::claim(uint32_t id, uint64_t participant, Clock::time_point now, bool new_life) {
  if (participant == 0) return true;
  bool may = latch_.allows(id, participant, now);
  if (!may && new_life) {
    const auto last = latch_.last_heard(id);
    may = !last || now - *last >= kNewLifeSilence;
  }
  if (may) latch_.hold(id, participant, now);
  return may;
}

bool PlaceVouch::speaks_for(uint32_t id, uint64_t participant) const {
  if (participant == 0) return true;
  const auto holder = latch_.holder(id);
  return !holder || *holder == participant;
}

}  // namespace pheromesh::core
