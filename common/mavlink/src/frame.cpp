#include "pheromesh/mavlink/frame.hpp"

#include <openssl/evp.h>
#include <openssl/hmac.h>

#include <algorithm>

#include "pheromesh/mavlink/messages.hpp"

namespace pheromesh::mavlink {

namespace {

constexpr std::size_t kSigBytes = 6;  // the truncated SHA-256 sent
constexpr std::size_t kTimestampBytes = 6;

// The first 6 bytes of SHA-256(key + frame[0, signed_len) + link id + timestamp).
std::array<uint8_t, kSigBytes> sign_bytes(const SecretKey& key, std::span<const uint8_t> frame_to_crc,
                                          std::span<const uint8_t> link_and_time) {
  std::array<uint8_t, EVP_MAX_MD_SIZE> md{};
  unsigned int md_len = 0;
  EVP_MD_CTX* ctx = EVP_MD_CTX_new();
  EVP_DigestInit_ex(ctx, EVP_sha256(), nullptr);
  EVP_DigestUpdate(ctx, key.bytes.data(), key.bytes.size());
  EVP_DigestUpdate(ctx, frame_to_crc.data(), frame_to_crc.size());
  EVP_DigestUpdate(ctx, link_and_time.data(), link_and_time.size());
  EVP_DigestFinal_ex(ctx, md.data(), &md_len);
  EVP_MD_CTX_free(ctx);
  std::array<uint8_t, kSigBytes> out{};
  std::copy_n(md.begin(), kSigBytes, out.begin());
  return out;
}

uint16_t frame_crc(std::span<const uint8_t> header_and_payload, uint8_t crc_extra) {
  // Every byte after the magic, then CRC_EXTRA.
  return crc_accumulate(crc_extra, crc_x25(header_and_payload.subspan(1)));
}

}  // namespace

uint16_t crc_accumulate(uint8_t byte, uint16_t crc) {
  // CRC-16/MCRF4XX, one byte at a time without a table (MAVLink spec, "CRC").
  uint8_t t = static_cast<uint8_t>(byte ^ static_cast<uint8_t>(crc & 0xFF));
  t = static_cast<uint8_t>(t ^ static_cast<uint8_t>(t << 4));
  return static_cast<uint16_t>((crc >> 8) ^ (static_cast<uint16_t>(t) << 8) ^ (static_cast<uint16_t>(t) << 3) ^
                               (t >> 4));
}

uint16_t crc_x25(std::span<const uint8_t> bytes, uint16_t crc) {
  for (const uint8_t b : bytes) crc = crc_accumulate(b, crc);
  return crc;
}

SecretKey derive_signing_key(std::span<const uint8_t> control_key) {
  SecretKey k;
  unsigned int len = 0;
  HMAC(EVP_sha256(), control_key.data(), static_cast<int>(control_key.size()),
       reinterpret_cast<const unsigned char*>(kSigningKeyLabel.data()), kSigningKeyLabel.size(), k.bytes.data(), &len);
  return k;
}

uint64_t signing_timestamp(std::chrono::system_clock::time_point t) {
  // 2015-01-01T00:00:00Z is 1420070400 s after the Unix epoch.
  constexpr int64_t kEpoch2015Us = int64_t{1420070400} * 1000000;
  const int64_t us = std::chrono::duration_cast<std::chrono::microseconds>(t.time_since_epoch()).count();
  return us <= kEpoch2015Us ? 0 : static_cast<uint64_t>((us - kEpoch2015Us) / 10);
}

std::vector<uint8_t> encode_frame(const Header& h, std::span<const uint8_t> payload, uint8_t crc_extra,
                                  const std::optional<Signing>& signing) {
  // MAVLink 2 truncation: trailing zeros are not sent, but one byte stays.
  std::size_t len = std::min(payload.size(), kMaxPayloadLen);
  while (len > 1 && payload[len - 1] == 0) --len;
  std::vector<uint8_t> f;
  f.reserve(kHeaderLen + len + kCrcLen + (signing ? kSignatureLen : 0));
  f.push_back(kMagicV2);
  f.push_back(static_cast<uint8_t>(len));
  f.push_back(signing ? kIncompatSigned : 0);
  f.push_back(0);  // compat flags
  f.push_back(h.seq);
  f.push_back(h.sysid);
  f.push_back(h.compid);
  f.push_back(static_cast<uint8_t>(h.msgid & 0xFF));
  f.push_back(static_cast<uint8_t>((h.msgid >> 8) & 0xFF));
  f.push_back(static_cast<uint8_t>((h.msgid >> 16) & 0xFF));
  f.insert(f.end(), payload.begin(), payload.begin() + static_cast<std::ptrdiff_t>(len));
  const uint16_t crc = frame_crc(f, crc_extra);
  f.push_back(static_cast<uint8_t>(crc & 0xFF));
  f.push_back(static_cast<uint8_t>(crc >> 8));
  if (signing && signing->key != nullptr) {
    std::array<uint8_t, 1 + kTimestampBytes> lt{};
    lt[0] = signing->link_id;
    for (std::size_t i = 0; i < kTimestampBytes; ++i) lt[1 + i] = static_cast<uint8_t>(signing->timestamp >> (8 * i));
    const auto sig = sign_bytes(*signing->key, f, lt);
    f.insert(f.end(), lt.begin(), lt.end());
    f.insert(f.end(), sig.begin(), sig.end());
  }
  return f;
}

bool signature_valid(const Frame& f, const SecretKey& key) {
  if (!f.is_signed || f.bytes.size() < kHeaderLen + kCrcLen + kSignatureLen) return false;
  const std::size_t signed_len = f.bytes.size() - kSignatureLen;
  const std::span<const uint8_t> all(f.bytes);
  const auto sig = sign_bytes(key, all.first(signed_len), all.subspan(signed_len, 1 + kTimestampBytes));
  // Compared in constant time: a forger learns nothing from how long it took.
  uint8_t diff = 0;
  for (std::size_t i = 0; i < kSigBytes; ++i) diff = static_cast<uint8_t>(diff | (sig[i] ^ f.signature[i]));
  return diff == 0;
}

std::optional<uint8_t> crc_extra_of(uint32_t msgid) {
  switch (msgid) {
    case Heartbeat::kId:
      return Heartbeat::kCrcExtra;
    case SysStatus::kId:
      return SysStatus::kCrcExtra;
    case Attitude::kId:
      return Attitude::kCrcExtra;
    case GlobalPositionInt::kId:
      return GlobalPositionInt::kCrcExtra;
    case CommandLong::kId:
      return CommandLong::kCrcExtra;
    case CommandAck::kId:
      return CommandAck::kCrcExtra;
    case AdsbVehicle::kId:
      return AdsbVehicle::kCrcExtra;
    case StatusText::kId:
      return StatusText::kCrcExtra;
    default:
      return std::nullopt;
  }
}

std::vector<Frame> Decoder::decode(std::span<const uint8_t> bytes) {
  std::vector<Frame> out;
  std::size_t i = 0;
  const std::size_t n = bytes.size();
  while (i < n) {
    if (bytes[i] != kMagicV2) {
      if (bytes[i] == kMagicV1) ++stats_.v1_frames;
      ++stats_.skipped_bytes;
      ++i;
      continue;
    }
    // A candidate frame at i: every length read is checked against n.
    if (n - i < kHeaderLen + kCrcLen) {
      ++stats_.truncated;
      stats_.skipped_bytes += n - i;
      break;
    }
    const std::size_t len = bytes[i + 1];
    const uint8_t incompat = bytes[i + 2];
    if ((incompat & ~kIncompatSigned) != 0) {
      ++stats_.bad_flags;
      ++stats_.skipped_bytes;
      ++i;
      continue;
    }
    const bool is_signed = (incompat & kIncompatSigned) != 0;
    const std::size_t total = kHeaderLen + len + kCrcLen + (is_signed ? kSignatureLen : 0);
    if (n - i < total) {
      ++stats_.truncated;
      ++stats_.skipped_bytes;
      ++i;
      continue;
    }
    const std::span<const uint8_t> frame = bytes.subspan(i, total);
    const uint32_t msgid = static_cast<uint32_t>(frame[7]) | (static_cast<uint32_t>(frame[8]) << 8) |
                           (static_cast<uint32_t>(frame[9]) << 16);
    const auto extra = crc_extra_of(msgid);
    if (!extra) {
      ++stats_.unknown_msgid;
      ++stats_.skipped_bytes;
      ++i;
      continue;
    }
    const uint16_t want = frame_crc(frame.first(kHeaderLen + len), *extra);
    const uint16_t got =
        static_cast<uint16_t>(frame[kHeaderLen + len] | (static_cast<uint16_t>(frame[kHeaderLen + len + 1]) << 8));
    if (want != got) {
      ++stats_.bad_crc;
      ++stats_.skipped_bytes;
      ++i;
      continue;
    }
    Frame f;
    f.incompat_flags = incompat;
    f.compat_flags = frame[3];
    f.header = {frame[4], frame[5], frame[6], msgid};
    f.payload.assign(frame.begin() + kHeaderLen, frame.begin() + static_cast<std::ptrdiff_t>(kHeaderLen + len));
    f.is_signed = is_signed;
    if (is_signed) {
      const std::size_t s = kHeaderLen + len + kCrcLen;
      f.link_id = frame[s];
      for (std::size_t k = 0; k < kTimestampBytes; ++k)
        f.timestamp |= static_cast<uint64_t>(frame[s + 1 + k]) << (8 * k);
      std::copy_n(frame.begin() + static_cast<std::ptrdiff_t>(s + 1 + kTimestampBytes), kSigBytes, f.signature.begin());
    }
    f.bytes.assign(frame.begin(), frame.end());
    out.push_back(std::move(f));
    ++stats_.frames;
    i += total;
  }
  return out;
}

}  // namespace pheromesh::mavlink
