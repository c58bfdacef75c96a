// The MAVLink messages pheromesh speaks, from the common message set
// (message_definitions/v1.0/common.xml, standard.xml, minimal.xml of the
// MAVLink project). Each lists its fields in wire order: the base fields
// sorted by type size, largest first (stable for equal sizes), then the
// extension fields in their declared order. kCrcExtra is the CRC_EXTRA of
// the definition; kLen the payload length with every extension.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "pheromesh/mavlink/frame.hpp"

namespace pheromesh::mavlink {

// Enum values used here (common.xml, minimal.xml).
inline constexpr uint8_t kMavTypeQuadrotor = 2;     // MAV_TYPE_QUADROTOR
inline constexpr uint8_t kMavTypeGcs = 6;           // MAV_TYPE_GCS
inline constexpr uint8_t kMavAutopilotGeneric = 0;  // MAV_AUTOPILOT_GENERIC
inline constexpr uint8_t kMavAutopilotInvalid = 8;  // MAV_AUTOPILOT_INVALID (not a flight controller)
inline constexpr uint8_t kMavModeFlagSafetyArmed = 128;
inline constexpr uint8_t kMavModeFlagGuidedEnabled = 8;
inline constexpr uint8_t kMavModeFlagAutoEnabled = 4;
inline constexpr uint8_t kMavStateStandby = 3;
inline constexpr uint8_t kMavStateActive = 4;
inline constexpr uint8_t kMavStateCritical = 5;
inline constexpr uint8_t kMavStatePoweroff = 7;
inline constexpr uint8_t kMavlinkVersion = 3;            // HEARTBEAT.mavlink_version
inline constexpr uint8_t kSeverityWarning = 4;           // MAV_SEVERITY_WARNING
inline constexpr uint8_t kSeverityNotice = 5;            // MAV_SEVERITY_NOTICE
inline constexpr uint8_t kSeverityInfo = 6;              // MAV_SEVERITY_INFO
inline constexpr uint16_t kCmdDoPauseContinue = 193;     // MAV_CMD_DO_PAUSE_CONTINUE
inline constexpr uint16_t kCmdComponentArmDisarm = 400;  // MAV_CMD_COMPONENT_ARM_DISARM
inline constexpr uint8_t kResultAccepted = 0;            // MAV_RESULT_ACCEPTED
inline constexpr uint8_t kResultTemporarilyRejected = 1;
inline constexpr uint8_t kResultDenied = 2;
inline constexpr uint8_t kResultUnsupported = 3;
inline constexpr uint8_t kResultFailed = 4;
inline constexpr uint16_t kAdsbFlagValidCoords = 1;
inline constexpr uint16_t kAdsbFlagValidAltitude = 2;
inline constexpr uint16_t kAdsbFlagValidHeading = 4;
inline constexpr uint16_t kAdsbFlagValidVelocity = 8;
inline constexpr uint16_t kAdsbFlagValidCallsign = 16;
inline constexpr uint16_t kAdsbFlagSimulated = 64;
inline constexpr uint8_t kAdsbAltitudeGeometric = 1;  // ADSB_ALTITUDE_TYPE_GEOMETRIC
inline constexpr uint8_t kAdsbEmitterUav = 14;        // ADSB_EMITTER_TYPE_UAV

// HEARTBEAT (0).
struct Heartbeat {
  static constexpr uint32_t kId = 0;
  static constexpr uint8_t kCrcExtra = 50;
  static constexpr std::size_t kLen = 9;
  uint32_t custom_mode = 0;
  uint8_t type = 0;
  uint8_t autopilot = 0;
  uint8_t base_mode = 0;
  uint8_t system_status = 0;
  uint8_t mavlink_version = kMavlinkVersion;
  [[nodiscard]] std::vector<uint8_t> payload() const;
  static Heartbeat from(std::span<const uint8_t> payload);
};

// SYS_STATUS (1); the extension fields (sensors *_extended) are sent as 0.
struct SysStatus {
  static constexpr uint32_t kId = 1;
  static constexpr uint8_t kCrcExtra = 124;
  static constexpr std::size_t kLen = 43;
  uint32_t sensors_present = 0, sensors_enabled = 0, sensors_health = 0;  // MAV_SYS_STATUS_SENSOR bits
  uint16_t load = 0;                                                      // [d%]
  uint16_t voltage_battery = 0;                                           // [mV], UINT16_MAX unknown
  int16_t current_battery = -1;                                           // [cA], -1 unknown
  uint16_t drop_rate_comm = 0;                                            // [c%]
  uint16_t errors_comm = 0;
  uint16_t errors_count[4] = {0, 0, 0, 0};
  int8_t battery_remaining = -1;  // [%], -1 unknown
  [[nodiscard]] std::vector<uint8_t> payload() const;
  static SysStatus from(std::span<const uint8_t> payload);
};

// ATTITUDE (30).
struct Attitude {
  static constexpr uint32_t kId = 30;
  static constexpr uint8_t kCrcExtra = 39;
  static constexpr std::size_t kLen = 28;
  uint32_t time_boot_ms = 0;                          // [ms]
  float roll = 0, pitch = 0, yaw = 0;                 // [rad], yaw -pi..pi clockwise from north
  float rollspeed = 0, pitchspeed = 0, yawspeed = 0;  // [rad/s]
  [[nodiscard]] std::vector<uint8_t> payload() const;
  static Attitude from(std::span<const uint8_t> payload);
};

// GLOBAL_POSITION_INT (33).
struct GlobalPositionInt {
  static constexpr uint32_t kId = 33;
  static constexpr uint8_t kCrcExtra = 104;
  static constexpr std::size_t kLen = 28;
  uint32_t time_boot_ms = 0;       // [ms]
  int32_t lat = 0, lon = 0;        // [degE7]
  int32_t alt = 0;                 // [mm] above mean sea level
  int32_t relative_alt = 0;        // [mm] above home
  int16_t vx = 0, vy = 0, vz = 0;  // [cm/s] north, east, down
  uint16_t hdg = UINT16_MAX;       // [cdeg] 0..35999, UINT16_MAX unknown
  [[nodiscard]] std::vector<uint8_t> payload() const;
  static GlobalPositionInt from(std::span<const uint8_t> payload);
};

// COMMAND_LONG (76).
struct CommandLong {
  static constexpr uint32_t kId = 76;
  static constexpr uint8_t kCrcExtra = 152;
  static constexpr std::size_t kLen = 33;
  float param[7] = {0, 0, 0, 0, 0, 0, 0};  // param1..param7
  uint16_t command = 0;                    // MAV_CMD
  uint8_t target_system = 0, target_component = 0;
  uint8_t confirmation = 0;
  [[nodiscard]] std::vector<uint8_t> payload() const;
  static CommandLong from(std::span<const uint8_t> payload);
};

// COMMAND_ACK (77).
struct CommandAck {
  static constexpr uint32_t kId = 77;
  static constexpr uint8_t kCrcExtra = 143;
  static constexpr std::size_t kLen = 10;
  uint16_t command = 0;
  uint8_t result = 0;  // MAV_RESULT
  uint8_t progress = 0;
  int32_t result_param2 = 0;
  uint8_t target_system = 0, target_component = 0;
  [[nodiscard]] std::vector<uint8_t> payload() const;
  static CommandAck from(std::span<const uint8_t> payload);
};

// ADSB_VEHICLE (246).
struct AdsbVehicle {
  static constexpr uint32_t kId = 246;
  static constexpr uint8_t kCrcExtra = 184;
  static constexpr std::size_t kLen = 38;
  uint32_t icao_address = 0;
  int32_t lat = 0, lon = 0;   // [degE7]
  int32_t altitude = 0;       // [mm]
  uint16_t heading = 0;       // [cdeg]
  uint16_t hor_velocity = 0;  // [cm/s]
  int16_t ver_velocity = 0;   // [cm/s] up
  uint16_t flags = 0;         // ADSB_FLAGS
  uint16_t squawk = 0;
  uint8_t altitude_type = 0;
  std::string callsign;  // up to 8 characters (9 sent, NUL-padded)
  uint8_t emitter_type = 0;
  uint8_t tslc = 0;  // [s] since last communication
  [[nodiscard]] std::vector<uint8_t> payload() const;
  static AdsbVehicle from(std::span<const uint8_t> payload);
};

// STATUSTEXT (253).
struct StatusText {
  static constexpr uint32_t kId = 253;
  static constexpr uint8_t kCrcExtra = 83;
  static constexpr std::size_t kLen = 54;
  static constexpr std::size_t kTextLen = 50;
  uint8_t severity = kSeverityInfo;
  std::string text;  // up to 50 bytes; longer text is cut
  uint16_t id = 0;
  uint8_t chunk_seq = 0;
  [[nodiscard]] std::vector<uint8_t> payload() const;
  static StatusText from(std::span<const uint8_t> payload);
};

// A frame of message `m`.
template <class M>
std::vector<uint8_t> encode(const M& m, Header h, const std::optional<Signing>& signing = std::nullopt) {
  h.msgid = M::kId;
  const std::vector<uint8_t> p = m.payload();
  return encode_frame(h, p, M::kCrcExtra, signing);
}

// Message `M` of a frame of its id (its payload zero-extended to kLen:
// MAVLink 2 truncation); nullopt for another id.
template <class M>
std::optional<M> decode(const Frame& f) {
  if (f.header.msgid != M::kId) return std::nullopt;
  return M::from(f.payload);
}

}  // namespace pheromesh::mavlink
