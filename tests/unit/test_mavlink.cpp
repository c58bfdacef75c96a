// MAVLink 2 framing, signing and messages (common/mavlink), against frames
// computed independently: tests/data/mavlink/reference_frames.py (struct.pack for the
// payload, hashlib.sha256 for the signature, the CRC-16/MCRF4XX written out
// from the MAVLink spec), run by hand and pasted here. Its CRC gives the
// catalogue check value 0x6F91 for "123456789", as the first test does here.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "pheromesh/mavlink/command_gate.hpp"
#include "pheromesh/mavlink/frame.hpp"
#include "pheromesh/mavlink/messages.hpp"

namespace pheromesh::mavlink {
namespace {

using Bytes = std::vector<uint8_t>;

TEST(MavlinkCrc, GivesTheCatalogueCheckValueOfCrc16Mcrf4xx) {
  const std::string s = "123456789";
  EXPECT_EQ(crc_x25(Bytes(s.begin(), s.end())), 0x6F91);
}

// HEARTBEAT of a quadrotor, system 1 component 1, seq 0: header FD 09 00 00
// 00 01 01 | msgid 00 00 00 | custom_mode 00 00 00 00, type 02, autopilot 08,
// base_mode 00, system_status 04, mavlink_version 03 | CRC A6 90 (CRC over
// bytes 1..18, then CRC_EXTRA 50).
const Bytes kHeartbeat = {0xFD, 0x09, 0x00, 0x00, 0x00, 0x01, 0x01, 0x00, 0x00, 0x00, 0x00,
                          0x00, 0x00, 0x00, 0x02, 0x08, 0x00, 0x04, 0x03, 0xA6, 0x90};

TEST(MavlinkFrame, HeartbeatIsEncodedByteForByteAsTheSpecificationLaysItOut) {
  Heartbeat hb;
  hb.type = kMavTypeQuadrotor;
  hb.autopilot = kMavAutopilotInvalid;
  hb.system_status = kMavStateActive;
  EXPECT_EQ(encode(hb, Header{0, 1, 1, 0}), kHeartbeat);
}

// GLOBAL_POSITION_INT, seq 7 system 3: time 1000 ms, lat 1e7, lon -2e7, alt
// 130000 mm, relative 30000 mm, vx 150, vy -250, vz 0, hdg 0. vz and hdg are
// trailing zeros: the payload is cut from 28 to 24 bytes (len 0x18).
const Bytes kPosition = {0xFD, 0x18, 0x00, 0x00, 0x07, 0x03, 0x01, 0x21, 0x00, 0x00, 0xE8, 0x03,
                         0x00, 0x00, 0x80, 0x96, 0x98, 0x00, 0x00, 0xD3, 0xCE, 0xFE, 0xD0, 0xFB,
                         0x01, 0x00, 0x30, 0x75, 0x00, 0x00, 0x96, 0x00, 0x06, 0xFF, 0x34, 0xAE};

GlobalPositionInt position() {
  GlobalPositionInt p;
  p.time_boot_ms = 1000;
  p.lat = 10000000;
  p.lon = -20000000;
  p.alt = 130000;
  p.relative_alt = 30000;
  p.vx = 150;
  p.vy = -250;
  p.hdg = 0;
  return p;
}

TEST(MavlinkFrame, TrailingZerosOfThePayloadAreCutAndFilledInAgainOnDecoding) {
  EXPECT_EQ(encode(position(), Header{7, 3, 1, 0}), kPosition);
  Decoder d;
  const auto frames = d.decode(kPosition);
  ASSERT_EQ(frames.size(), 1U);
  EXPECT_EQ(frames[0].payload.size(), 24U);
  const auto back = decode<GlobalPositionInt>(frames[0]);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->lat, 10000000);
  EXPECT_EQ(back->lon, -20000000);
  EXPECT_EQ(back->vy, -250);
  EXPECT_EQ(back->hdg, 0);
  EXPECT_FALSE(decode<Heartbeat>(frames[0]).has_value());
}

TEST(MavlinkFrame, AnAllZeroPayloadKeepsOneByte) {
  const Bytes f = encode(Heartbeat{0, 0, 0, 0, 0, 0}, Header{});
  EXPECT_EQ(f[1], 1);  // len
  EXPECT_EQ(f.size(), kHeaderLen + 1 + kCrcLen);
  Decoder d;
  ASSERT_EQ(d.decode(f).size(), 1U);
}

// COMMAND_LONG pause (193) to system 251 component 1 from 255/190, seq 5,
// signed with the key 00 01 .. 1F, link 1, timestamp 0x123456789A: payload
// cut to 32 bytes (confirmation 0), incompat flag 01, then 01 | 9A 78 56 34
// 12 00 | SHA-256(key + frame + link + timestamp)[0..6] = 62 36 50 3B 82 65.
const Bytes kSignedPause = {0xFD, 0x20, 0x01, 0x00, 0x05, 0xFF, 0xBE, 0x4C, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
                            0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
                            0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xC1, 0x00, 0xFB, 0x01, 0xCA, 0x7C, 0x01,
                            0x9A, 0x78, 0x56, 0x34, 0x12, 0x00, 0x62, 0x36, 0x50, 0x3B, 0x82, 0x65};

SecretKey counting_key() {
  SecretKey k;
  for (std::size_t i = 0; i < k.bytes.size(); ++i) k.bytes[i] = static_cast<uint8_t>(i);
  return k;
}

CommandLong pause_command() {
  CommandLong c;
  c.command = kCmdDoPauseContinue;
  c.target_system = 251;
  c.target_component = 1;
  return c;
}

TEST(MavlinkSigning, ASignedCommandCarriesLinkTimestampAndTheTruncatedSha256) {
  const SecretKey key = counting_key();
  const Bytes f = encode(pause_command(), Header{5, 255, 190, 0}, Signing{&key, 1, 0x123456789AULL});
  EXPECT_EQ(f, kSignedPause);
  Decoder d;
  const auto frames = d.decode(f);
  ASSERT_EQ(frames.size(), 1U);
  EXPECT_TRUE(frames[0].is_signed);
  EXPECT_EQ(frames[0].link_id, 1);
  EXPECT_EQ(frames[0].timestamp, 0x123456789AULL);
  EXPECT_TRUE(signature_valid(frames[0], key));
  SecretKey other = key;
  other.bytes[31] ^= 1;
  EXPECT_FALSE(signature_valid(frames[0], other));
}

TEST(MavlinkSigning, TheKeyIsHmacSha256OfTheLabelUnderTheControlKey) {
  // Python: hmac.new(b"\xab" * 32, b"pheromesh mavlink signing key v1", hashlib.sha256).hexdigest()
  const std::vector<uint8_t> control(32, 0xAB);
  const SecretKey k = derive_signing_key(control);
  const std::array<uint8_t, 32> want{0x8d, 0xf6, 0x03, 0x8c, 0xed, 0x48, 0x59, 0xa2, 0x6f, 0xbb, 0xa5,
                                     0x0f, 0xcb, 0xfb, 0x1b, 0xd1, 0x5a, 0x40, 0x6f, 0xcb, 0x4f, 0x47,
                                     0x82, 0x66, 0xba, 0x4e, 0x61, 0x28, 0x3b, 0xaa, 0xea, 0x2f};
  EXPECT_EQ(k.bytes, want);
}

TEST(MavlinkSigning, TimestampCountsTenMicrosecondsFrom2015) {
  using namespace std::chrono;
  const system_clock::time_point t2015{seconds(1420070400)};
  EXPECT_EQ(signing_timestamp(t2015), 0U);
  EXPECT_EQ(signing_timestamp(t2015 + seconds(1)), 100000U);
  EXPECT_EQ(signing_timestamp(t2015 - seconds(1)), 0U);
}

TEST(MavlinkMessages, EveryMessageSurvivesARoundTrip) {
  AdsbVehicle a;
  a.icao_address = 0xF00007;
  a.lat = -338700000;
  a.lon = 1512100000;
  a.altitude = 30000;
  a.heading = 27000;
  a.hor_velocity = 1000;
  a.flags = kAdsbFlagValidCoords | kAdsbFlagValidCallsign;
  a.altitude_type = kAdsbAltitudeGeometric;
  a.callsign = "PH7";
  a.emitter_type = kAdsbEmitterUav;
  a.tslc = 1;
  Decoder d;
  auto f = d.decode(encode(a, Header{}));
  ASSERT_EQ(f.size(), 1U);
  const auto b = decode<AdsbVehicle>(f[0]);
  ASSERT_TRUE(b);
  EXPECT_EQ(b->icao_address, a.icao_address);
  EXPECT_EQ(b->lat, a.lat);
  EXPECT_EQ(b->lon, a.lon);
  EXPECT_EQ(b->heading, a.heading);
  EXPECT_EQ(b->callsign, "PH7");
  EXPECT_EQ(b->emitter_type, kAdsbEmitterUav);
  EXPECT_EQ(b->tslc, 1);

  StatusText s;
  s.severity = kSeverityWarning;
  s.text = std::string(60, 'x');  // cut to 50
  f = d.decode(encode(s, Header{}));
  ASSERT_EQ(f.size(), 1U);
  EXPECT_EQ(decode<StatusText>(f[0])->text, std::string(50, 'x'));

  SysStatus st;
  st.errors_count[2] = 7;
  st.load = 500;
  f = d.decode(encode(st, Header{}));
  ASSERT_EQ(f.size(), 1U);
  EXPECT_EQ(decode<SysStatus>(f[0])->errors_count[2], 7);
  EXPECT_EQ(decode<SysStatus>(f[0])->battery_remaining, -1);

  Attitude at;
  at.yaw = -1.5F;
  f = d.decode(encode(at, Header{}));
  EXPECT_FLOAT_EQ(decode<Attitude>(f.at(0))->yaw, -1.5F);

  CommandAck ack;
  ack.command = kCmdDoPauseContinue;
  ack.result = kResultDenied;
  f = d.decode(encode(ack, Header{}));
  EXPECT_EQ(decode<CommandAck>(f.at(0))->result, kResultDenied);
  EXPECT_EQ(d.stats().frames, 5U);
}

TEST(MavlinkDecoder, FindsEveryFrameOfADatagramAndSkipsGarbageBetween) {
  Bytes dgram = {0x00, 0xFD};  // a stray magic with nothing after it is not a frame
  dgram.insert(dgram.end(), kHeartbeat.begin(), kHeartbeat.end());
  dgram.push_back(0x55);
  dgram.insert(dgram.end(), kPosition.begin(), kPosition.end());
  Decoder d;
  const auto frames = d.decode(dgram);
  ASSERT_EQ(frames.size(), 2U);
  EXPECT_EQ(frames[0].header.msgid, Heartbeat::kId);
  EXPECT_EQ(frames[1].header.msgid, GlobalPositionInt::kId);
  EXPECT_EQ(d.stats().frames, 2U);
  EXPECT_GE(d.stats().skipped_bytes, 3U);
}

TEST(MavlinkDecoder, ACorruptedOrCutFrameIsCountedNotReturned) {
  Decoder d;
  Bytes bad = kHeartbeat;
  bad[14] ^= 0x01;  // type 2 -> 3: the CRC no longer checks
  EXPECT_TRUE(d.decode(bad).empty());
  EXPECT_EQ(d.stats().bad_crc, 1U);
  const Bytes cut(kHeartbeat.begin(), kHeartbeat.end() - 1);
  EXPECT_TRUE(d.decode(cut).empty());
  EXPECT_GE(d.stats().truncated, 1U);
  Bytes unknown = kHeartbeat;
  unknown[7] = 0x99;  // msgid 153, not one we know
  EXPECT_TRUE(d.decode(unknown).empty());
  EXPECT_EQ(d.stats().unknown_msgid, 1U);
  EXPECT_EQ(d.stats().frames, 0U);
}

// --- the command gate -----------------------------------------------------------

std::chrono::system_clock::time_point at_timestamp(uint64_t ts) {
  using namespace std::chrono;
  return system_clock::time_point{seconds(1420070400)} + microseconds(ts * 10);
}

TEST(MavlinkCommandGate, ASignedPauseIsTakenAndItsReplayRefused) {
  CommandGate gate(counting_key());
  const auto now = at_timestamp(0x123456789AULL + 100);
  auto cmds = gate.take(kSignedPause, now);
  ASSERT_EQ(cmds.size(), 1U);
  EXPECT_EQ(cmds[0].action, CommandGate::Action::Pause);
  EXPECT_EQ(cmds[0].from_sysid, 255);
  EXPECT_EQ(cmds[0].from_compid, 190);
  EXPECT_TRUE(gate.take(kSignedPause, now).empty());
  EXPECT_EQ(gate.stats().replayed, 1U);
  EXPECT_EQ(gate.stats().accepted, 1U);
}

TEST(MavlinkCommandGate, UnsignedAndBadlySignedCommandsAreCountedAndDropped) {
  const SecretKey key = counting_key();
  CommandGate gate(key);
  const auto now = std::chrono::system_clock::now();
  const uint64_t ts = signing_timestamp(now);
  EXPECT_TRUE(gate.take(encode(pause_command(), Header{}), now).empty());
  EXPECT_EQ(gate.stats().unsigned_refused, 1U);
  SecretKey wrong = key;
  wrong.bytes[0] ^= 0xFF;
  EXPECT_TRUE(gate.take(encode(pause_command(), Header{}, Signing{&wrong, 0, ts}), now).empty());
  EXPECT_EQ(gate.stats().bad_signature, 1U);
  // A ground station without the key takes no command, whoever signed it.
  CommandGate keyless(std::nullopt);
  EXPECT_TRUE(keyless.take(encode(pause_command(), Header{}, Signing{&key, 0, ts}), now).empty());
  EXPECT_EQ(keyless.stats().bad_signature, 1U);
  // A stale timestamp (over a minute old) is a replay.
  EXPECT_TRUE(gate.take(encode(pause_command(), Header{}, Signing{&key, 0, ts - 6'000'001}), now).empty());
  EXPECT_EQ(gate.stats().replayed, 1U);
  EXPECT_EQ(gate.stats().accepted, 0U);
}

// `pheromesh replay --mavlink` holds no key: its gate takes a command signed
// or not, and the same signed frame twice (nothing it steers needs that).
TEST(MavlinkCommandGate, AGateThatChecksNoSignatureTakesUnsignedAndSignedCommandsAlike) {
  const SecretKey key = counting_key();
  CommandGate gate(std::nullopt, CommandGate::Signatures::NotChecked);
  const auto now = std::chrono::system_clock::now();
  const Bytes signed_pause = encode(pause_command(), Header{}, Signing{&key, 0, signing_timestamp(now)});
  for (const Bytes& d : {encode(pause_command(), Header{}), signed_pause, signed_pause}) {
    const auto cmds = gate.take(d, now);
    ASSERT_EQ(cmds.size(), 1U);
    EXPECT_EQ(cmds[0].action, CommandGate::Action::Pause);
  }
  EXPECT_EQ(gate.stats().accepted, 3U);
  EXPECT_EQ(gate.stats().unsigned_refused + gate.stats().bad_signature + gate.stats().replayed, 0U);
  // Its guard: the same three frames through a keyless gate that requires signatures.
  CommandGate required(std::nullopt);
  for (const Bytes& d : {encode(pause_command(), Header{}), signed_pause}) EXPECT_TRUE(required.take(d, now).empty());
}

TEST(MavlinkCommandGate, ContinueDisarmAndOthersAreMappedAndHeartbeatsIgnored) {
  const SecretKey key = counting_key();
  CommandGate gate(key);
  const auto now = std::chrono::system_clock::now();
  uint64_t ts = signing_timestamp(now);
  const auto signed_cmd = [&](uint16_t command, float p1) {
    CommandLong c;
    c.command = command;
    c.param[0] = p1;
    return encode(c, Header{}, Signing{&key, 0, ++ts});
  };
  Bytes dgram = signed_cmd(kCmdDoPauseContinue, 1.0F);
  for (const auto& f : {signed_cmd(kCmdComponentArmDisarm, 0.0F), signed_cmd(kCmdComponentArmDisarm, 1.0F),
                        signed_cmd(kCmdDoPauseContinue, 0.5F), signed_cmd(21, 0.0F), encode(Heartbeat{}, Header{})}) {
    dgram.insert(dgram.end(), f.begin(), f.end());
  }
  const auto cmds = gate.take(dgram, now);
  ASSERT_EQ(cmds.size(), 5U);
  using A = CommandGate::Action;
  EXPECT_EQ(cmds[0].action, A::Resume);
  EXPECT_EQ(cmds[1].action, A::Stop);
  EXPECT_EQ(cmds[2].action, A::Unsupported);  // arm
  EXPECT_EQ(cmds[3].action, A::Unsupported);  // pause-continue 0.5
  EXPECT_EQ(cmds[4].action, A::Unsupported);  // NAV_LAND
  EXPECT_EQ(gate.stats().other_messages, 1U);
}

TEST(MavlinkCommandGate, StreamsRememberedStayBounded) {
  const SecretKey key = counting_key();
  CommandGate gate(key);
  const auto now = std::chrono::system_clock::now();
  const uint64_t ts = signing_timestamp(now);
  for (int i = 0; i < 600; ++i) {
    const auto f = encode(pause_command(), Header{0, static_cast<uint8_t>(i % 256), static_cast<uint8_t>(i / 256), 0},
                          Signing{&key, 0, ts});
    EXPECT_EQ(gate.take(f, now).size(), 1U) << i;
  }
  EXPECT_EQ(gate.stats().accepted, 600U);
}

}  // namespace
}  // namespace pheromesh::mavlink
