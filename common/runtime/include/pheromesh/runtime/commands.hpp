// Ground-station commands as a UAV or place agent receives them: subscribed,
// authenticated (console/control.hpp), ordered, logged; pause state kept.
#pragma once

#include <memory>
#include <vector>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/console/control.hpp"

namespace spdlog {
class logger;
}

namespace pheromesh::runtime {

class SwarmCommands {
 public:
  // Subscribes to the commands; the key comes from $PHEROMESH_CONTROL_KEY.
  SwarmCommands(bus::Bus& bus, std::shared_ptr<spdlog::logger> log);
  // Commands admitted since the last call, in order. Pause and resume are
  // applied to paused() here; the caller applies the others.
  std::vector<core::CommandMsg> take();
  [[nodiscard]] bool paused() const { return paused_; }
  [[nodiscard]] uint64_t rejected() const { return gate_.rejected(); }

 private:
  bus::Bus* bus_;
  std::shared_ptr<spdlog::logger> log_;
  console::CommandGate gate_;
  std::vector<core::CommandMsg> inbox_;
  bool paused_ = false;
};

}  // namespace pheromesh::runtime
