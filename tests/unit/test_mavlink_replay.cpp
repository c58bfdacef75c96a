// `pheromesh replay --mavlink` (common/console/src/mavlink_replay.cpp): a
// recording played to a MAVLink station at its recorded pace, its pause and
// continue from the station, and what the frames show as the live stream
// would show it. The time is passed in.
#include "pheromesh/console/mavlink_replay.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "pheromesh/core/geodetic.hpp"
#include "pheromesh/mavlink/messages.hpp"

namespace pheromesh::console {
namespace mavlink_replay_test {

namespace ml = pheromesh::mavlink;
using Clock = MavlinkReplay::Clock;
using namespace std::chrono_literals;

// Two UAVs on a 40 x 30 map of 2 m cells at 45° N 7° E, 10 Hz, recorded from
// t = 100 s: one frame every 0.1 s (one tick), 50 frames. UAV 0 flies one cell
// east per tick from x = 1; UAV 1 stands at (5, 5). One target at (7, 8).
Recording recording(std::size_t frames = 50) {
  Recording r;
  r.info.width = 40;
  r.info.height = 30;
  r.info.tile_size = 10;
  r.info.regions = {{0, 0, 20, 30}, {20, 0, 20, 30}};
  r.info.tick_rate_hz = 10;
  r.info.geo = core::GeoFrame{45.0, 7.0, 250.0, 2.0, 40.0};
  for (uint32_t k = 0; k < frames; ++k) {
    Frame f;
    f.version = k + 1;
    f.t_s = 100.0 + k / 10.0;
    f.tick = k;
    UavView a;
    a.id = 0;
    a.x = 1.0 + k;
    a.y = 3.0;
    a.tick = k;
    UavView b;
    b.id = 1;
    b.x = 5;
    b.y = 5;
    b.tick = k;
    f.uavs = {a, b};
    for (uint32_t reg = 0; reg < 2; ++reg) {
      RegionView v;
      v.id = reg;
      v.liveness = Liveness::Alive;
      v.tick = k;
      f.regions.push_back(v);
    }
    TargetView t;
    t.cell = {7, 8};
    f.targets = {t};
    r.frames.push_back(f);
  }
  return r;
}

std::vector<ml::Frame> frames_of(const std::vector<std::vector<uint8_t>>& datagrams) {
  ml::Decoder d;
  std::vector<ml::Frame> all;
  for (const auto& g : datagrams) {
    for (auto& f : d.decode(g)) all.push_back(std::move(f));
  }
  EXPECT_EQ(d.stats().bad_crc + d.stats().truncated + d.stats().skipped_bytes, 0U);
  return all;
}

// The newest GLOBAL_POSITION_INT of `sysid` among `frames`.
std::optional<ml::GlobalPositionInt> position(const std::vector<ml::Frame>& frames, uint8_t sysid) {
  std::optional<ml::GlobalPositionInt> p;
  for (const auto& f : frames) {
    if (f.header.sysid != sysid) continue;
    if (auto m = ml::decode<ml::GlobalPositionInt>(f)) p = m;
  }
  return p;
}

// The longitude [degE7] the stream gives a UAV at column x, row 3.
int32_t lon_at(double x) {
  return static_cast<int32_t>(std::llround(core::map_to_geo({45.0, 7.0, 250.0, 2.0, 40.0}, {x, 3.0}).lon_deg * 1e7));
}

std::vector<uint8_t> heartbeat_statuses(const std::vector<ml::Frame>& frames) {
  std::vector<uint8_t> out;
  for (const auto& f : frames) {
    if (f.header.sysid == kMavlinkGroundSysid) continue;
    if (auto h = ml::decode<ml::Heartbeat>(f)) out.push_back(h->system_status);
  }
  return out;
}

std::vector<std::string> texts(const std::vector<ml::Frame>& frames) {
  std::vector<std::string> out;
  for (const auto& f : frames) {
    const auto t = ml::decode<ml::StatusText>(f);
    if (!t) continue;
    if (t->chunk_seq > 0 && !out.empty()) {
      out.back() += t->text;  // a long text comes in chunks of 50 bytes
    } else {
      out.push_back(t->text);
    }
  }
  return out;
}

// A station's COMMAND_LONG as the replay's gate takes it (unsigned).
mavlink::CommandGate::Command command(uint16_t cmd, float param1) {
  ml::CommandLong c;
  c.command = cmd;
  c.param[0] = param1;
  mavlink::CommandGate gate(std::nullopt, mavlink::CommandGate::Signatures::NotChecked);
  auto taken = gate.take(ml::encode(c, ml::Header{0, 255, 190, 0}), std::chrono::system_clock::now());
  EXPECT_EQ(taken.size(), 1U);
  return taken.empty() ? mavlink::CommandGate::Command{} : taken.front();
}

TEST(MavlinkReplay, ThePlaybackKeepsTheRecordedPaceFromTheFirstFrame) {
  const Recording rec = recording();
  const auto t0 = Clock::now();
  MavlinkReplay r(rec, 4.0, t0);
  auto p = position(frames_of(r.due(t0)), 1);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->lon, lon_at(1.0));  // the first frame at once
  // 1 s later the frame recorded 1 s after the first: tick 10, x = 11.
  p = position(frames_of(r.due(t0 + 1000ms)), 1);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->lon, lon_at(11.0));
  EXPECT_NEAR(r.played_s(), 1.0, 1e-9);
  EXPECT_FALSE(r.ended());
  p = position(frames_of(r.due(t0 + 2500ms)), 1);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->lon, lon_at(26.0));  // tick 25
}

// UAV 0 moves one cell east per tick: 2 m x 10 Hz = 20 m/s east, heading
// 90°, from the positions of successive ticks (a recording holds no velocity).
TEST(MavlinkReplay, SpeedAndHeadingComeFromTheRecordedPositions) {
  const Recording rec = recording();
  const auto t0 = Clock::now();
  MavlinkReplay r(rec, 4.0, t0);
  r.due(t0);
  const auto frames = frames_of(r.due(t0 + 500ms));
  const auto p = position(frames, 1);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->vy, 2000);  // east [cm/s]
  EXPECT_EQ(p->vx, 0);     // north
  EXPECT_EQ(p->hdg, 9000);
  const auto still = position(frames, 2);
  ASSERT_TRUE(still);
  EXPECT_EQ(still->vy, 0);
  EXPECT_EQ(still->alt, 290000);  // 250 m ground + 40 m flight height [mm]
}

TEST(MavlinkReplay, PauseHoldsThePlaybackAndItsUavsAreStandbyUntilContinue) {
  const Recording rec = recording();
  const auto t0 = Clock::now();
  MavlinkReplay r(rec, 4.0, t0);
  r.due(t0);
  EXPECT_EQ(r.command(command(ml::kCmdDoPauseContinue, 0), t0 + 1000ms), ml::kResultAccepted);
  EXPECT_TRUE(r.paused());
  // Two seconds paused: still the frame of 1 s, heartbeats STANDBY, speed 0.
  const auto paused = frames_of(r.due(t0 + 3000ms));
  auto p = position(paused, 1);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->lon, lon_at(11.0));
  EXPECT_EQ(p->vy, 0);
  EXPECT_EQ(heartbeat_statuses(paused), std::vector<uint8_t>({ml::kMavStateStandby, ml::kMavStateStandby}));
  EXPECT_EQ(r.command(command(ml::kCmdDoPauseContinue, 1), t0 + 3000ms), ml::kResultAccepted);
  EXPECT_FALSE(r.paused());
  // A second after continue: 2 s played, tick 20.
  const auto flying = frames_of(r.due(t0 + 4000ms));
  p = position(flying, 1);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->lon, lon_at(21.0));
  EXPECT_NEAR(r.played_s(), 2.0, 1e-9);
  EXPECT_EQ(heartbeat_statuses(flying), std::vector<uint8_t>({ml::kMavStateActive, ml::kMavStateActive}));
}

TEST(MavlinkReplay, DisarmAndEveryOtherCommandAreUnsupportedAndChangeNothing) {
  const Recording rec = recording();
  const auto t0 = Clock::now();
  MavlinkReplay r(rec, 4.0, t0);
  r.due(t0);
  for (const auto& c : {command(ml::kCmdComponentArmDisarm, 0), command(ml::kCmdComponentArmDisarm, 1),
                        command(ml::kCmdDoPauseContinue, 0.5F), command(21, 0)}) {
    EXPECT_EQ(r.command(c, t0 + 500ms), ml::kResultUnsupported) << c.message.command;
  }
  EXPECT_FALSE(r.paused());
  const auto p = position(frames_of(r.due(t0 + 1000ms)), 1);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->lon, lon_at(11.0));
  // The acknowledgement goes to the sender, unsigned.
  ml::Decoder decoder;
  const std::vector<uint8_t> bytes = r.ack(command(ml::kCmdComponentArmDisarm, 0), ml::kResultUnsupported);
  const auto ack = decoder.decode(bytes);
  ASSERT_EQ(ack.size(), 1U);
  EXPECT_FALSE(ack[0].is_signed);
  const auto a = ml::decode<ml::CommandAck>(ack[0]);
  ASSERT_TRUE(a);
  EXPECT_EQ(a->result, ml::kResultUnsupported);
  EXPECT_EQ(a->target_system, 255);
}

// UAV 1 is lost at 0.5 s and back at 1.0 s; region 1 lost at 0.5 s; the
// target found by UAV 0 at tick 7: each a STATUSTEXT when it is played, the
// lost UAV silent meanwhile and counted in SYS_STATUS.
TEST(MavlinkReplay, LossesReturnsAndFoundTargetsBecomeStatusTextsWhenPlayed) {
  Recording rec = recording();
  for (std::size_t k = 5; k < 10; ++k) rec.frames[k].uavs[1].liveness = Liveness::Dead;
  for (std::size_t k = 5; k < rec.frames.size(); ++k) rec.frames[k].regions[1].liveness = Liveness::Dead;
  for (std::size_t k = 7; k < rec.frames.size(); ++k) {
    rec.frames[k].targets[0].status = TargetStatus::Found;
    rec.frames[k].targets[0].found_by = 0;
    rec.frames[k].targets[0].found_tick = 7;
  }
  const auto t0 = Clock::now();
  MavlinkReplay r(rec, 4.0, t0);
  EXPECT_TRUE(texts(frames_of(r.due(t0))).empty());
  const auto lost = frames_of(r.due(t0 + 800ms));
  EXPECT_EQ(texts(lost),
            std::vector<std::string>({"uav 1 lost (liveliness) at tick 4", "place agent 1 lost (liveliness)",
                                      "target 0 at (7,8) first acquired by uav 0 at tick 7 (1/1)"}));
  EXPECT_FALSE(position(lost, 2).has_value());  // silent while lost
  std::optional<ml::SysStatus> status;
  for (const auto& f : frames_of(r.due(t0 + 1000ms))) {
    if (auto s = ml::decode<ml::SysStatus>(f)) status = s;
  }
  ASSERT_TRUE(status);
  EXPECT_EQ(status->errors_count[0], 1);  // place agents lost
  EXPECT_EQ(status->errors_count[1], 0);  // UAV 1 is back at 1.0 s
  EXPECT_EQ(status->errors_count[2], 1);  // targets found
  EXPECT_EQ(status->errors_count[3], 1);  // targets
  EXPECT_EQ(texts(frames_of(r.due(t0 + 1100ms))), std::vector<std::string>());
}

TEST(MavlinkReplay, AfterTheLastFrameTheLastStateIsHeldAndFinishedUavsPowerOff) {
  Recording rec = recording(20);
  rec.frames.back().uavs[0].liveness = Liveness::Finished;
  rec.frames.back().uavs[1].liveness = Liveness::Finished;
  const auto t0 = Clock::now();
  MavlinkReplay r(rec, 4.0, t0);
  r.due(t0);
  const auto end = frames_of(r.due(t0 + 10s));
  EXPECT_TRUE(r.ended());
  const auto p = position(end, 1);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->lon, lon_at(20.0));
  EXPECT_EQ(p->vy, 0);
  EXPECT_EQ(heartbeat_statuses(end), std::vector<uint8_t>({ml::kMavStatePoweroff, ml::kMavStatePoweroff}));
}

TEST(MavlinkReplay, ARecordingWithoutTheMapsPlaceIsStreamedAtTheDefaultFrame) {
  Recording rec = recording();
  rec.info.geo.reset();
  const MavlinkRun run = mavlink_run_of(rec);
  EXPECT_EQ(run.geo.origin_lat_deg, 0.0);
  EXPECT_EQ(run.geo.cell_size_m, 1.0);
  EXPECT_EQ(run.regions, 2U);
  EXPECT_EQ(run.targets, 1U);
  EXPECT_EQ(run.tick_rate_hz, 10.0);
}

}  // namespace mavlink_replay_test
}  // namespace pheromesh::console
