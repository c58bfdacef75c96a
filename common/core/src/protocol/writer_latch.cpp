#include "pheromesh/core/writer_latch.hpp"

namespace pheromesh::core {

bool WriterLatch::allows(uint32_t key, uint64_t writer, Clock::time_point now) const {
  if (writer == 0) return true;
  const auto it = held_.find(key);
  if (it == held_.end() || it->second.writer == writer || it->second.open) return true;
  return takeover_after_ && now - it->second.last >= *takeover_after_;
}

void WriterLatch::hold(uint32_t key, uint64_t writer, Clock::time_point now) {
  if (writer == 0) return;
  Held& h = held_[key];  // a new entry holds writer 0, which no count names
  if (h.writer != 0) drop_holder(h.writer);
  h = Held{writer, now};
  ++keys_of_[writer];
}

void WriterLatch::release(uint32_t key) {
  const auto it = held_.find(key);
  if (it == held_.end()) return;
  drop_holder(it->second.writer);
  held_.erase(it);
}

void WriterLatch::open(uint32_t key) {
  const auto it = held_.find(key);
  if (it != held_.end()) it->second.open = true;
}

void WriterLatch::drop_holder(uint64_t writer) {
  const auto it = keys_of_.find(writer);
  if (it != keys_of_.end() && --it->second == 0) keys_of_.erase(it);
}

void WriterLatch::heard(uint32_t key, uint64_t writer, Clock::time_point now) {
  const auto it = held_.find(key);
  if (it == held_.end() || writer == 0 || it->second.writer != writer) return;
  it->second.last = now;
  it->second.open = false;
}

bool WriterLatch::held(uint32_t key, Clock::time_point now) const {
  const auto it = held_.find(key);
  if (it == held_.end()) return false;
  return !takeover_after_ || now - it->second.last < *takeover_after_;
}

std::optional<uint64_t> WriterLatch::holder(uint32_t key) const {
  const auto it = held_.find(key);
  if (it == held_.end()) return std::nullopt;
  return it->second.writer;
}

std::optional<WriterLatch::Clock::time_point> WriterLatch::last_heard(uint32_t key) const {
  const auto it = held_.find(key);
  if (it == held_.end()) return std::nullopt;
  return it->second.last;
}

}  // namespace pheromesh::core
