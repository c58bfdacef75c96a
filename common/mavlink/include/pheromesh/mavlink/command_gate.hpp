// What the ground station takes from a ground-control station: COMMAND_LONG
// frames signed with the swarm's MAVLink key (frame.hpp,
// derive_signing_key), mapped to the console's swarm commands
// (docs/mavlink.md):
//   MAV_CMD_DO_PAUSE_CONTINUE (193): param1 0 = pause, 1 = continue;
//   MAV_CMD_COMPONENT_ARM_DISARM (400): param1 0 (disarm) = stop the run.
// Everything else is counted and dropped: malformed frames and bad CRCs
// (Decoder), unsigned and badly signed commands, replays (a signing
// timestamp not above the newest of its stream, or more than a minute
// behind the local clock: MAVLink "Message Signing", replay protection),
// and commands we do not carry out (these get a signed COMMAND_ACK
// UNSUPPORTED). Frames of other messages (a GCS's own HEARTBEAT) are
// ignored. Pure: the wall time is passed in.
//
// A gate made with Signatures::NotChecked (`pheromesh replay --mavlink`,
// which holds no key and whose commands steer only its own playback) takes
// every well-formed COMMAND_LONG, signed or not, and checks no signature.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <tuple>
#include <vector>

#include "pheromesh/mavlink/frame.hpp"
#include "pheromesh/mavlink/messages.hpp"

namespace pheromesh::mavlink {

class CommandGate {
 public:
  enum class Action : uint8_t { Pause, Resume, Stop, Unsupported };
  // A command that verified: what it asks, and whom to acknowledge.
  struct Command {
    Action action = Action::Unsupported;
    CommandLong message;
    uint8_t from_sysid = 0, from_compid = 0;
  };
  struct Stats {
    uint64_t accepted = 0;  // verified commands, Unsupported ones included
    uint64_t unsigned_refused = 0;
    uint64_t bad_signature = 0;   // signed, but not with the key (or this ground station has no key)
    uint64_t replayed = 0;        // signed with the key, timestamp not fresh
    uint64_t other_messages = 0;  // well-formed frames of messages other than COMMAND_LONG
  };
  // Streams remembered for replay protection; the least recently used one is
  // forgotten beyond this (memory stays bounded whatever a peer sends).
  static constexpr std::size_t kMaxStreams = 256;
  // A timestamp this far behind the local clock is refused [10 µs] (one minute).
  static constexpr uint64_t kMaxAge = 6'000'000;

  enum class Signatures : uint8_t { Required, NotChecked };
  // `key`: the swarm's MAVLink key; without it every command is refused
  // (unless signatures are NotChecked).
  explicit CommandGate(std::optional<SecretKey> key, Signatures signatures = Signatures::Required)
      : key_(key), signatures_(signatures) {}
  // The commands of one datagram received at `now`.
  std::vector<Command> take(std::span<const uint8_t> datagram, std::chrono::system_clock::time_point now);
  [[nodiscard]] const Stats& stats() const { return stats_; }
  [[nodiscard]] const Decoder::Stats& frames() const { return decoder_.stats(); }
  // Malformed input of every kind the decoder counts.
  [[nodiscard]] uint64_t malformed() const;

 private:
  static Action action_of(const CommandLong& c);
  bool fresh(const Frame& f, uint64_t now_ts);

  std::optional<SecretKey> key_;
  Signatures signatures_;
  Decoder decoder_;
  Stats stats_;
  using Stream = std::tuple<uint8_t, uint8_t, uint8_t>;  // sysid, compid, link id
  struct Seen {
    uint64_t newest = 0;
    uint64_t used = 0;  // for least-recently-used eviction
  };
  std::map<Stream, Seen> streams_;
  uint64_t use_ = 0;
};

}  // namespace pheromesh::mavlink
