#include "pheromesh/core/writer_latch.hpp"

namespace pheromesh::core {

bool WriterLatch::allows(uint32_t key, uint64_t writer, Clock::time_point now) const {
  if (writer == 0) return true;
  const auto it = held_.find(key);
  if (it == held_.end() || it->second.writer == writer) return true;
  return takeover_after_ && now - it->second.last >= *takeover_after_;
}

void WriterLatch::hold(uint32_t key, uint64_t writer, Clock::time_point now) {
  if (writer != 0) held_[key] = Held{writer, now};
}

void WriterLatch::heard(uint32_t key, uint64_t writer, Clock::time_point now) {
  const auto it = held_.find(key);
  if (it != held_.end() && writer != 0 && it->second.writer == writer) it->second.last = now;
}

std::optional<uint64_t> WriterLatch::holder(uint32_t key) const {
  const auto it = held_.find(key);
  if (it == held_.end()) return std::nullopt;
  return it->second.writer;
}

}  // namespace pheromesh::core
