#include "pheromesh/mavlink/messages.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

namespace pheromesh::mavlink {

namespace {

// Little-endian fields written one after the other, in wire order.
class Put {
 public:
  explicit Put(std::size_t len) { b_.reserve(len); }
  template <class T>
  Put& le(T v) {
    using U = std::make_unsigned_t<
        std::conditional_t<std::is_floating_point_v<T>, std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>, T>>;
    U u = 0;
    if constexpr (std::is_floating_point_v<T>) {
      u = std::bit_cast<U>(v);
    } else {
      u = static_cast<U>(v);
    }
    for (std::size_t i = 0; i < sizeof(T); ++i) b_.push_back(static_cast<uint8_t>(u >> (8 * i)));
    return *this;
  }
  // A char[n] field: the text cut to n bytes, NUL-padded.
  Put& chars(const std::string& s, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) b_.push_back(i < s.size() ? static_cast<uint8_t>(s[i]) : 0);
    return *this;
  }
  std::vector<uint8_t> done() { return std::move(b_); }

 private:
  std::vector<uint8_t> b_;
};

// Reads a payload zero-extended to `len` (MAVLink 2 truncation); bytes past
// `len` (a newer definition's extensions) are ignored.
class Get {
 public:
  Get(std::span<const uint8_t> p, std::size_t len) : b_(len, 0) {
    std::copy_n(p.begin(), std::min(p.size(), len), b_.begin());
  }
  template <class T>
  T le() {
    using U = std::make_unsigned_t<
        std::conditional_t<std::is_floating_point_v<T>, std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>, T>>;
    U u = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) u = static_cast<U>(u | (static_cast<U>(b_[at_ + i]) << (8 * i)));
    at_ += sizeof(T);
    if constexpr (std::is_floating_point_v<T>) {
      return std::bit_cast<T>(u);
    } else {
      return static_cast<T>(u);
    }
  }
  // A char[n] field up to its first NUL.
  std::string chars(std::size_t n) {
    std::string s;
    for (std::size_t i = 0; i < n && b_[at_ + i] != 0; ++i) s.push_back(static_cast<char>(b_[at_ + i]));
    at_ += n;
    return s;
  }

 private:
  std::vector<uint8_t> b_;
  std::size_t at_ = 0;
};

}  // namespace

std::vector<uint8_t> Heartbeat::payload() const {
  return Put(kLen).le(custom_mode).le(type).le(autopilot).le(base_mode).le(system_status).le(mavlink_version).done();
}
Heartbeat Heartbeat::from(std::span<const uint8_t> p) {
  Get g(p, kLen);
  Heartbeat m;
  m.custom_mode = g.le<uint32_t>();
  m.type = g.le<uint8_t>();
  m.autopilot = g.le<uint8_t>();
  m.base_mode = g.le<uint8_t>();
  m.system_status = g.le<uint8_t>();
  m.mavlink_version = g.le<uint8_t>();
  return m;
}

std::vector<uint8_t> SysStatus::payload() const {
  Put p(kLen);
  p.le(sensors_present).le(sensors_enabled).le(sensors_health).le(load).le(voltage_battery).le(current_battery);
  p.le(drop_rate_comm).le(errors_comm);
  for (const uint16_t e : errors_count) p.le(e);
  p.le(battery_remaining).le(uint32_t{0}).le(uint32_t{0}).le(uint32_t{0});
  return p.done();
}
SysStatus SysStatus::from(std::span<const uint8_t> p) {
  Get g(p, kLen);
  SysStatus m;
  m.sensors_present = g.le<uint32_t>();
  m.sensors_enabled = g.le<uint32_t>();
  m.sensors_health = g.le<uint32_t>();
  m.load = g.le<uint16_t>();
  m.voltage_battery = g.le<uint16_t>();
  m.current_battery = g.le<int16_t>();
  m.drop_rate_comm = g.le<uint16_t>();
  m.errors_comm = g.le<uint16_t>();
  for (uint16_t& e : m.errors_count) e = g.le<uint16_t>();
  m.battery_remaining = g.le<int8_t>();
  return m;
}

std::vector<uint8_t> Attitude::payload() const {
  return Put(kLen).le(time_boot_ms).le(roll).le(pitch).le(yaw).le(rollspeed).le(pitchspeed).le(yawspeed).done();
}
Attitude Attitude::from(std::span<const uint8_t> p) {
  Get g(p, kLen);
  Attitude m;
  m.time_boot_ms = g.le<uint32_t>();
  m.roll = g.le<float>();
  m.pitch = g.le<float>();
  m.yaw = g.le<float>();
  m.rollspeed = g.le<float>();
  m.pitchspeed = g.le<float>();
  m.yawspeed = g.le<float>();
  return m;
}

std::vector<uint8_t> GlobalPositionInt::payload() const {
  return Put(kLen).le(time_boot_ms).le(lat).le(lon).le(alt).le(relative_alt).le(vx).le(vy).le(vz).le(hdg).done();
}
GlobalPositionInt GlobalPositionInt::from(std::span<const uint8_t> p) {
  Get g(p, kLen);
  GlobalPositionInt m;
  m.time_boot_ms = g.le<uint32_t>();
  m.lat = g.le<int32_t>();
  m.lon = g.le<int32_t>();
  m.alt = g.le<int32_t>();
  m.relative_alt = g.le<int32_t>();
  m.vx = g.le<int16_t>();
  m.vy = g.le<int16_t>();
  m.vz = g.le<int16_t>();
  m.hdg = g.le<uint16_t>();
  return m;
}

std::vector<uint8_t> CommandLong::payload() const {
  Put p(kLen);
  for (const float v : param) p.le(v);
  return p.le(command).le(target_system).le(target_component).le(confirmation).done();
}
CommandLong CommandLong::from(std::span<const uint8_t> p) {
  Get g(p, kLen);
  CommandLong m;
  for (float& v : m.param) v = g.le<float>();
  m.command = g.le<uint16_t>();
  m.target_system = g.le<uint8_t>();
  m.target_component = g.le<uint8_t>();
  m.confirmation = g.le<uint8_t>();
  return m;
}

std::vector<uint8_t> CommandAck::payload() const {
  return Put(kLen).le(command).le(result).le(progress).le(result_param2).le(target_system).le(target_component).done();
}
CommandAck CommandAck::from(std::span<const uint8_t> p) {
  Get g(p, kLen);
  CommandAck m;
  m.command = g.le<uint16_t>();
  m.result = g.le<uint8_t>();
  m.progress = g.le<uint8_t>();
  m.result_param2 = g.le<int32_t>();
  m.target_system = g.le<uint8_t>();
  m.target_component = g.le<uint8_t>();
  return m;
}

std::vector<uint8_t> AdsbVehicle::payload() const {
  Put p(kLen);
  p.le(icao_address).le(lat).le(lon).le(altitude).le(heading).le(hor_velocity).le(ver_velocity).le(flags).le(squawk);
  return p.le(altitude_type).chars(callsign, 9).le(emitter_type).le(tslc).done();
}
AdsbVehicle AdsbVehicle::from(std::span<const uint8_t> p) {
  Get g(p, kLen);
  AdsbVehicle m;
  m.icao_address = g.le<uint32_t>();
  m.lat = g.le<int32_t>();
  m.lon = g.le<int32_t>();
  m.altitude = g.le<int32_t>();
  m.heading = g.le<uint16_t>();
  m.hor_velocity = g.le<uint16_t>();
  m.ver_velocity = g.le<int16_t>();
  m.flags = g.le<uint16_t>();
  m.squawk = g.le<uint16_t>();
  m.altitude_type = g.le<uint8_t>();
  m.callsign = g.chars(9);
  m.emitter_type = g.le<uint8_t>();
  m.tslc = g.le<uint8_t>();
  return m;
}

std::vector<uint8_t> StatusText::payload() const {
  return Put(kLen).le(severity).chars(text, kTextLen).le(id).le(chunk_seq).done();
}
StatusText StatusText::from(std::span<const uint8_t> p) {
  Get g(p, kLen);
  StatusText m;
  m.severity = g.le<uint8_t>();
  m.text = g.chars(kTextLen);
  m.id = g.le<uint16_t>();
  m.chunk_seq = g.le<uint8_t>();
  return m;
}

}  // namespace pheromesh::mavlink
