// The pace of keeping manual-by-topic writers alive, shared by the vendor
// transports: true at most four times per liveliness lease (qos.hpp).
#pragma once

#include <chrono>

namespace pheromesh::bus {

class KeepAlivePace {
 public:
  explicit KeepAlivePace(std::chrono::milliseconds lease) : lease_(lease) {}
  bool due() {
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ < lease_ / 4) return false;
    last_ = now;
    return true;
  }

 private:
  std::chrono::milliseconds lease_;
  std::chrono::steady_clock::time_point last_{};
};

}  // namespace pheromesh::bus
