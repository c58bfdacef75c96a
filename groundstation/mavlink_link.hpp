// The ground station's UDP socket to a MAVLink ground-control station
// (--mavlink udp:HOST:PORT, docs/mavlink.md): non-blocking, so a slow or
// absent station never holds up the ground station's loop. A datagram the
// kernel cannot take at once is dropped and counted. Commands come back to
// this socket's port from wherever the station sends them.
#pragma once

#include <netinet/in.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "pheromesh/console/mavlink_feed.hpp"
#include "pheromesh/core/result.hpp"

namespace pheromesh::groundstation {

class MavlinkLink {
 public:
  struct Datagram {
    std::vector<uint8_t> bytes;
    sockaddr_in from{};
  };
  static core::Result<std::unique_ptr<MavlinkLink>> open(const console::MavlinkTarget& target);
  ~MavlinkLink();
  MavlinkLink(const MavlinkLink&) = delete;
  MavlinkLink& operator=(const MavlinkLink&) = delete;

  // To the station; false if dropped (counted).
  bool send(std::span<const uint8_t> bytes);
  // To whoever sent `to` (a COMMAND_ACK).
  bool reply(const sockaddr_in& to, std::span<const uint8_t> bytes);
  // What arrived, at most `max` datagrams (bounded work per call).
  std::vector<Datagram> receive(std::size_t max);
  [[nodiscard]] uint64_t dropped() const { return dropped_; }
  [[nodiscard]] const std::string& peer() const { return peer_; }

 private:
  MavlinkLink(int fd, sockaddr_in to, std::string peer) : fd_(fd), to_(to), peer_(std::move(peer)) {}
  int fd_;
  sockaddr_in to_;
  std::string peer_;
  uint64_t dropped_ = 0;
  std::vector<uint8_t> buf_ = std::vector<uint8_t>(65536);
};

}  // namespace pheromesh::groundstation
