// The ground station's MAVLink stream (common/console/src/mavlink_feed.cpp):
// which frames go out when, to which systems, carrying which positions; and
// the --mavlink / --mavlink-rate-hz values it refuses.
#include "pheromesh/console/mavlink_feed.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "pheromesh/core/run_metrics.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/world.hpp"
#include "pheromesh/mavlink/messages.hpp"

namespace pheromesh::console {
namespace {

namespace ml = pheromesh::mavlink;
using Clock = MavlinkFeed::Clock;
using namespace std::chrono_literals;

TEST(MavlinkTarget, UdpHostPortIsParsed) {
  const auto t = parse_mavlink_target("udp:127.0.0.1:14550");
  ASSERT_TRUE(t.ok()) << t.error().message;
  EXPECT_EQ(t.value().host, "127.0.0.1");
  EXPECT_EQ(t.value().port, 14550);
  EXPECT_TRUE(parse_mavlink_target("udp:gcs.local:1").ok());
}

TEST(MavlinkTarget, AnythingElseIsRefusedNamingTheFlagAndTheForm) {
  for (const char* bad : {"127.0.0.1:14550", "tcp:127.0.0.1:5760", "udp:127.0.0.1", "udp::14550", "udp:host:0",
                          "udp:host:65536", "udp:host:14x", "udp:host:", "udp:::1:14550", ""}) {
    const auto t = parse_mavlink_target(bad);
    ASSERT_FALSE(t.ok()) << bad;
    EXPECT_EQ(t.error().message.rfind("--mavlink ", 0), 0U) << t.error().message;
    EXPECT_NE(t.error().message.find("udp:HOST:PORT"), std::string::npos) << t.error().message;
  }
}

TEST(MavlinkRate, OutOfRangeIsRefusedNamingTheFlagAndTheRange) {
  EXPECT_TRUE(check_mavlink_rate(4.0).ok());
  EXPECT_TRUE(check_mavlink_rate(kMavlinkMaxRateHz).ok());
  EXPECT_TRUE(check_mavlink_rate(kMavlinkMinRateHz).ok());
  for (const double hz : {0.0, 0.1, 20.5, -1.0, std::nan("")}) {
    const auto r = check_mavlink_rate(hz);
    ASSERT_FALSE(r.ok()) << hz;
    EXPECT_NE(r.error().message.find("--mavlink-rate-hz"), std::string::npos);
    EXPECT_NE(r.error().message.find("between 0.2 and 20"), std::string::npos) << r.error().message;
  }
}

TEST(MavlinkAdsb, IcaoAddressAndCallsignComeFromTheUavId) {
  EXPECT_EQ(mavlink_icao_address(0), 0xFA0000U);
  EXPECT_EQ(mavlink_icao_address(999), 0xFA03E7U);
  EXPECT_EQ(mavlink_callsign(42), "PH42");
}

// A swarm of 300 UAVs on a 60 x 60 map of 2 m cells at 45° N 7° E, 10 Hz.
struct Swarm {
  core::ScenarioConfig s;
  core::MapGeometry geo;  // World keeps a pointer to it
  core::World world;
  core::RunRecorder rec;
  static core::ScenarioConfig scenario() {
    auto r = core::parse_scenario(
        "map { width: 60 height: 60 targets { x: 3 y: 3 } }\n"
        "swarm { uavs: 300 }\n"
        "geo { origin_lat_deg: 45 origin_lon_deg: 7 origin_alt_m: 250 cell_size_m: 2 flight_height_m: 40 }\n",
        "feed.textproto");
    EXPECT_TRUE(r.ok()) << r.error().message;
    return r.value();
  }
  Swarm() : s(scenario()), geo(s.geometry()), world(geo, s.obstacles, s.targets), rec(s, world) {}
  // At tick 1000 + t: any cell of the map is within reach of the start cell
  // (the recorder refuses a state the UAV could not have flown to).
  void state(uint32_t uav, uint32_t t, double x, double y, double vx = 0, double vy = 0) {
    core::UavStateMsg m;
    m.uav = uav;
    m.tick = 1000 + t;
    m.x = x;
    m.y = y;
    m.vx = vx;
    m.vy = vy;
    EXPECT_TRUE(rec.on_uav_state(m));
  }
};

std::vector<ml::Frame> frames_of(const std::vector<std::vector<uint8_t>>& datagrams) {
  ml::Decoder d;
  std::vector<ml::Frame> all;
  for (const auto& g : datagrams) {
    EXPECT_LE(g.size(), kMavlinkDatagramBytes);
    for (auto& f : d.decode(g)) all.push_back(std::move(f));
  }
  EXPECT_EQ(d.stats().bad_crc + d.stats().truncated + d.stats().skipped_bytes, 0U);
  return all;
}

TEST(MavlinkFeed, TheFirst250UavsAreVehiclesAndEveryUavIsTraffic) {
  Swarm w;
  for (uint32_t id = 0; id < 300; ++id) w.state(id, 1, id % 40, id / 40);
  const auto t0 = Clock::now();
  MavlinkFeed feed(w.s, 4.0, t0);
  const auto frames = frames_of(feed.due(w.rec, t0));
  std::set<uint8_t> heartbeat_systems, position_systems;
  std::set<uint32_t> icao;
  bool ground_heartbeat = false, sys_status = false;
  for (const auto& f : frames) {
    if (const auto hb = ml::decode<ml::Heartbeat>(f)) {
      if (f.header.sysid == kMavlinkGroundSysid) {
        ground_heartbeat = hb->type == ml::kMavTypeGcs;
      } else {
        EXPECT_EQ(hb->type, ml::kMavTypeQuadrotor);
        EXPECT_EQ(hb->system_status, ml::kMavStateActive);
        heartbeat_systems.insert(f.header.sysid);
      }
    }
    if (ml::decode<ml::GlobalPositionInt>(f)) position_systems.insert(f.header.sysid);
    if (const auto a = ml::decode<ml::AdsbVehicle>(f)) {
      EXPECT_EQ(f.header.sysid, kMavlinkGroundSysid);
      icao.insert(a->icao_address);
    }
    sys_status = sys_status || (ml::decode<ml::SysStatus>(f).has_value() && f.header.sysid == kMavlinkGroundSysid);
  }
  EXPECT_TRUE(ground_heartbeat);
  EXPECT_TRUE(sys_status);
  EXPECT_EQ(heartbeat_systems.size(), 250U);
  EXPECT_EQ(*heartbeat_systems.begin(), 1);
  EXPECT_EQ(*heartbeat_systems.rbegin(), 250);
  EXPECT_EQ(position_systems, heartbeat_systems);
  EXPECT_EQ(icao.size(), 300U);
}

// UAV 0 at (100 / 2, 50 / 2)... in cells: x = 50 (100 m east), y = 25 (50 m
// south), moving one cell east per tick: 2 m x 10 Hz = 20 m/s, heading 90°.
// At 45°: 100 m east = 100 / (N cos 45°) rad = 0.00126828172 deg, 50 m south
// = -50 / M rad = -0.00044991632 deg (M, N in test_geodetic.cpp).
TEST(MavlinkFeed, PositionHeadingAndSpeedAreInWgs84AndSiUnits) {
  Swarm w;
  w.state(0, 1, 50.0, 25.0, 1.0, 0.0);
  const auto t0 = Clock::now();
  MavlinkFeed feed(w.s, 4.0, t0);
  std::optional<ml::GlobalPositionInt> p;
  std::optional<ml::AdsbVehicle> a;
  std::optional<ml::Attitude> att;
  for (const auto& f : frames_of(feed.due(w.rec, t0 + 1500ms))) {
    if (auto m = ml::decode<ml::GlobalPositionInt>(f)) p = m;
    if (auto m = ml::decode<ml::AdsbVehicle>(f)) a = m;
    if (auto m = ml::decode<ml::Attitude>(f)) att = m;
  }
  ASSERT_TRUE(p && a && att);
  EXPECT_EQ(p->lat, 450000000 - 4499);  // -0.00044991632 deg = -4499.16 degE7
  EXPECT_EQ(p->lon, 70000000 + 12683);  // 0.00126828172 deg = 12682.8 degE7
  EXPECT_EQ(p->alt, 290000);            // 250 m ground + 40 m flight height [mm]
  EXPECT_EQ(p->relative_alt, 40000);
  EXPECT_EQ(p->vx, 0);     // north [cm/s]
  EXPECT_EQ(p->vy, 2000);  // east [cm/s]
  EXPECT_EQ(p->hdg, 9000);
  EXPECT_EQ(p->time_boot_ms, 1500U);
  EXPECT_NEAR(att->yaw, 1.5707963F, 1e-6F);
  EXPECT_EQ(a->lat, p->lat);
  EXPECT_EQ(a->lon, p->lon);
  EXPECT_EQ(a->altitude, 290000);
  EXPECT_EQ(a->heading, 9000);
  EXPECT_EQ(a->hor_velocity, 2000);
  EXPECT_EQ(a->callsign, "PH0");
  EXPECT_NE(a->flags & ml::kAdsbFlagSimulated, 0);
}

TEST(MavlinkFeed, RatesAreKeptHeartbeatsOncePerSecondPositionsAtTheirRate) {
  Swarm w;
  w.state(0, 1, 1, 1);
  const auto t0 = Clock::now();
  MavlinkFeed feed(w.s, 4.0, t0);
  std::map<uint32_t, int> count;
  for (int ms = 0; ms < 2000; ms += 50) {
    for (const auto& f : frames_of(feed.due(w.rec, t0 + std::chrono::milliseconds(ms)))) {
      if (f.header.sysid == 1) ++count[f.header.msgid];
    }
  }
  EXPECT_EQ(count[ml::Heartbeat::kId], 2);          // t = 0, 1 s
  EXPECT_EQ(count[ml::GlobalPositionInt::kId], 8);  // every 250 ms in 2 s
  EXPECT_EQ(count[ml::Attitude::kId], 8);
}

TEST(MavlinkFeed, PausedUavsAreStandbyLostOnesFallSilentFinishedOnesPowerOff) {
  Swarm w;
  w.state(0, 1, 1, 1);
  w.state(1, 1, 2, 1);
  core::UavStateMsg fin;
  fin.uav = 2;
  fin.tick = 1000;
  fin.x = 3;
  fin.y = 1;
  fin.finished = true;
  EXPECT_TRUE(w.rec.on_uav_state(fin));
  w.rec.on_uav_departed(core::UavDeparture(1));
  const auto t0 = Clock::now();
  MavlinkFeed feed(w.s, 4.0, t0);
  feed.set_paused(true);
  std::map<uint8_t, uint8_t> status;
  for (const auto& f : frames_of(feed.due(w.rec, t0))) {
    if (auto hb = ml::decode<ml::Heartbeat>(f)) status[f.header.sysid] = hb->system_status;
  }
  EXPECT_EQ(status.at(1), ml::kMavStateStandby);
  EXPECT_FALSE(status.contains(2));  // UAV 1 was lost
  EXPECT_EQ(status.at(3), ml::kMavStatePoweroff);
}

TEST(MavlinkFeed, LossesAndTargetsBecomeStatusTextsAndTheQueueIsBounded) {
  Swarm w;
  const auto t0 = Clock::now();
  MavlinkFeed feed(w.s, 4.0, t0);
  feed.note({IntakeNote::Kind::PlaceLost, IntakeNote::Level::Warn, "place agent 1 lost"});
  feed.note({IntakeNote::Kind::StateDropped, IntakeNote::Level::Warn, "not for the GCS"});
  feed.note({IntakeNote::Kind::TargetAcquired, IntakeNote::Level::Info, "target 0 found"});
  std::vector<std::string> texts;
  for (const auto& f : frames_of(feed.due(w.rec, t0))) {
    if (auto t = ml::decode<ml::StatusText>(f)) texts.push_back(t->text);
  }
  EXPECT_EQ(texts, (std::vector<std::string>{"place agent 1 lost", "target 0 found"}));
  // A long line goes in chunks of 50 bytes under one id, numbered from 0.
  const std::string long_line =
      "target 1 at (7,22) first acquired by uav 3 at tick 117 (0.2 s after it was first seen)";
  feed.note({IntakeNote::Kind::TargetAcquired, IntakeNote::Level::Info, long_line});
  std::vector<ml::StatusText> chunks;
  for (const auto& f : frames_of(feed.due(w.rec, t0 + 1ms))) {
    if (auto t = ml::decode<ml::StatusText>(f)) chunks.push_back(*t);
  }
  ASSERT_EQ(chunks.size(), 2U);
  EXPECT_EQ(chunks[0].text + chunks[1].text, long_line);
  EXPECT_NE(chunks[0].id, 0);
  EXPECT_EQ(chunks[1].id, chunks[0].id);
  EXPECT_EQ(chunks[0].chunk_seq, 0);
  EXPECT_EQ(chunks[1].chunk_seq, 1);
  for (std::size_t i = 0; i < kMavlinkTextQueue + 5; ++i) {
    feed.note({IntakeNote::Kind::UavLost, IntakeNote::Level::Warn, "uav lost"});
  }
  EXPECT_EQ(feed.stats().texts_dropped, 5U);
}

TEST(MavlinkFeed, SequenceNumbersCountPerSystem) {
  Swarm w;
  w.state(0, 1, 1, 1);
  const auto t0 = Clock::now();
  MavlinkFeed feed(w.s, 4.0, t0);
  std::vector<uint8_t> seqs;
  for (int ms = 0; ms < 600; ms += 250) {
    for (const auto& f : frames_of(feed.due(w.rec, t0 + std::chrono::milliseconds(ms)))) {
      if (f.header.sysid == 1) seqs.push_back(f.header.seq);
    }
  }
  ASSERT_GE(seqs.size(), 4U);
  for (std::size_t i = 0; i < seqs.size(); ++i) EXPECT_EQ(seqs[i], i);
}

}  // namespace
}  // namespace pheromesh::console
