// Authorising ground-station commands (idl Command). `pheromesh run` makes a
// random control key and gives it to every process it starts in
// $PHEROMESH_CONTROL_KEY; the ground station signs each command with
// HMAC-SHA256 under that key, and every UAV and place agent acts only on
// commands that verify, in increasing seq order per issuer. A process without
// the key acts on no command (counted).
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/result.hpp"

namespace pheromesh::auth {

using ControlKey = std::vector<uint8_t>;
inline constexpr const char* kControlKeyEnv = "PHEROMESH_CONTROL_KEY";

// `bytes` random bytes from /dev/urandom as hex digits.
std::string random_hex(std::size_t bytes);
// 32 random bytes as 64 hex digits.
std::string random_control_key_hex();
// Parses 64 hex digits (any case).
core::Result<ControlKey> parse_control_key(const std::string& hex);
// The key from $PHEROMESH_CONTROL_KEY; nullopt if unset; an error if malformed.
core::Result<std::optional<ControlKey>> control_key_from_env();

// HMAC-SHA256 (RFC 2104) of `data` under `key`.
std::array<uint8_t, 32> hmac_sha256(std::span<const uint8_t> key, std::span<const uint8_t> data);
// The bytes a command's mac covers: every field before mac, little-endian.
std::vector<uint8_t> command_bytes(const core::CommandMsg& m);
void sign(core::CommandMsg& m, const ControlKey& key);
[[nodiscard]] bool verify(const core::CommandMsg& m, const ControlKey& key);

std::string describe(const core::CommandMsg& m);  // "pause", "obstacle 5,5 3x3", ...

// Receiver side: which received commands to act on. Each signed command is
// admitted once per process, also when it arrives after a newer one: a
// process that joins late hears the history from several relays (its home
// and its backup place agent), in no set order, and must still see the
// start and every pop-up obstacle (before, a restarted UAV that heard
// "resume" (seq 3) first refused "start" (seq 1) as out of order and waited
// for the rest of the run). What a late command means is the receiver's
// call: runtime::SwarmCommands lets a late pause or resume be superseded.
class CommandGate {
 public:
  // Seqs further back than this from an issuer's newest admitted one are
  // refused: too old to tell from a replay (memory stays bounded).
  static constexpr uint32_t kWindow = 4096;
  explicit CommandGate(std::optional<ControlKey> key) : key_(std::move(key)) {}
  // Commands to apply, sorted by (issuer, seq); the others are counted and described in `refused`.
  std::vector<core::CommandMsg> admit(std::vector<core::CommandMsg>& received, std::vector<std::string>* refused = nullptr);
  [[nodiscard]] uint64_t accepted() const { return accepted_; }
  [[nodiscard]] uint64_t rejected() const { return rejected_; }
  [[nodiscard]] bool has_key() const { return key_.has_value(); }

 private:
  std::optional<ControlKey> key_;
  struct Seen {
    uint32_t newest = 0;
    std::set<uint32_t> seqs;  // admitted, within kWindow of `newest`
  };
  std::map<uint32_t, Seen> seen_;  // by issuer; only issuers whose commands were signed with the key
  uint64_t accepted_ = 0, rejected_ = 0;
};

}  // namespace pheromesh::auth
