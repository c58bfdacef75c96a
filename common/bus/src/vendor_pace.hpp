// The pace of keeping manual-by-topic writers alive, shared by the vendor
// transports: true at most ten times per liveliness lease (qos.hpp).
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
#pragma once

#include <chrono>

namespace pheromesh::bus {

class KeepAlivePace {
 public:
  static constexpr int kPerLease = 10;
  explicit KeepAlivePace(std::chrono::milliseconds lease) : lease_(lease) {}
  bool due() {
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ < lease_ / kPerLease) return false;
    last_ = now;
    return true;
  }

 private:
  std::chrono::milliseconds lease_;
  std::chrono::steady_clock::time_point last_{};
};

}  // namespace pheromesh::bus
