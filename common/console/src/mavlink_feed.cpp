#include "pheromesh/console/mavlink_feed.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "pheromesh/mavlink/messages.hpp"

namespace pheromesh::console {

namespace ml = pheromesh::mavlink;
using Clock = MavlinkFeed::Clock;

namespace {

int32_t deg_e7(double deg) { return static_cast<int32_t>(std::llround(deg * 1e7)); }
int32_t mm(double m) { return static_cast<int32_t>(std::llround(std::clamp(m * 1000.0, -2.0e9, 2.0e9))); }
int16_t cm_s16(double mps) { return static_cast<int16_t>(std::lround(std::clamp(mps * 100.0, -32767.0, 32767.0))); }
uint16_t cm_u16(double mps) { return static_cast<uint16_t>(std::lround(std::clamp(mps * 100.0, 0.0, 65534.0))); }
uint16_t cdeg(double deg) { return static_cast<uint16_t>(std::lround(deg * 100.0) % 36000); }

}  // namespace

core::Result<MavlinkTarget> parse_mavlink_target(std::string_view value, std::string_view flag) {
  const auto bad = [&](const std::string& why) -> core::Result<MavlinkTarget> {
    // CLI11 names the flag itself: with flag "" the message starts at the value.
    return core::Error{(flag.empty() ? std::string() : std::string(flag) + " ") + std::string(value) + ": " + why +
                       "; give udp:HOST:PORT, e.g. udp:127.0.0.1:14550 (QGroundControl listens on UDP 14550)"};
  };
  constexpr std::string_view kScheme = "udp:";
  if (value.substr(0, kScheme.size()) != kScheme) return bad("only udp: is supported");
  const std::string_view rest = value.substr(kScheme.size());
  const std::size_t colon = rest.rfind(':');
  if (colon == std::string_view::npos || colon == 0) return bad("HOST and PORT are both needed");
  const std::string_view host = rest.substr(0, colon);
  const std::string_view port = rest.substr(colon + 1);
  if (host.find(':') != std::string_view::npos) return bad("the host must be a name or an IPv4 address");
  if (std::any_of(host.begin(), host.end(), [](char c) { return c == ' ' || c == '\t'; })) {
    return bad("the host must not contain spaces");
  }
  unsigned long p = 0;
  const auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), p);
  if (port.empty() || ec != std::errc() || end != port.data() + port.size() || p == 0 || p > 65535) {
    return bad("the port must be a number 1..65535");
  }
  return MavlinkTarget{std::string(host), static_cast<uint16_t>(p)};
}

core::Result<double> check_mavlink_rate(double hz, std::string_view flag) {
  if (std::isfinite(hz) && hz >= kMavlinkMinRateHz && hz <= kMavlinkMaxRateHz) return hz;
  char buf[160];
  std::snprintf(buf, sizeof buf,
                " %g: must be between %g and %g [Hz] (position, attitude and ADS-B reports per UAV per second)", hz,
                kMavlinkMinRateHz, kMavlinkMaxRateHz);
  return core::Error{std::string(flag) + buf};
}

uint32_t mavlink_icao_address(uint32_t uav) { return 0xFA0000U + (uav & 0xFFFFU); }
std::string mavlink_callsign(uint32_t uav) { return "PH" + std::to_string(uav); }

MavlinkRun mavlink_run_of(const core::ScenarioConfig& scenario) {
  return {scenario.geo, scenario.tick_rate_hz, scenario.geometry().region_count(), scenario.targets.size()};
}

MavlinkSwarm mavlink_swarm_of(const core::RunRecorder& rec, uint32_t regions) {
  MavlinkSwarm out;
  for (core::RegionId r = 0; r < regions; ++r) out.places_lost += rec.region_departed(r) ? 1U : 0U;
  for (const auto& [id, u] : rec.uavs()) {
    out.uavs_lost += u.alive ? 0U : 1U;
    if (!u.heard) continue;
    out.uavs.push_back({id, u.heard_tick, u.last.x, u.last.y, u.last.vx, u.last.vy, u.alive, u.finished});
  }
  out.targets_found = rec.acquisitions().found();
  return out;
}

MavlinkFeed::MavlinkFeed(const MavlinkRun& run, double rate_hz, Clock::time_point start)
    : geo_(run.geo),
      cells_per_tick_to_mps_(run.geo.cell_size_m * run.tick_rate_hz),
      regions_(run.regions),
      targets_(run.targets),
      position_period_(std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / rate_hz))),
      start_(start),
      next_heartbeat_(start),
      next_position_(start) {}

void MavlinkFeed::note(const IntakeNote& n) {
  using K = IntakeNote::Kind;
  if (n.kind != K::PlaceLost && n.kind != K::PlaceBack && n.kind != K::UavLost && n.kind != K::UavBack &&
      n.kind != K::TargetAcquired) {
    return;
  }
  if (texts_.size() >= kMavlinkTextQueue) {
    ++stats_.texts_dropped;
    return;
  }
  texts_.push_back(n.text);
}

void MavlinkFeed::put(std::vector<uint8_t> frame) {
  ++stats_.frames;
  if (out_.empty() || out_.back().size() + frame.size() > kMavlinkDatagramBytes) out_.emplace_back();
  out_.back().insert(out_.back().end(), frame.begin(), frame.end());
}

std::vector<std::vector<uint8_t>> MavlinkFeed::due(const MavlinkSwarm& swarm, Clock::time_point now) {
  out_.clear();
  const auto boot_ms =
      static_cast<uint32_t>(std::chrono::duration_cast<std::chrono::milliseconds>(now - start_).count());
  for (const MavlinkUav& u : swarm.uavs) {
    auto [it, fresh] = heard_tick_.try_emplace(u.id, u.tick);
    if (fresh || it->second != u.tick) {
      it->second = u.tick;
      heard_at_[u.id] = now;
    }
  }
  if (now >= next_heartbeat_) {
    next_heartbeat_ = std::max(next_heartbeat_ + std::chrono::seconds(1), now);
    heartbeats(swarm);
    ground_status(swarm);
  }
  if (now >= next_position_) {
    next_position_ = std::max(next_position_ + position_period_, now);
    positions(swarm, now, boot_ms);
  }
  while (!texts_.empty()) {
    status_text(texts_.front());
    texts_.pop_front();
  }
  stats_.datagrams += out_.size();
  return std::move(out_);
}

void MavlinkFeed::status_text(const std::string& text) {
  // A text longer than one STATUSTEXT goes in chunks of 50 bytes under one
  // non-zero id, chunk_seq counting from 0 (common.xml, STATUSTEXT); a
  // single chunk has id 0. Cut at kMavlinkTextChunks chunks.
  const std::size_t n = ml::StatusText::kTextLen;
  const std::size_t chunks = std::min<std::size_t>((text.size() + n - 1) / n, kMavlinkTextChunks);
  if (chunks > 1 && ++text_id_ == 0) ++text_id_;
  for (std::size_t c = 0; c < std::max<std::size_t>(chunks, 1); ++c) {
    ml::StatusText t;
    t.severity = ml::kSeverityNotice;
    t.text = text.substr(std::min(text.size(), c * n), n);
    t.id = chunks > 1 ? text_id_ : 0;
    t.chunk_seq = static_cast<uint8_t>(c);
    put(ml::encode(t, {next_seq(kMavlinkGroundSysid), kMavlinkGroundSysid, kMavlinkCompid, 0}));
  }
}

void MavlinkFeed::heartbeats(const MavlinkSwarm& swarm) {
  ml::Heartbeat g;
  g.type = ml::kMavTypeGcs;
  g.autopilot = ml::kMavAutopilotInvalid;
  g.system_status = ml::kMavStateActive;
  put(ml::encode(g, {next_seq(kMavlinkGroundSysid), kMavlinkGroundSysid, kMavlinkCompid, 0}));
  for (const MavlinkUav& u : swarm.uavs) {
    // A lost UAV falls silent: the station reports the link lost, as for a real one.
    if (u.id >= kMavlinkMaxVehicles || !u.alive) continue;
    const auto sysid = static_cast<uint8_t>(u.id + 1);
    ml::Heartbeat h;
    h.type = ml::kMavTypeQuadrotor;
    h.autopilot = ml::kMavAutopilotGeneric;
    if (u.finished) {
      h.system_status = ml::kMavStatePoweroff;
    } else {
      h.base_mode = ml::kMavModeFlagSafetyArmed | ml::kMavModeFlagAutoEnabled;
      h.system_status = paused_ ? ml::kMavStateStandby : ml::kMavStateActive;
    }
    put(ml::encode(h, {next_seq(sysid), sysid, kMavlinkCompid, 0}));
  }
}

void MavlinkFeed::ground_status(const MavlinkSwarm& swarm) {
  // SYS_STATUS of the ground station (docs/mavlink.md): the swarm's health
  // in the counters a station shows.
  const uint32_t places_lost = swarm.places_lost, uavs_lost = swarm.uavs_lost;
  ml::SysStatus s;
  s.drop_rate_comm = regions_ == 0 ? 0 : static_cast<uint16_t>(10000U * places_lost / regions_);
  s.errors_count[0] = static_cast<uint16_t>(std::min<uint32_t>(places_lost, UINT16_MAX));
  s.errors_count[1] = static_cast<uint16_t>(std::min<uint32_t>(uavs_lost, UINT16_MAX));
  s.errors_count[2] = static_cast<uint16_t>(std::min<std::size_t>(swarm.targets_found, UINT16_MAX));
  s.errors_count[3] = static_cast<uint16_t>(std::min<std::size_t>(targets_, UINT16_MAX));
  s.voltage_battery = UINT16_MAX;
  put(ml::encode(s, {next_seq(kMavlinkGroundSysid), kMavlinkGroundSysid, kMavlinkCompid, 0}));
}

void MavlinkFeed::positions(const MavlinkSwarm& swarm, Clock::time_point now, uint32_t boot_ms) {
  for (const MavlinkUav& u : swarm.uavs) {
    if (u.alive) position(u, now, boot_ms);
  }
}

void MavlinkFeed::position(const MavlinkUav& u, Clock::time_point now, uint32_t boot_ms) {
  const uint32_t id = u.id;
  const core::GeoPoint g = core::map_to_geo(geo_, {u.x, u.y});
  const double east_mps = u.vx * cells_per_tick_to_mps_;
  const double north_mps = -u.vy * cells_per_tick_to_mps_;  // rows grow to the south
  const double heading = core::heading_deg(u.vx, u.vy);
  if (id < kMavlinkMaxVehicles) {
    const auto sysid = static_cast<uint8_t>(id + 1);
    ml::GlobalPositionInt p;
    p.time_boot_ms = boot_ms;
    p.lat = deg_e7(g.lat_deg);
    p.lon = deg_e7(g.lon_deg);
    p.alt = mm(g.alt_m);
    p.relative_alt = mm(geo_.flight_height_m);
    p.vx = cm_s16(north_mps);
    p.vy = cm_s16(east_mps);
    p.hdg = cdeg(heading);
    put(ml::encode(p, {next_seq(sysid), sysid, kMavlinkCompid, 0}));
    ml::Attitude a;
    a.time_boot_ms = boot_ms;
    const double yaw = heading > 180.0 ? heading - 360.0 : heading;
    a.yaw = static_cast<float>(yaw * std::numbers::pi / 180.0);
    put(ml::encode(a, {next_seq(sysid), sysid, kMavlinkCompid, 0}));
  }
  ml::AdsbVehicle v;
  v.icao_address = mavlink_icao_address(id);
  v.lat = deg_e7(g.lat_deg);
  v.lon = deg_e7(g.lon_deg);
  v.altitude = mm(g.alt_m);
  v.heading = cdeg(heading);
  v.hor_velocity = cm_u16(std::hypot(east_mps, north_mps));
  v.flags = ml::kAdsbFlagValidCoords | ml::kAdsbFlagValidAltitude | ml::kAdsbFlagValidHeading |
            ml::kAdsbFlagValidVelocity | ml::kAdsbFlagValidCallsign | ml::kAdsbFlagSimulated;
  v.altitude_type = ml::kAdsbAltitudeGeometric;
  v.callsign = mavlink_callsign(id);
  v.emitter_type = ml::kAdsbEmitterUav;
  const auto heard = heard_at_.find(id);
  const double silent_s = heard == heard_at_.end() ? 0.0 : std::chrono::duration<double>(now - heard->second).count();
  v.tslc = static_cast<uint8_t>(std::clamp(silent_s, 0.0, 255.0));
  put(ml::encode(v, {next_seq(kMavlinkGroundSysid), kMavlinkGroundSysid, kMavlinkCompid, 0}));
}

std::vector<uint8_t> MavlinkFeed::ack(const mavlink::CommandGate::Command& c, uint8_t result,
                                      const std::optional<mavlink::Signing>& signing) {
  ml::CommandAck a;
  a.command = c.message.command;
  a.result = result;
  a.target_system = c.from_sysid;
  a.target_component = c.from_compid;
  ++stats_.frames;
  return ml::encode(a, {next_seq(kMavlinkGroundSysid), kMavlinkGroundSysid, kMavlinkCompid, 0}, signing);
}

}  // namespace pheromesh::console
