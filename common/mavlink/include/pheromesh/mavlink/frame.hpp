// MAVLink 2 framing, written from the MAVLink specification ("MAVLink 2
// Packet Format", "Message Signing" at mavlink.io): a frame is
//
//   0xFD len incompat compat seq sysid compid msgid[3] payload[len] crc[2] (signature[13])
//
// little-endian throughout. The CRC is CRC-16/MCRF4XX (the X.25 CRC of the
// MAVLink C library: polynomial 0x1021 reflected, initial 0xFFFF, no final
// xor) over every byte after the magic up to the payload's end, then the
// message's CRC_EXTRA byte (a hash of its name and fields that catches a
// sender and receiver built from different definitions). Trailing zero bytes
// of the payload are not sent (MAVLink 2 truncation; at least one byte
// stays) and a receiver fills them in again.
//
// Signing (incompat flag 0x01) appends link id (1 byte), timestamp (6
// bytes, units of 10 µs since 2015-01-01T00:00:00Z) and the first 6 bytes
// of SHA-256(secret key[32] + header[10] + payload + crc[2] + link id +
// timestamp). Pure: no sockets; the time is passed in.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace pheromesh::mavlink {

inline constexpr uint8_t kMagicV2 = 0xFD;
inline constexpr uint8_t kMagicV1 = 0xFE;
inline constexpr std::size_t kHeaderLen = 10;  // magic .. msgid
inline constexpr std::size_t kCrcLen = 2;
inline constexpr std::size_t kSignatureLen = 13;  // link id, timestamp[6], signature[6]
inline constexpr std::size_t kMaxPayloadLen = 255;
inline constexpr std::size_t kMaxFrameLen = kHeaderLen + kMaxPayloadLen + kCrcLen + kSignatureLen;  // 280
inline constexpr uint8_t kIncompatSigned = 0x01;

// CRC-16/MCRF4XX: one byte into `crc`, and a run of bytes.
uint16_t crc_accumulate(uint8_t byte, uint16_t crc);
uint16_t crc_x25(std::span<const uint8_t> bytes, uint16_t crc = 0xFFFF);

struct SecretKey {
  std::array<uint8_t, 32> bytes{};
};
// The MAVLink signing key of a swarm: HMAC-SHA256 under the swarm's control
// key ($PHEROMESH_CONTROL_KEY, 32 bytes) of the ASCII label
// kSigningKeyLabel (docs/mavlink.md). A ground station given this key can
// sign commands; it cannot sign the swarm's own commands (HMAC is one-way).
inline constexpr std::string_view kSigningKeyLabel = "pheromesh mavlink signing key v1";
SecretKey derive_signing_key(std::span<const uint8_t> control_key);

// The signing timestamp of a wall-clock time [10 µs since 2015-01-01T00:00:00Z].
uint64_t signing_timestamp(std::chrono::system_clock::time_point t);

// Who sends, and the frame's sequence number.
struct Header {
  uint8_t seq = 0;
  uint8_t sysid = 0;
  uint8_t compid = 0;
  uint32_t msgid = 0;  // 24 bits
};

struct Signing {
  const SecretKey* key = nullptr;
  uint8_t link_id = 0;
  uint64_t timestamp = 0;  // signing_timestamp(); only 48 bits are sent
};

// A frame of `payload` (the message's full payload, truncated here) with
// the message's CRC_EXTRA; signed if `signing` is given.
std::vector<uint8_t> encode_frame(const Header& h, std::span<const uint8_t> payload, uint8_t crc_extra,
                                  const std::optional<Signing>& signing = std::nullopt);

// A frame as received, its CRC checked.
struct Frame {
  Header header;
  uint8_t incompat_flags = 0;
  uint8_t compat_flags = 0;
  std::vector<uint8_t> payload;  // as sent (possibly truncated)
  bool is_signed = false;
  uint8_t link_id = 0;
  uint64_t timestamp = 0;  // 48 bits
  std::array<uint8_t, 6> signature{};
  std::vector<uint8_t> bytes;  // the whole frame, for the signature check
};

// Whether the signature of a signed frame is that of `key`.
[[nodiscard]] bool signature_valid(const Frame& f, const SecretKey& key);

// The CRC_EXTRA of a message this library knows (messages.hpp); nullopt
// for another id, whose frames cannot be checked and are dropped.
std::optional<uint8_t> crc_extra_of(uint32_t msgid);

// Splits a datagram into frames. Never reads outside `bytes`; anything that
// is not a whole frame of a known message with a good CRC is skipped and
// counted. Resynchronises on the next magic byte after a bad frame.
class Decoder {
 public:
  struct Stats {
    uint64_t frames = 0;         // good frames returned
    uint64_t bad_crc = 0;        // a whole frame whose CRC did not check
    uint64_t truncated = 0;      // a frame cut short by the datagram's end
    uint64_t unknown_msgid = 0;  // a frame of a message we do not know (CRC not checkable)
    uint64_t bad_flags = 0;      // incompat flags other than signing
    uint64_t v1_frames = 0;      // MAVLink 1 (0xFE) frames: not accepted
    uint64_t skipped_bytes = 0;  // bytes outside any good frame
  };
  std::vector<Frame> decode(std::span<const uint8_t> bytes);
  [[nodiscard]] const Stats& stats() const { return stats_; }

 private:
  Stats stats_;
};

}  // namespace pheromesh::mavlink
