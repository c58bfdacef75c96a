// Command authentication (auth/control.hpp): HMAC-SHA256 against RFC 4231,
// the receiver's gate, key parsing.
#include <gtest/gtest.h>

#include <span>
#include <string>
#include <vector>

#include "pheromesh/auth/control.hpp"

namespace pheromesh::auth {
namespace {

TEST(Auth, HmacSha256Rfc4231Case2) {
  const std::string key = "Jefe", data = "what do ya want for nothing?";
  const auto mac = hmac_sha256(std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(key.data()), key.size()),
                               std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(data.data()), data.size()));
  std::string hex;
  for (uint8_t b : mac) {
    static constexpr char k[] = "0123456789abcdef";
    hex += k[b >> 4];
    hex += k[b & 15];
  }
  EXPECT_EQ(hex, "5bdcc146bf60754e6a042426089575c75a003f089d2739839dec58b964ec3843");
}

core::CommandMsg signed_command(const ControlKey& key, uint32_t seq, core::CommandKind kind) {
  core::CommandMsg c;
  c.issuer = core::process_key(core::kRoleGround, 0);
  c.seq = seq;
  c.issued_ms = 1'700'000'000'000ULL;
  c.kind = static_cast<uint8_t>(kind);
  c.x = 5;
  c.y = 6;
  c.w = 3;
  c.h = 2;
  sign(c, key);
  return c;
}

TEST(Auth, GateAdmitsSignedCommandsInOrderOnce) {
  const ControlKey key = parse_control_key(std::string(64, 'a')).value();
  CommandGate gate(key);
  std::vector<core::CommandMsg> in{signed_command(key, 2, core::CommandKind::Obstacle),
                                   signed_command(key, 1, core::CommandKind::Pause)};
  auto ok = gate.admit(in);
  ASSERT_EQ(ok.size(), 2U);
  EXPECT_EQ(ok[0].seq, 1U);  // sorted by seq
  EXPECT_EQ(ok[1].seq, 2U);
  // Replayed, tampered with, or signed with another key: refused and counted.
  auto tampered = signed_command(key, 3, core::CommandKind::Obstacle);
  tampered.w = 30;
  const ControlKey other = parse_control_key(std::string(64, 'b')).value();
  std::vector<core::CommandMsg> bad{signed_command(key, 2, core::CommandKind::Obstacle), tampered,
                                    signed_command(other, 4, core::CommandKind::Pause)};
  std::vector<std::string> why;
  EXPECT_TRUE(gate.admit(bad, &why).empty());
  EXPECT_EQ(gate.rejected(), 3U);
  ASSERT_EQ(why.size(), 3U);
  EXPECT_NE(why[0].find("replayed"), std::string::npos);
  EXPECT_NE(why[1].find("bad signature"), std::string::npos);
  // A process without the key acts on nothing.
  CommandGate keyless(std::nullopt);
  std::vector<core::CommandMsg> one{signed_command(key, 1, core::CommandKind::Pause)};
  EXPECT_TRUE(keyless.admit(one).empty());
  EXPECT_EQ(keyless.rejected(), 1U);
}

TEST(Auth, GateAdmitsACommandOlderThanTheNewestOnceAndRefusesOnesTooOldToTell) {
  const ControlKey key = parse_control_key(std::string(64, 'd')).value();
  CommandGate gate(key);
  std::vector<core::CommandMsg> newest{signed_command(key, 5000, core::CommandKind::Obstacle)};
  ASSERT_EQ(gate.admit(newest).size(), 1U);
  // Late (from another relay's history), never admitted before: admitted.
  std::vector<core::CommandMsg> late{signed_command(key, 4000, core::CommandKind::Obstacle)};
  ASSERT_EQ(gate.admit(late).size(), 1U);
  std::vector<core::CommandMsg> again{signed_command(key, 4000, core::CommandKind::Obstacle),
                                      signed_command(key, 5000, core::CommandKind::Obstacle)};
  std::vector<std::string> why;
  EXPECT_TRUE(gate.admit(again, &why).empty());
  ASSERT_EQ(why.size(), 2U);
  EXPECT_NE(why[0].find("replayed"), std::string::npos) << why[0];
  // 5000 - 4096 = 904: seq 904 and older cannot be told from a replay any more.
  std::vector<core::CommandMsg> old{signed_command(key, 904, core::CommandKind::Obstacle),
                                    signed_command(key, 905, core::CommandKind::Obstacle)};
  why.clear();
  const auto ok = gate.admit(old, &why);
  ASSERT_EQ(ok.size(), 1U);
  EXPECT_EQ(ok[0].seq, 905U);
  ASSERT_EQ(why.size(), 1U);
  EXPECT_NE(why[0].find("too old"), std::string::npos) << why[0];
  EXPECT_EQ(gate.accepted(), 3U);
  EXPECT_EQ(gate.rejected(), 3U);
}

TEST(Auth, TheEndOfARunIsAdmittedWhenSignedAndKindsBeyondItAreNot) {
  const ControlKey key = parse_control_key(std::string(64, 'c')).value();
  CommandGate gate(key);
  std::vector<core::CommandMsg> in{signed_command(key, 1, core::CommandKind::End)};
  const auto ok = gate.admit(in);
  ASSERT_EQ(ok.size(), 1U);
  EXPECT_EQ(describe(ok[0]), "end of the run");
  auto unknown = signed_command(key, 2, core::CommandKind::End);
  unknown.kind = static_cast<uint8_t>(core::CommandKind::End) + 1;
  sign(unknown, key);
  std::vector<core::CommandMsg> bad{unknown};
  std::vector<std::string> why;
  EXPECT_TRUE(gate.admit(bad, &why).empty());
  ASSERT_EQ(why.size(), 1U);
  EXPECT_NE(why[0].find("unknown kind"), std::string::npos);
}

TEST(Auth, KeyParsingNamesTheProblem) {
  EXPECT_FALSE(parse_control_key("abc").ok());
  EXPECT_NE(parse_control_key(std::string(63, 'a') + "z").error().message.find("character 64"), std::string::npos);
  EXPECT_EQ(random_control_key_hex().size(), 64U);
  EXPECT_TRUE(parse_control_key(random_control_key_hex()).ok());
}

}  // namespace
}  // namespace pheromesh::auth
