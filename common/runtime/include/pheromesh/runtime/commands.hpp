// Ground-station commands as a UAV or place agent receives them: subscribed,
// authenticated (auth/control.hpp), ordered, logged; pause state kept.
#pragma once

#include <array>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/auth/control.hpp"

namespace spdlog {
class logger;
}

namespace pheromesh::runtime {

class SwarmCommands {
 public:
  // Subscribes to the commands; the key comes from $PHEROMESH_CONTROL_KEY.
  SwarmCommands(bus::Bus& bus, std::shared_ptr<spdlog::logger> log);
  // Commands admitted since the last call, in order. Pause and resume are
  // applied to paused() here (one older than the last applied changes
  // nothing: the newer stands, but it is still returned, for a place agent
  // to relay on); the caller applies the others, late ones too (a pop-up
  // obstacle is one whatever its order).
  std::vector<core::CommandMsg> take();
  [[nodiscard]] bool paused() const { return paused_; }
  // The ground station's start arrived (it is transient-local: a process
  // started late, or restarted, gets it at once).
  [[nodiscard]] bool started() const { return started_; }
  // The ground station ended the run (pheromesh-ground --until-done).
  [[nodiscard]] bool ended() const { return ended_; }
  // False without a control key: no command can be admitted, so no start.
  [[nodiscard]] bool can_start() const { return gate_.has_key(); }
  [[nodiscard]] uint64_t rejected() const { return gate_.rejected(); }

 private:
  bus::Bus* bus_;
  std::shared_ptr<spdlog::logger> log_;
  auth::CommandGate gate_;
  std::vector<core::CommandMsg> inbox_;
  std::map<std::pair<uint32_t, uint32_t>, core::CommandMsg> admitted_;  // by (issuer, seq)
  std::map<uint32_t, uint32_t> toggle_seq_;  // by issuer: the seq of the pause or resume applied last
  bool paused_ = false;
  bool started_ = false;
  bool ended_ = false;
};

}  // namespace pheromesh::runtime
