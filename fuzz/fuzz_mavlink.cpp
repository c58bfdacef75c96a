// Fuzz harness: what the ground station reads from a MAVLink ground-control
// station (docs/mavlink.md): a UDP datagram split into frames
// (mavlink::Decoder), each COMMAND_LONG checked for its signature and
// freshness (mavlink::CommandGate), and every message decoded from whatever
// frame carries its id. Invariants: a returned frame is whole (its bytes are
// header + payload + CRC (+ signature)) and decodes again to itself.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <span>

#include "pheromesh/mavlink/command_gate.hpp"
#include "pheromesh/mavlink/frame.hpp"
#include "pheromesh/mavlink/messages.hpp"

using namespace pheromesh;

namespace {

mavlink::SecretKey fixed_key() {
  mavlink::SecretKey k;
  for (std::size_t i = 0; i < k.bytes.size(); ++i) k.bytes[i] = static_cast<uint8_t>(i);
  return k;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const std::span<const uint8_t> in(data, size);
  // The seeds' signed frames carry timestamps near 0x123456789A.
  static const auto now = std::chrono::system_clock::time_point{std::chrono::seconds(1420070400)} +
                          std::chrono::microseconds(uint64_t{0x123456789A} * 10);
  mavlink::CommandGate gate(fixed_key());
  (void)gate.take(in, now);
  (void)gate.malformed();

  mavlink::Decoder d;
  for (const mavlink::Frame& f : d.decode(in)) {
    const std::size_t want =
        mavlink::kHeaderLen + f.payload.size() + mavlink::kCrcLen + (f.is_signed ? mavlink::kSignatureLen : 0);
    if (f.bytes.size() != want || f.payload.size() > mavlink::kMaxPayloadLen) __builtin_trap();
    mavlink::Decoder again;
    if (again.decode(f.bytes).size() != 1) __builtin_trap();
    (void)mavlink::signature_valid(f, fixed_key());
    (void)mavlink::decode<mavlink::Heartbeat>(f);
    (void)mavlink::decode<mavlink::SysStatus>(f);
    (void)mavlink::decode<mavlink::Attitude>(f);
    (void)mavlink::decode<mavlink::GlobalPositionInt>(f);
    (void)mavlink::decode<mavlink::CommandLong>(f);
    (void)mavlink::decode<mavlink::CommandAck>(f);
    (void)mavlink::decode<mavlink::AdsbVehicle>(f);
    (void)mavlink::decode<mavlink::StatusText>(f);
  }
  return 0;
}
