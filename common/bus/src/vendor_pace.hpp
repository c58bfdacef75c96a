// The pace of keeping manual-by-topic writers alive, shared by the vendor
// transports: a round at most ten times per liveliness lease (qos.hpp), in
// which each such writer that wrote nothing since the round before is
// asserted.
//
// An assertion is a heartbeat that neither vendor sends again when it is
// lost, so a reader sees the writer's liveliness lapse when every assertion
// of one lease is lost. At four per lease, 30 % packet loss lapsed live
// processes 6 times in one 34 s lockstep run of 9 processes (0.3^4 per lease
// and reader: the ground station reported them lost and back, docs/dds.md
// "Lockstep under packet loss"); at ten per lease that takes 0.3^10 (6e-6),
// and 8 runs so had 1 lapse in all. The cost is
// one small datagram per manual-by-topic writer and matched reader every
// lease / 10 while the process polls its bus.
//
// A write asserts a manual-by-topic writer's liveliness (DDS 1.4, LIVELINESS
// QoS), and a written sample is sent again until acknowledged, so a writer
// that wrote since the previous round is not asserted: a realtime UAV writes
// its state every tick, and its assertions were one heartbeat datagram per
// UAV tick of 12-17 (measured: docs/benchmarks.md, "Where a UAV tick goes").
#pragma once

#include <chrono>
#include <cstddef>
#include <vector>

namespace pheromesh::bus {

class KeepAlivePace {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr int kPerLease = 10;
  explicit KeepAlivePace(std::chrono::milliseconds lease) : lease_(lease) {}

  // Writer `id` (a transport's endpoint index) wrote a sample.
  void wrote(std::size_t id) {
    if (id >= wrote_.size()) wrote_.resize(id + 1, false);
    wrote_[id] = true;
  }

  // A round is due at most kPerLease times per lease: calls assert_one(id)
  // for each of `writers` that did not write since the previous round.
  // Returns whether the round was due.
  template <class Writers, class Assert>
  bool round(Clock::time_point now, const Writers& writers, Assert&& assert_one) {
    if (now - last_ < lease_ / kPerLease) return false;
    last_ = now;
    for (const std::size_t id : writers) {
      if (id >= wrote_.size() || !wrote_[id]) assert_one(id);
    }
    wrote_.assign(wrote_.size(), false);
    return true;
  }

 private:
  std::chrono::milliseconds lease_;
  Clock::time_point last_{};
  std::vector<bool> wrote_;
};

}  // namespace pheromesh::bus
