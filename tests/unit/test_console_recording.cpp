// Recording file of the web console (docs/recording.md) and ReplayIndex.
#include <gtest/gtest.h>

#include <google/protobuf/descriptor.h>
#include <google/protobuf/descriptor.pb.h>
#include <google/protobuf/dynamic_message.h>
#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/unknown_field_set.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include <unistd.h>

#include "pheromesh/console/recording.hpp"
#include "pheromesh/console/state.hpp"

namespace pheromesh::console {
namespace {

namespace fs = std::filesystem;
namespace gpb = google::protobuf;

// ------------------------------------------------------------------ helpers --

class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    std::random_device rd;
    dir_ = fs::temp_directory_path() / ("pheromesh-recording-test-" + std::to_string(::getpid()) + "-" +
                                        std::to_string(counter++) + "-" + std::to_string(rd()));
    fs::create_directories(dir_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] std::string file(const std::string& name) const { return (dir_ / name).string(); }

 private:
  fs::path dir_;
};

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

void append_varint(std::string& out, uint64_t v) {
  while (v >= 0x80) {
    out.push_back(static_cast<char>((v & 0x7F) | 0x80));
    v >>= 7;
  }
  out.push_back(static_cast<char>(v));
}

// One record of a file, found independently of the reader under test.
struct RawRecord {
  std::size_t start = 0;  // byte offset of its tag
  uint64_t tag = 0;
  std::size_t body = 0;   // byte offset of its message
  std::size_t size = 0;   // bytes of its message
  [[nodiscard]] std::size_t end() const { return body + size; }
};

std::vector<RawRecord> split_records(const std::string& bytes) {
  std::vector<RawRecord> out;
  gpb::io::CodedInputStream in(reinterpret_cast<const uint8_t*>(bytes.data()), static_cast<int>(bytes.size()));
  if (!in.Skip(8)) return out;
  while (in.BytesUntilLimit() != 0 && in.CurrentPosition() < static_cast<int>(bytes.size())) {
    RawRecord r;
    r.start = static_cast<std::size_t>(in.CurrentPosition());
    uint64_t len = 0;
    if (!in.ReadVarint64(&r.tag) || !in.ReadVarint64(&len)) break;
    r.body = static_cast<std::size_t>(in.CurrentPosition());
    r.size = static_cast<std::size_t>(len);
    if (!in.Skip(static_cast<int>(len))) break;
    out.push_back(r);
  }
  return out;
}

std::string body_of(const std::string& bytes, const RawRecord& r) { return bytes.substr(r.body, r.size); }

// A hand-made header record (tag 0x0A): magic (field 1), format_version (field 2).
std::string header_record(const std::string& magic, uint32_t format_version) {
  std::string h;
  h.push_back('\x0A');
  append_varint(h, magic.size());
  h += magic;
  h.push_back('\x10');
  append_varint(h, format_version);
  std::string rec = "\x0A";
  append_varint(rec, h.size());
  return rec + h;
}

// "2024-05-01T12:00:00Z" (no std::regex: GCC 12 warns inside it under sanitizers)
bool looks_like_utc(const std::string& s) {
  const std::string pattern = "dddd-dd-ddTdd:dd:ddZ";
  if (s.size() != pattern.size()) return false;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const bool ok = pattern[k] == 'd' ? (s[k] >= '0' && s[k] <= '9') : s[k] == pattern[k];
    if (!ok) return false;
  }
  return true;
}

// ---------------------------------------------------------------- test data --

ConsoleInfo make_info() {
  ConsoleInfo i;
  i.scenario_name = "small-test";
  i.scenario_path = "scenarios/small-test.textproto";
  i.policy = "shao-search";
  i.width = 40;
  i.height = 30;
  i.tile_size = 10;
  i.regions = {{0, 0, 20, 30}, {20, 0, 20, 30}};
  i.layers = {"target", "obstacle", "path", "target_state"};
  i.tick_rate_hz = 12.5;
  i.ticks = 300;
  i.uavs_expected = 4;
  i.lease_ms = 1000;
  i.sensor_radius = 2.5;
  i.clock = "lockstep";
  i.dds = "cyclone";
  i.geo = core::GeoFrame{47.397, 8.545, 488.0, 2.5, 40.0};
  return i;
}

// A few frames that use every field and every enum value.
std::vector<Frame> make_frames() {
  std::vector<Frame> out;
  {
    Frame f;
    f.version = 1;
    f.t_s = 0.25;
    f.tick = 3;
    f.paused = false;
    f.scales = {{0, 4.0F}, {2, 0.5F}};
    TileDelta a;
    a.layer = 0;
    a.tx = 0;
    a.ty = 0;
    a.rect = {0, 0, 16, 16};
    a.tick = 2;
    for (int v = 0; v < 256; ++v) a.q.push_back(static_cast<uint8_t>(255 - v));  // every byte value, 255 first
    TileDelta b;
    b.layer = 2;
    b.tx = 3;
    b.ty = -1;
    b.rect = {30, 20, 2, 3};
    b.tick = 1;
    b.q = {0, 255, 0, 128, 255, 0};
    f.tiles = {a, b};
    f.uavs = {{0, 1.5, 2.25, 0, 0, 3, Liveness::Alive, {}},
              {1, 10.0, 0.0, 7, 1, 2, Liveness::Stale, {}},
              {7, 39.0, 29.0, 4, 2, 1, Liveness::Dead, {}},
              {9, 20.0, 5.0, 2, 0, 3, Liveness::Finished, {}}};
    f.regions = {{0, Liveness::Alive, 3, 12.5F, 31.5, 100, 98, 2},
                 {1, Liveness::Dead, 0, 0.0F, 0.0, 0, 0, 0}};
    f.regions[0].samples_refused = 5;  // refused as implausible (core/plausibility.hpp)
    f.targets = {{{5, 6}, TargetStatus::NotFound, -1, 0, false},
                 {{30, 7}, TargetStatus::Found, 0, 3, false},
                 {{12, 20}, TargetStatus::RevisitDue, 7, 2, true}};
    f.obstacles = {{{5, 5, 3, 2}, false}, {{25, 10, 1, 1}, true}};
    f.series = SeriesPoint{1, 0.25, 3, 0.125, 1, 0.875};
    f.commands = {{1, 0.2, "http 127.0.0.1:53122 (token ok)", "kill uav 3", true, "SIGKILL sent to uav-3 (pid 4242)"},
                  {1, 0.21, "http [::1]:8080 — Jürgen", "obstacle 5 5 3 3 ✓ 🚁 障害物", false, "refusé: déjà là"}};
    out.push_back(f);
  }
  {
    Frame f;  // paused, nothing but the lists, no series
    f.version = 2;
    f.t_s = 0.5;
    f.tick = 3;
    f.paused = true;
    f.uavs = {{0, 1.5, 2.25, 0, 0, 3, Liveness::Alive, {}}};
    f.regions = {{0, Liveness::Stale, 3, 0.0F, 0.0, 100, 98, 2},
                 {1, Liveness::Finished, 7, 9.5F, 1.0, 5, 4, 1}};
    out.push_back(f);
  }
  {
    Frame f;  // versions may skip; t_s may repeat
    f.version = 5;
    f.t_s = 0.5;
    f.tick = 4;
    f.scales = {{1, 1024.0F}};
    TileDelta t;
    t.layer = 1;
    t.tx = 1;
    t.ty = 2;
    t.rect = {10, 20, 1, 1};
    t.tick = 4;
    t.q = {0};
    f.tiles = {t};
    f.uavs = {{0, 3.0, 2.25, 6, 2, 4, Liveness::Alive, {}},
              {3, -0.5, 1e9, 1, 1, 4, Liveness::Stale, {}},
              {4, 0.0, 0.0, 0, 9, 4, Liveness::Alive, {}}};  // role 9: a role added later, kept as a number
    f.targets = {{{0, 0}, TargetStatus::Found, 3, 4, true}};
    f.series = SeriesPoint{0, 0.5, 4, 1.0, 2, 0.0};
    f.commands = {{0, 0.49, "", "", false, ""}};
    out.push_back(f);
  }
  return out;
}

// ------------------------------------------------------------- comparisons --

void expect_info_eq(const ConsoleInfo& a, const ConsoleInfo& b) {
  EXPECT_EQ(a.scenario_name, b.scenario_name);
  EXPECT_EQ(a.scenario_path, b.scenario_path);
  EXPECT_EQ(a.policy, b.policy);
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_EQ(a.tile_size, b.tile_size);
  EXPECT_EQ(a.regions, b.regions);
  EXPECT_EQ(a.layers, b.layers);
  EXPECT_EQ(a.tick_rate_hz, b.tick_rate_hz);
  EXPECT_EQ(a.ticks, b.ticks);
  EXPECT_EQ(a.uavs_expected, b.uavs_expected);
  EXPECT_EQ(a.lease_ms, b.lease_ms);
  EXPECT_EQ(a.sensor_radius, b.sensor_radius);
  EXPECT_EQ(a.clock, b.clock);
  EXPECT_EQ(a.dds, b.dds);
  ASSERT_EQ(a.geo.has_value(), b.geo.has_value());
  if (a.geo) {
    EXPECT_EQ(a.geo->origin_lat_deg, b.geo->origin_lat_deg);
    EXPECT_EQ(a.geo->origin_lon_deg, b.geo->origin_lon_deg);
    EXPECT_EQ(a.geo->origin_alt_m, b.geo->origin_alt_m);
    EXPECT_EQ(a.geo->cell_size_m, b.geo->cell_size_m);
    EXPECT_EQ(a.geo->flight_height_m, b.geo->flight_height_m);
  }
}

void expect_uav_eq(const UavView& a, const UavView& b, bool with_track) {
  SCOPED_TRACE("uav " + std::to_string(a.id));
  EXPECT_EQ(a.id, b.id);
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.y, b.y);
  EXPECT_EQ(a.heading, b.heading);
  EXPECT_EQ(a.role, b.role);
  EXPECT_EQ(a.tick, b.tick);
  EXPECT_EQ(a.liveness, b.liveness);
  if (!with_track) return;
  ASSERT_EQ(a.track.size(), b.track.size());
  for (std::size_t k = 0; k < a.track.size(); ++k) {
    EXPECT_EQ(a.track[k].x, b.track[k].x) << "track point " << k;
    EXPECT_EQ(a.track[k].y, b.track[k].y) << "track point " << k;
    EXPECT_EQ(a.track[k].version, b.track[k].version) << "track point " << k;
  }
}

void expect_region_eq(const RegionView& a, const RegionView& b) {
  SCOPED_TRACE("region " + std::to_string(a.id));
  EXPECT_EQ(a.id, b.id);
  EXPECT_EQ(a.liveness, b.liveness);
  EXPECT_EQ(a.tick, b.tick);
  EXPECT_EQ(a.tick_rate_hz, b.tick_rate_hz);
  EXPECT_EQ(a.deposits_per_s, b.deposits_per_s);
  EXPECT_EQ(a.deposits_received, b.deposits_received);
  EXPECT_EQ(a.deposits_applied, b.deposits_applied);
  EXPECT_EQ(a.deposits_rejected, b.deposits_rejected);
  EXPECT_EQ(a.samples_refused, b.samples_refused);
}

void expect_target_eq(const TargetView& a, const TargetView& b) {
  EXPECT_EQ(a.cell, b.cell);
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.found_by, b.found_by);
  EXPECT_EQ(a.found_tick, b.found_tick);
  EXPECT_EQ(a.popup, b.popup);
}

void expect_series_eq(const SeriesPoint& a, const SeriesPoint& b) {
  EXPECT_EQ(a.version, b.version);
  EXPECT_EQ(a.t_s, b.t_s);
  EXPECT_EQ(a.tick, b.tick);
  EXPECT_EQ(a.coverage, b.coverage);
  EXPECT_EQ(a.targets_found, b.targets_found);
  EXPECT_EQ(a.uncertainty, b.uncertainty);
}

void expect_command_eq(const CommandLogEntry& a, const CommandLogEntry& b) {
  EXPECT_EQ(a.version, b.version);
  EXPECT_EQ(a.t_s, b.t_s);
  EXPECT_EQ(a.who, b.who);
  EXPECT_EQ(a.what, b.what);
  EXPECT_EQ(a.ok, b.ok);
  EXPECT_EQ(a.result, b.result);
}

void expect_frame_eq(const Frame& a, const Frame& b) {
  SCOPED_TRACE("frame " + std::to_string(a.version));
  EXPECT_EQ(a.version, b.version);
  EXPECT_EQ(a.t_s, b.t_s);
  EXPECT_EQ(a.tick, b.tick);
  EXPECT_EQ(a.paused, b.paused);
  EXPECT_EQ(a.scales, b.scales);
  ASSERT_EQ(a.tiles.size(), b.tiles.size());
  for (std::size_t k = 0; k < a.tiles.size(); ++k) {
    SCOPED_TRACE("tile " + std::to_string(k));
    EXPECT_EQ(a.tiles[k].layer, b.tiles[k].layer);
    EXPECT_EQ(a.tiles[k].tx, b.tiles[k].tx);
    EXPECT_EQ(a.tiles[k].ty, b.tiles[k].ty);
    EXPECT_EQ(a.tiles[k].rect, b.tiles[k].rect);
    EXPECT_EQ(a.tiles[k].tick, b.tiles[k].tick);
    EXPECT_EQ(a.tiles[k].q, b.tiles[k].q);
  }
  ASSERT_EQ(a.uavs.size(), b.uavs.size());
  for (std::size_t k = 0; k < a.uavs.size(); ++k) expect_uav_eq(a.uavs[k], b.uavs[k], true);
  ASSERT_EQ(a.regions.size(), b.regions.size());
  for (std::size_t k = 0; k < a.regions.size(); ++k) expect_region_eq(a.regions[k], b.regions[k]);
  ASSERT_EQ(a.targets.size(), b.targets.size());
  for (std::size_t k = 0; k < a.targets.size(); ++k) expect_target_eq(a.targets[k], b.targets[k]);
  ASSERT_EQ(a.obstacles.size(), b.obstacles.size());
  for (std::size_t k = 0; k < a.obstacles.size(); ++k) {
    EXPECT_EQ(a.obstacles[k].rect, b.obstacles[k].rect);
    EXPECT_EQ(a.obstacles[k].popup, b.obstacles[k].popup);
  }
  ASSERT_EQ(a.series.has_value(), b.series.has_value());
  if (a.series) expect_series_eq(*a.series, *b.series);
  ASSERT_EQ(a.commands.size(), b.commands.size());
  for (std::size_t k = 0; k < a.commands.size(); ++k) expect_command_eq(a.commands[k], b.commands[k]);
}

void expect_state_eq(const ConsoleState& a, const ConsoleState& b) {
  EXPECT_EQ(a.version, b.version);
  EXPECT_EQ(a.t_s, b.t_s);
  EXPECT_EQ(a.tick, b.tick);
  EXPECT_EQ(a.paused, b.paused);
  ASSERT_EQ(a.layers.size(), b.layers.size());
  for (std::size_t l = 0; l < a.layers.size(); ++l) {
    SCOPED_TRACE("layer " + std::to_string(l));
    EXPECT_EQ(a.layers[l].scale, b.layers[l].scale);
    ASSERT_EQ(a.layers[l].tiles.size(), b.layers[l].tiles.size());
    for (auto ia = a.layers[l].tiles.begin(), ib = b.layers[l].tiles.begin(); ia != a.layers[l].tiles.end(); ++ia, ++ib) {
      EXPECT_EQ(ia->first, ib->first);
      EXPECT_EQ(ia->second.rect, ib->second.rect);
      EXPECT_EQ(ia->second.tick, ib->second.tick);
      EXPECT_EQ(ia->second.q, ib->second.q);
      EXPECT_EQ(ia->second.version, ib->second.version);
    }
  }
  ASSERT_EQ(a.uavs.size(), b.uavs.size());
  for (auto ia = a.uavs.begin(), ib = b.uavs.begin(); ia != a.uavs.end(); ++ia, ++ib) {
    EXPECT_EQ(ia->first, ib->first);
    expect_uav_eq(ia->second, ib->second, true);
  }
  ASSERT_EQ(a.regions.size(), b.regions.size());
  for (std::size_t k = 0; k < a.regions.size(); ++k) expect_region_eq(a.regions[k], b.regions[k]);
  ASSERT_EQ(a.targets.size(), b.targets.size());
  for (std::size_t k = 0; k < a.targets.size(); ++k) expect_target_eq(a.targets[k], b.targets[k]);
  ASSERT_EQ(a.obstacles.size(), b.obstacles.size());
  for (std::size_t k = 0; k < a.obstacles.size(); ++k) {
    EXPECT_EQ(a.obstacles[k].rect, b.obstacles[k].rect);
    EXPECT_EQ(a.obstacles[k].popup, b.obstacles[k].popup);
  }
  ASSERT_EQ(a.series.size(), b.series.size());
  for (std::size_t k = 0; k < a.series.size(); ++k) expect_series_eq(a.series[k], b.series[k]);
  ASSERT_EQ(a.commands.size(), b.commands.size());
  for (std::size_t k = 0; k < a.commands.size(); ++k) expect_command_eq(a.commands[k], b.commands[k]);
}

// Writes info + frames to path; every write must succeed.
void write_recording(const std::string& path, const ConsoleInfo& info, const std::vector<Frame>& frames) {
  auto w = RecordingWriter::open(path, info);
  ASSERT_TRUE(w.ok()) << w.error().message;
  for (const auto& f : frames) ASSERT_TRUE(w.value()->write(f)) << "frame " << f.version;
  const auto closed = w.value()->close();
  ASSERT_TRUE(closed.ok()) << closed.error().message;
  EXPECT_EQ(closed.value(), fs::file_size(path));
}

// ------------------------------------------------------------- recordings --

TEST(ConsoleRecording, RoundTripKeepsEveryField) {
  TempDir dir;
  const std::string path = dir.file("run.phmrec");
  const ConsoleInfo info = make_info();
  const std::vector<Frame> frames = make_frames();
  write_recording(path, info, frames);

  const auto rec = read_recording(path);
  ASSERT_TRUE(rec.ok()) << rec.error().message;
  EXPECT_FALSE(rec->truncated);
  EXPECT_EQ(rec->warning, "");
  expect_info_eq(rec->info, info);
  EXPECT_TRUE(looks_like_utc(rec->created_utc)) << rec->created_utc;
  EXPECT_EQ(rec->writer.rfind("pheromesh ", 0), 0U) << rec->writer;
  ASSERT_EQ(rec->frames.size(), frames.size());
  for (std::size_t k = 0; k < frames.size(); ++k) expect_frame_eq(rec->frames[k], frames[k]);
}

// A recording written before ConsoleInfo carried the map's place reads
// with no geo frame (a replay's MAVLink stream then says so), not a made-up one.
TEST(ConsoleRecording, ARecordingWithoutTheMapsPlaceReadsWithNoGeoFrame) {
  TempDir dir;
  const std::string path = dir.file("old.phmrec");
  ConsoleInfo info = make_info();
  info.geo.reset();
  write_recording(path, info, make_frames());
  const auto rec = read_recording(path);
  ASSERT_TRUE(rec.ok()) << rec.error().message;
  EXPECT_FALSE(rec->info.geo.has_value());
}

TEST(ConsoleRecording, FileStartsWithMagicThenHeaderThenOneRecordPerFrame) {
  TempDir dir;
  const std::string path = dir.file("layout.phmrec");
  write_recording(path, make_info(), make_frames());
  const std::string bytes = read_bytes(path);
  ASSERT_GE(bytes.size(), 8U);
  EXPECT_EQ(bytes.substr(0, 8), "PHMREC01");
  const auto records = split_records(bytes);
  ASSERT_EQ(records.size(), 1 + make_frames().size());
  EXPECT_EQ(records.front().tag, 0x0AU);  // RecordingFile.header
  for (std::size_t k = 1; k < records.size(); ++k) EXPECT_EQ(records[k].tag, 0x12U) << k;  // RecordingFile.frames
  EXPECT_EQ(records.back().end(), bytes.size());
}

TEST(ConsoleRecording, WriterFlushesEveryFrameToItsTemporaryFileWhileStillOpen) {
  TempDir dir;
  const std::string path = dir.file("live.phmrec");
  const auto frames = make_frames();
  auto w = RecordingWriter::open(path, make_info());
  ASSERT_TRUE(w.ok()) << w.error().message;
  EXPECT_EQ(w.value()->path(), path);
  const std::string temp = w.value()->temp_path();
  ASSERT_NE(temp, path);
  EXPECT_EQ(fs::path(temp).parent_path(), fs::path(path).parent_path());
  for (std::size_t n = 1; n <= frames.size(); ++n) {
    ASSERT_TRUE(w.value()->write(frames[n - 1]));
    // Read while the writer is open, as after a SIGKILL: nothing may sit in a
    // buffer, and the final name must not exist yet.
    EXPECT_FALSE(fs::exists(path));
    const auto rec = read_recording(temp);
    ASSERT_TRUE(rec.ok()) << rec.error().message;
    EXPECT_FALSE(rec->truncated) << rec->warning;
    ASSERT_EQ(rec->frames.size(), n);
    expect_frame_eq(rec->frames.back(), frames[n - 1]);
    EXPECT_EQ(w.value()->bytes_written(), fs::file_size(temp));
  }
  ASSERT_TRUE(w.value()->close().ok());
  EXPECT_FALSE(fs::exists(temp));
  const auto rec = read_recording(path);
  ASSERT_TRUE(rec.ok()) << rec.error().message;
  EXPECT_EQ(rec->frames.size(), frames.size());
  EXPECT_FALSE(w.value()->write(frames.back()));
}

TEST(ConsoleRecording, WriterRefusesFramesWhoseVersionDoesNotIncrease) {
  TempDir dir;
  const std::string path = dir.file("versions.phmrec");
  auto w = RecordingWriter::open(path, make_info());
  ASSERT_TRUE(w.ok()) << w.error().message;
  Frame f;
  f.version = 0;
  EXPECT_FALSE(w.value()->write(f));
  f.version = 3;
  EXPECT_TRUE(w.value()->write(f));
  const uint64_t size = w.value()->bytes_written();
  EXPECT_FALSE(w.value()->write(f));
  f.version = 2;
  EXPECT_FALSE(w.value()->write(f));
  EXPECT_EQ(w.value()->bytes_written(), size);
  f.version = 4;
  EXPECT_TRUE(w.value()->write(f));
  ASSERT_TRUE(w.value()->close().ok());
  const auto rec = read_recording(path);
  ASSERT_TRUE(rec.ok()) << rec.error().message;
  ASSERT_EQ(rec->frames.size(), 2U);
  EXPECT_EQ(rec->frames[0].version, 3U);
  EXPECT_EQ(rec->frames[1].version, 4U);
}

TEST(ConsoleRecording, WriterReportsAFileItCannotCreate) {
  TempDir dir;
  const std::string path = dir.file("no-such-dir/run.phmrec");
  const auto w = RecordingWriter::open(path, make_info());
  ASSERT_FALSE(w.ok());
  EXPECT_NE(w.error().message.find(path), std::string::npos) << w.error().message;
}

TEST(ConsoleRecording, InvalidUtf8IsReplacedSoTheFileStaysReadable) {
  TempDir dir;
  const std::string path = dir.file("utf8.phmrec");
  ConsoleInfo info = make_info();
  info.scenario_path = "scen\xFFrios/a.textproto";
  Frame f;
  f.version = 1;
  f.commands = {{0, 0, "bad \xFF\xFE byte", "overlong \xC0\xAF, surrogate \xED\xA0\x80, cut \xE2\x82", true,
                 "fine: \xC3\xBC \xE2\x9C\x93 \xF0\x9F\x9A\x81"}};
  write_recording(path, info, {f});
  const auto rec = read_recording(path);
  ASSERT_TRUE(rec.ok()) << rec.error().message;
  const std::string r = "\xEF\xBF\xBD";  // U+FFFD
  EXPECT_EQ(rec->info.scenario_path, "scen" + r + "rios/a.textproto");
  ASSERT_EQ(rec->frames.size(), 1U);
  ASSERT_EQ(rec->frames[0].commands.size(), 1U);
  EXPECT_EQ(rec->frames[0].commands[0].who, "bad " + r + r + " byte");
  EXPECT_EQ(rec->frames[0].commands[0].what,
            "overlong " + r + r + ", surrogate " + r + r + r + ", cut " + r + r);
  EXPECT_EQ(rec->frames[0].commands[0].result, "fine: \xC3\xBC \xE2\x9C\x93 \xF0\x9F\x9A\x81");
}

TEST(ConsoleRecording, HeaderOnlyFileHasNoFrames) {
  TempDir dir;
  const std::string path = dir.file("empty.phmrec");
  {
    auto w = RecordingWriter::open(path, make_info());
    ASSERT_TRUE(w.ok()) << w.error().message;
  }
  const auto rec = read_recording(path);
  ASSERT_TRUE(rec.ok()) << rec.error().message;
  EXPECT_TRUE(rec->frames.empty());
  EXPECT_FALSE(rec->truncated);
  EXPECT_EQ(rec->warning, "");
  expect_info_eq(rec->info, make_info());
}

TEST(ConsoleRecording, FileCutInsideTheLastFrameReadsAsThePreviousFrames) {
  TempDir dir;
  const std::string full = dir.file("full.phmrec");
  const std::string cut = dir.file("cut.phmrec");
  const auto frames = make_frames();
  write_recording(full, make_info(), frames);
  const std::string bytes = read_bytes(full);
  const auto records = split_records(bytes);
  ASSERT_EQ(records.size(), 1 + frames.size());
  const RawRecord last = records.back();
  ASSERT_EQ(last.end(), bytes.size());

  // At the record boundary: a complete file of one frame less.
  write_bytes(cut, bytes.substr(0, last.start));
  {
    const auto rec = read_recording(cut);
    ASSERT_TRUE(rec.ok()) << rec.error().message;
    EXPECT_FALSE(rec->truncated);
    EXPECT_EQ(rec->warning, "");
    EXPECT_EQ(rec->frames.size(), frames.size() - 1);
  }
  // Inside the record (tag, length or message): the same frames, truncated.
  for (std::size_t size = last.start + 1; size < last.end(); ++size) {
    SCOPED_TRACE("file cut to " + std::to_string(size) + " bytes");
    write_bytes(cut, bytes.substr(0, size));
    const auto rec = read_recording(cut);
    ASSERT_TRUE(rec.ok()) << rec.error().message;
    EXPECT_TRUE(rec->truncated);
    EXPECT_NE(rec->warning.find(cut), std::string::npos) << rec->warning;
    EXPECT_NE(rec->warning.find("byte " + std::to_string(last.start)), std::string::npos) << rec->warning;
    ASSERT_EQ(rec->frames.size(), frames.size() - 1);
    for (std::size_t k = 0; k + 1 < frames.size(); ++k) expect_frame_eq(rec->frames[k], frames[k]);
  }
}

TEST(ConsoleRecording, FileCutBeforeItsFirstFrameIsAnError) {
  TempDir dir;
  const std::string full = dir.file("full.phmrec");
  const std::string cut = dir.file("cut.phmrec");
  write_recording(full, make_info(), {});
  const std::string bytes = read_bytes(full);
  // Every cut in the magic and the header's tag and length, then a sample of the header.
  for (std::size_t size = 0; size < bytes.size(); size += size < 16 ? 1 : 97) {
    SCOPED_TRACE("file cut to " + std::to_string(size) + " bytes");
    write_bytes(cut, bytes.substr(0, size));
    const auto rec = read_recording(cut);
    ASSERT_FALSE(rec.ok());
    EXPECT_NE(rec.error().message.find(cut), std::string::npos) << rec.error().message;
  }
}

TEST(ConsoleRecording, WrongMagicIsNotARecording) {
  TempDir dir;
  const std::string path = dir.file("not-a-recording.bin");
  write_recording(path, make_info(), make_frames());
  std::string bytes = read_bytes(path);
  bytes[3] = 'X';
  write_bytes(path, bytes);
  const auto rec = read_recording(path);
  ASSERT_FALSE(rec.ok());
  EXPECT_NE(rec.error().message.find(path), std::string::npos) << rec.error().message;
  EXPECT_NE(rec.error().message.find("not a pheromesh recording"), std::string::npos) << rec.error().message;

  write_bytes(path, "{\"json\": true}\n");
  const auto json = read_recording(path);
  ASSERT_FALSE(json.ok());
  EXPECT_NE(json.error().message.find("not a pheromesh recording"), std::string::npos) << json.error().message;
}

TEST(ConsoleRecording, MissingFileIsAnErrorNamingIt) {
  TempDir dir;
  const std::string path = dir.file("missing.phmrec");
  const auto rec = read_recording(path);
  ASSERT_FALSE(rec.ok());
  EXPECT_NE(rec.error().message.find(path), std::string::npos) << rec.error().message;
}

TEST(ConsoleRecording, NewerFormatVersionAndWrongHeaderMagicAreRefused) {
  TempDir dir;
  const std::string path = dir.file("future.phmrec");
  write_bytes(path, "PHMREC01" + header_record("pheromesh-recording", 2));
  const auto future = read_recording(path);
  ASSERT_FALSE(future.ok());
  EXPECT_NE(future.error().message.find(path), std::string::npos) << future.error().message;
  EXPECT_NE(future.error().message.find("format version 2"), std::string::npos) << future.error().message;

  write_bytes(path, "PHMREC01" + header_record("pheromesh-recording", 1));
  const auto v1 = read_recording(path);  // the hand-made header itself is fine
  ASSERT_TRUE(v1.ok()) << v1.error().message;
  EXPECT_TRUE(v1->frames.empty());

  write_bytes(path, "PHMREC01" + header_record("something-else", 1));
  const auto other = read_recording(path);
  ASSERT_FALSE(other.ok());
  EXPECT_NE(other.error().message.find("something-else"), std::string::npos) << other.error().message;

  write_bytes(path, "PHMREC01" + header_record("pheromesh-recording", 0));
  const auto none = read_recording(path);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().message.find("format_version"), std::string::npos) << none.error().message;
}

TEST(ConsoleRecording, CorruptFrameInTheMiddleNamesFileOffsetAndRecord) {
  TempDir dir;
  const std::string path = dir.file("corrupt.phmrec");
  write_recording(path, make_info(), make_frames());
  std::string bytes = read_bytes(path);
  const auto records = split_records(bytes);
  ASSERT_EQ(records.size(), 4U);
  // Frame record 2: its first field's tag gets wire type 7, which does not exist.
  ASSERT_EQ(bytes[records[2].body], '\x08');  // version, varint
  bytes[records[2].body] = '\x0F';
  write_bytes(path, bytes);
  const auto rec = read_recording(path);
  ASSERT_FALSE(rec.ok());
  const std::string& m = rec.error().message;
  EXPECT_NE(m.find(path), std::string::npos) << m;
  EXPECT_NE(m.find("byte " + std::to_string(records[2].start)), std::string::npos) << m;
  EXPECT_NE(m.find("record 2"), std::string::npos) << m;
}

TEST(ConsoleRecording, AbsurdRecordLengthIsAnErrorNotATruncation) {
  TempDir dir;
  const std::string path = dir.file("absurd.phmrec");
  write_recording(path, make_info(), make_frames());
  std::string bytes = read_bytes(path);
  const std::size_t start = bytes.size();
  bytes.push_back('\x12');
  append_varint(bytes, uint64_t{100} << 20);
  bytes += "only a few bytes";
  write_bytes(path, bytes);
  const auto rec = read_recording(path);
  ASSERT_FALSE(rec.ok());
  const std::string& m = rec.error().message;
  EXPECT_NE(m.find(path), std::string::npos) << m;
  EXPECT_NE(m.find("byte " + std::to_string(start)), std::string::npos) << m;
  EXPECT_NE(m.find("limit"), std::string::npos) << m;
}

TEST(ConsoleRecording, FrameVersionsMustIncreaseStrictly) {
  TempDir dir;
  const std::string a = dir.file("a.phmrec");
  const std::string b = dir.file("b.phmrec");
  auto frames = make_frames();
  write_recording(a, make_info(), {frames[0], frames[1]});  // versions 1, 2
  write_recording(b, make_info(), {frames[1]});             // version 2
  const std::string bytes_b = read_bytes(b);
  const auto records_b = split_records(bytes_b);
  ASSERT_EQ(records_b.size(), 2U);
  std::string spliced = read_bytes(a);
  const std::size_t start = spliced.size();
  spliced += bytes_b.substr(records_b[1].start);  // 1, 2, 2
  write_bytes(a, spliced);
  const auto rec = read_recording(a);
  ASSERT_FALSE(rec.ok());
  const std::string& m = rec.error().message;
  EXPECT_NE(m.find(a), std::string::npos) << m;
  EXPECT_NE(m.find("byte " + std::to_string(start)), std::string::npos) << m;
  EXPECT_NE(m.find("record 3"), std::string::npos) << m;
  EXPECT_NE(m.find("version 2"), std::string::npos) << m;
}

TEST(ConsoleRecording, UnknownEnumValueIsRefused) {
  TempDir dir;
  const std::string path = dir.file("enum.phmrec");
  write_recording(path, make_info(), {});
  // Frame { version: 1, uavs { id: 3, role: ROLE_SEARCHER } }: liveness absent = LIVENESS_UNSPECIFIED.
  const std::string frame = std::string("\x08\x01\x3A\x04\x08\x03\x28\x01", 8);
  std::string rec_bytes = "\x12";
  append_varint(rec_bytes, frame.size());
  write_bytes(path, read_bytes(path) + rec_bytes + frame);
  const auto rec = read_recording(path);
  ASSERT_FALSE(rec.ok());
  const std::string& m = rec.error().message;
  EXPECT_NE(m.find("record 1"), std::string::npos) << m;
  EXPECT_NE(m.find("uav 3"), std::string::npos) << m;
  EXPECT_NE(m.find("liveness 0"), std::string::npos) << m;
}

TEST(ConsoleRecording, UnknownRecordKindsAreSkipped) {
  TempDir dir;
  const std::string path = dir.file("future-records.phmrec");
  const auto frames = make_frames();
  write_recording(path, make_info(), {frames[0]});
  std::string bytes = read_bytes(path);
  bytes += "\x1A\x03" "abc";  // field 3, length-delimited: a record kind added later
  write_bytes(path, bytes);
  {
    auto w = RecordingWriter::open(dir.file("second.phmrec"), make_info());
    ASSERT_TRUE(w.ok());
    ASSERT_TRUE(w.value()->write(frames[1]));
  }
  const std::string second = read_bytes(dir.file("second.phmrec"));
  write_bytes(path, bytes + second.substr(split_records(second)[1].start));
  const auto rec = read_recording(path);
  ASSERT_TRUE(rec.ok()) << rec.error().message;
  ASSERT_EQ(rec->frames.size(), 2U);
  expect_frame_eq(rec->frames[0], frames[0]);
  expect_frame_eq(rec->frames[1], frames[1]);
}

// The file carries its own schema: a program without recording.proto or its
// generated code decodes a frame with the descriptors from the header alone.
TEST(ConsoleRecording, EmbeddedSchemaDecodesFramesWithoutGeneratedCode) {
  TempDir dir;
  const std::string path = dir.file("self-describing.phmrec");
  const auto frames = make_frames();
  write_recording(path, make_info(), frames);
  const std::string bytes = read_bytes(path);
  const auto records = split_records(bytes);
  ASSERT_EQ(records.size(), 1 + frames.size());

  // Header field 6 (docs/recording.md) is a google.protobuf.FileDescriptorSet.
  gpb::UnknownFieldSet header;
  ASSERT_TRUE(header.ParseFromString(body_of(bytes, records[0])));
  gpb::FileDescriptorSet schema;
  bool found = false;
  for (int k = 0; k < header.field_count(); ++k) {
    const auto& field = header.field(k);
    if (field.number() == 6 && field.type() == gpb::UnknownField::TYPE_LENGTH_DELIMITED) {
      ASSERT_TRUE(schema.ParseFromString(field.length_delimited()));
      found = true;
    }
  }
  ASSERT_TRUE(found) << "no schema in the header";
  ASSERT_EQ(schema.file_size(), 2);
  EXPECT_EQ(schema.file(0).name(), "google/protobuf/descriptor.proto");  // dependencies first
  const std::string& name = schema.file(1).name();  // as the build passed it to protoc
  EXPECT_EQ(name.substr(name.size() - std::min<std::size_t>(name.size(), 15)), "recording.proto") << name;
  EXPECT_EQ(schema.file(1).package(), "pheromesh.recording");
  ASSERT_EQ(schema.file(1).dependency_size(), 1);
  EXPECT_EQ(schema.file(1).dependency(0), "google/protobuf/descriptor.proto");

  gpb::DescriptorPool pool;  // fresh: knows nothing compiled into this program
  for (const auto& file : schema.file()) ASSERT_NE(pool.BuildFile(file), nullptr) << file.name();
  const gpb::Descriptor* frame_type = pool.FindMessageTypeByName("pheromesh.recording.Frame");
  ASSERT_NE(frame_type, nullptr);
  EXPECT_NE(frame_type, gpb::DescriptorPool::generated_pool()->FindMessageTypeByName("pheromesh.recording.Frame"));

  gpb::DynamicMessageFactory factory(&pool);
  std::unique_ptr<gpb::Message> frame(factory.GetPrototype(frame_type)->New());
  ASSERT_TRUE(frame->ParseFromString(body_of(bytes, records[1])));
  const gpb::Reflection* r = frame->GetReflection();
  EXPECT_EQ(r->GetUInt64(*frame, frame_type->FindFieldByName("version")), frames[0].version);
  EXPECT_EQ(r->GetDouble(*frame, frame_type->FindFieldByName("t_s")), frames[0].t_s);

  const gpb::FieldDescriptor* tiles = frame_type->FindFieldByName("tiles");
  ASSERT_EQ(r->FieldSize(*frame, tiles), 2);
  const gpb::Message& tile = r->GetRepeatedMessage(*frame, tiles, 1);
  const std::string q = tile.GetReflection()->GetString(tile, tile.GetDescriptor()->FindFieldByName("q"));
  EXPECT_EQ(std::vector<uint8_t>(q.begin(), q.end()), frames[0].tiles[1].q);

  const gpb::FieldDescriptor* uavs = frame_type->FindFieldByName("uavs");
  ASSERT_EQ(r->FieldSize(*frame, uavs), 4);
  const gpb::Message& uav = r->GetRepeatedMessage(*frame, uavs, 3);
  const gpb::EnumValueDescriptor* liveness =
      uav.GetReflection()->GetEnum(uav, uav.GetDescriptor()->FindFieldByName("liveness"));
  EXPECT_EQ(liveness->name(), "LIVENESS_FINISHED");

  const gpb::FieldDescriptor* commands = frame_type->FindFieldByName("commands");
  ASSERT_EQ(r->FieldSize(*frame, commands), 2);
  const gpb::Message& cmd = r->GetRepeatedMessage(*frame, commands, 1);
  EXPECT_EQ(cmd.GetReflection()->GetString(cmd, cmd.GetDescriptor()->FindFieldByName("what")),
            frames[0].commands[1].what);
}

// ------------------------------------------------------------------ replay --

// A long run: tiles, scales, moving UAVs (some steps shorter than the track
// decimation), a series point every third frame, a command every other frame
// (more than kCommandLog in all), repeated times.
Recording make_long_recording(std::size_t n) {
  Recording rec;
  rec.info = make_info();
  std::mt19937 rng(7);
  for (std::size_t i = 0; i < n; ++i) {
    Frame f;
    f.version = 10 + 2 * i;
    f.t_s = 0.1 * static_cast<double>(i % 5 == 2 ? i - 1 : i);  // frames 5k+2 repeat the time before
    f.tick = static_cast<uint32_t>(i);
    f.paused = i % 17 == 3;
    if (i % 40 == 0) f.scales.emplace_back(static_cast<uint16_t>(i / 40 % 4), std::ldexp(1.0F, static_cast<int>(i / 40)));
    for (int k = 0; k < 2; ++k) {
      TileDelta d;
      d.layer = static_cast<uint16_t>(rng() % 5);  // 4: no such layer, ignored by apply()
      d.tx = static_cast<int32_t>(rng() % 4);
      d.ty = static_cast<int32_t>(rng() % 3);
      d.rect = {d.tx * 10, d.ty * 10, 10, 10};
      d.tick = f.tick;
      d.q.resize(100);
      for (auto& v : d.q) v = static_cast<uint8_t>(rng());
      f.tiles.push_back(std::move(d));
    }
    for (uint32_t u = 0; u < 3; ++u) {
      const double step = u == 0 ? 0.3 : 1.2;  // UAV 0 moves less than kTrackStep per frame
      const Liveness l = (u == 2 && i % 50 > 40) ? Liveness::Dead : Liveness::Alive;
      f.uavs.push_back({u, step * static_cast<double>(i % 90), 5.0 + u, static_cast<uint8_t>(i % 8),
                        static_cast<uint8_t>(u), f.tick, l, {}});
    }
    f.regions = {{0, Liveness::Alive, f.tick, 10.0F, 1.0 * static_cast<double>(i), i, i, 0},
                 {1, i % 30 < 5 ? Liveness::Stale : Liveness::Alive, f.tick, 9.0F, 2.0, i, i, i / 10}};
    f.targets = {{{5, 6}, i > 100 ? TargetStatus::Found : TargetStatus::NotFound, i > 100 ? 1 : -1,
                  i > 100 ? 100U : 0U, false}};
    if (i > 150) f.obstacles = {{{20, 20, 2, 2}, true}};
    if (i % 3 == 0) f.series = SeriesPoint{0, f.t_s, f.tick, static_cast<double>(i) / static_cast<double>(n), 0, 0.5};
    if (i % 2 == 0) f.commands = {{0, f.t_s, "http", "pause " + std::to_string(i), true, "ok"}};
    rec.frames.push_back(std::move(f));
  }
  return rec;
}

TEST(ConsoleReplay, StateAtEveryFrameTimeEqualsApplyingTheFramesInOrder) {
  const Recording rec = make_long_recording(200);
  const ReplayIndex index(rec);
  ConsoleState expected = initial_state(rec.info);
  for (std::size_t i = 0; i < rec.frames.size(); ++i) {
    apply(expected, rec.frames[i]);
    // The state after the last frame with this time.
    if (i + 1 < rec.frames.size() && rec.frames[i + 1].t_s <= rec.frames[i].t_s) continue;
    SCOPED_TRACE("t = " + std::to_string(rec.frames[i].t_s) + ", frame " + std::to_string(i));
    expect_state_eq(index.at(rec.frames[i].t_s), expected);
    if (HasFatalFailure()) return;
  }
  EXPECT_EQ(expected.commands.size(), kCommandLog);  // the log did overflow
  expect_state_eq(index.at(index.t1()), expected);
}

TEST(ConsoleReplay, RecordingReadBackReplaysLikeTheLiveConsole) {
  TempDir dir;
  const std::string path = dir.file("long.phmrec");
  const Recording live = make_long_recording(150);
  write_recording(path, live.info, live.frames);
  auto rec = read_recording(path);
  ASSERT_TRUE(rec.ok()) << rec.error().message;
  const ReplayIndex index(std::move(rec.value()));
  ConsoleState expected = initial_state(live.info);
  for (const auto& f : live.frames) apply(expected, f);
  expect_state_eq(index.at(live.frames.back().t_s), expected);
  EXPECT_EQ(index.recording().frames.size(), live.frames.size());
}

TEST(ConsoleReplay, TimesBetweenBeforeAndAfterTheFrames) {
  const Recording rec = make_long_recording(130);
  const ReplayIndex index(rec);
  EXPECT_EQ(index.t0(), rec.frames.front().t_s);
  EXPECT_EQ(index.t1(), rec.frames.back().t_s);

  std::vector<ConsoleState> after;  // after[i]: state after frames 0..i
  ConsoleState s = initial_state(rec.info);
  for (const auto& f : rec.frames) {
    apply(s, f);
    after.push_back(s);
  }
  // Between frames 69 and 70 (past the second checkpoint): the state after 69.
  ASSERT_LT(rec.frames[69].t_s, rec.frames[70].t_s);
  {
    SCOPED_TRACE("between frames 69 and 70");
    expect_state_eq(index.at((rec.frames[69].t_s + rec.frames[70].t_s) / 2), after[69]);
  }
  // Just before a checkpoint's frame: one frame less.
  ASSERT_LT(rec.frames[63].t_s, rec.frames[64].t_s);
  {
    SCOPED_TRACE("just before frame 64");
    expect_state_eq(index.at(std::nextafter(rec.frames[64].t_s, -1.0)), after[63]);
  }
  {
    SCOPED_TRACE("before the first frame");
    expect_state_eq(index.at(rec.frames.front().t_s - 100.0), after.front());
  }
  {
    SCOPED_TRACE("after the last frame");
    expect_state_eq(index.at(rec.frames.back().t_s + 100.0), after.back());
  }
}

TEST(ConsoleReplay, EmptyRecordingIsTheInitialState) {
  Recording rec;
  rec.info = make_info();
  const ReplayIndex index(rec);
  EXPECT_EQ(index.t0(), 0.0);
  EXPECT_EQ(index.t1(), 0.0);
  const ConsoleState s = index.at(5.0);
  expect_state_eq(s, initial_state(rec.info));
  EXPECT_EQ(s.layers.size(), rec.info.layers.size());
  EXPECT_EQ(s.regions.size(), rec.info.regions.size());
}

}  // namespace
}  // namespace pheromesh::console
