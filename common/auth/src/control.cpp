#include "pheromesh/auth/control.hpp"

#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/hmac.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

namespace pheromesh::auth {

std::string random_hex(std::size_t bytes) {
  std::ifstream in("/dev/urandom", std::ios::binary);
  std::vector<unsigned char> b(bytes);
  in.read(reinterpret_cast<char*>(b.data()), static_cast<std::streamsize>(b.size()));
  if (!in) throw std::runtime_error("cannot read /dev/urandom");
  static constexpr char kHex[] = "0123456789abcdef";
  std::string t;
  for (unsigned char c : b) {
    t += kHex[c >> 4];
    t += kHex[c & 15];
  }
  return t;
}

std::string random_control_key_hex() { return random_hex(32); }

core::Result<ControlKey> parse_control_key(const std::string& hex) {
  if (hex.size() != 64) return core::Error{"a control key is 64 hex digits, got " + std::to_string(hex.size()) + " characters"};
  ControlKey k;
  const auto nibble = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  for (std::size_t i = 0; i < hex.size(); i += 2) {
    const int hi = nibble(hex[i]), lo = nibble(hex[i + 1]);
    if (hi < 0 || lo < 0) return core::Error{"a control key is 64 hex digits; character " + std::to_string(i + (hi < 0 ? 1 : 2)) + " is not one"};
    k.push_back(static_cast<uint8_t>(hi * 16 + lo));
  }
  return k;
}

core::Result<std::optional<ControlKey>> control_key_from_env() {
  const char* v = std::getenv(kControlKeyEnv);
  if (v == nullptr || *v == '\0') return std::optional<ControlKey>{};
  auto k = parse_control_key(v);
  if (!k) return core::Error{std::string("$") + kControlKeyEnv + ": " + k.error().message};
  return std::optional<ControlKey>{std::move(k).value()};
}

std::array<uint8_t, 32> hmac_sha256(std::span<const uint8_t> key, std::span<const uint8_t> data) {
  std::array<uint8_t, 32> out{};
  unsigned int n = 0;
  HMAC(EVP_sha256(), key.data(), static_cast<int>(key.size()), data.data(), data.size(), out.data(), &n);
  return out;
}

std::vector<uint8_t> command_bytes(const core::CommandMsg& m) {
  std::vector<uint8_t> b;
  const auto put = [&b](uint64_t v, int bytes) {
    for (int i = 0; i < bytes; ++i) b.push_back(static_cast<uint8_t>(v >> (8 * i)));
  };
  put(m.issuer, 4);
  put(m.seq, 4);
  put(m.issued_ms, 8);
  put(m.kind, 1);
  put(static_cast<uint32_t>(m.x), 4);
  put(static_cast<uint32_t>(m.y), 4);
  put(static_cast<uint32_t>(m.w), 4);
  put(static_cast<uint32_t>(m.h), 4);
  return b;
}

void sign(core::CommandMsg& m, const ControlKey& key) { m.mac = hmac_sha256(key, command_bytes(m)); }

bool verify(const core::CommandMsg& m, const ControlKey& key) {
  const auto want = hmac_sha256(key, command_bytes(m));
  return CRYPTO_memcmp(want.data(), m.mac.data(), want.size()) == 0;
}

std::string describe(const core::CommandMsg& m) {
  switch (static_cast<core::CommandKind>(m.kind)) {
    case core::CommandKind::Pause: return "pause";
    case core::CommandKind::Resume: return "resume";
    case core::CommandKind::Obstacle:
      return "obstacle at (" + std::to_string(m.x) + "," + std::to_string(m.y) + ") " + std::to_string(m.w) + "x" +
             std::to_string(m.h);
    case core::CommandKind::Target: return "target at (" + std::to_string(m.x) + "," + std::to_string(m.y) + ")";
    case core::CommandKind::Start: return "start";
    case core::CommandKind::End:
      return "end of the run";
  }
  return "unknown command kind " + std::to_string(m.kind);
}

std::vector<core::CommandMsg> CommandGate::admit(std::vector<core::CommandMsg>& received, std::vector<std::string>* refused) {
  std::stable_sort(received.begin(), received.end(),
                   [](const auto& a, const auto& b) { return a.issuer != b.issuer ? a.issuer < b.issuer : a.seq < b.seq; });
  std::vector<core::CommandMsg> ok;
  for (const auto& c : received) {
    const char* why = nullptr;
    auto seen = seen_.find(c.issuer);
    if (!key_) {
      why = "this process has no control key";
    } else if (!verify(c, *key_)) {
      why = "bad signature";
    } else if (seen != seen_.end() && seen->second.seqs.contains(c.seq)) {
      why = "replayed seq (admitted before)";
    } else if (seen != seen_.end() && seen->second.newest >= kWindow && c.seq <= seen->second.newest - kWindow) {
      why = "seq too old to tell from a replay";
    } else if (c.kind < 1 || c.kind > static_cast<uint8_t>(core::CommandKind::End)) {
      why = "unknown kind";
    }
    if (why != nullptr) {
      ++rejected_;
      if (refused != nullptr) refused->push_back(describe(c) + " from " + std::to_string(c.issuer) + ": " + why);
      continue;
    }
    Seen& s = seen_[c.issuer];
    s.seqs.insert(c.seq);
    s.newest = std::max(s.newest, c.seq);
    if (s.newest >= kWindow) s.seqs.erase(s.seqs.begin(), s.seqs.upper_bound(s.newest - kWindow));
    ++accepted_;
    ok.push_back(c);
  }
  return ok;
}

}  // namespace pheromesh::auth
