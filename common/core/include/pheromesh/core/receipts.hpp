// A UAV's account of its own deposits (docs/faults.md, "No silent loss"):
// each deposit it writes stays unconfirmed until a view from its home place
// agent says that agent received that sequence number (View.deposit_ack).
// What is still unconfirmed when the UAV ends is what it counts as lost.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>

namespace pheromesh::core {

class DepositReceipts {
 public:
  // Sequence numbers are strictly increasing per UAV (restarts continue above).
  void sent(uint32_t seq) { pending_.push_back(seq); }
  // The home place agent received every deposit up to `ack`.
  void confirmed(uint32_t ack) {
    while (!pending_.empty() && pending_.front() <= ack) pending_.pop_front();
  }
  [[nodiscard]] std::size_t unconfirmed() const { return pending_.size(); }

 private:
  std::deque<uint32_t> pending_;
};

}  // namespace pheromesh::core
