// Recording file of the web console: "PHMREC01", then protobuf records
// (tag, varint length, message): the Header as field 1, each Frame as field 2
// of pheromesh.recording.RecordingFile. Layout and rules: docs/recording.md.
#include "pheromesh/console/recording.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <string_view>
#include <system_error>

#include "recording.pb.h"

#ifndef PHEROMESH_VERSION
#define PHEROMESH_VERSION "0.1.0"  // keep in step with project() in CMakeLists.txt
#endif

namespace pheromesh::console {
namespace {

namespace pb = pheromesh::recording;
using core::Error;

constexpr std::string_view kFileMagic = "PHMREC01";          // first 8 bytes of the file
constexpr std::string_view kHeaderMagic = "pheromesh-recording";  // Header.magic
constexpr uint32_t kFormatVersion = 1;
constexpr uint64_t kMaxRecordBytes = uint64_t{64} << 20;  // a longer record is corruption
// Record tags: (field number << 3) | wire type 2 (length-delimited) of RecordingFile.
constexpr uint64_t kWireLengthDelimited = 2;
constexpr uint64_t kHeaderField = 1;
constexpr uint64_t kFrameField = 2;
constexpr uint64_t kHeaderTag = (kHeaderField << 3) | kWireLengthDelimited;  // 0x0A
constexpr uint64_t kFrameTag = (kFrameField << 3) | kWireLengthDelimited;    // 0x12

// ---------------------------------------------------------------- encoding --

void append_varint(std::string& out, uint64_t v) {
  while (v >= 0x80) {
    out.push_back(static_cast<char>((v & 0x7F) | 0x80));
    v >>= 7;
  }
  out.push_back(static_cast<char>(v));
}

std::string record(uint64_t tag, const std::string& body) {
  std::string out;
  out.reserve(body.size() + 12);
  append_varint(out, tag);
  append_varint(out, body.size());
  out += body;
  return out;
}

// proto3 strings must be UTF-8 (the parser refuses anything else), but what a
// console shows can come from a command line or an HTTP client: every byte
// that does not start a well-formed UTF-8 sequence becomes U+FFFD.
std::string utf8(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  const auto* p = reinterpret_cast<const unsigned char*>(s.data());
  const std::size_t n = s.size();
  std::size_t i = 0;
  while (i < n) {
    const unsigned char c = p[i];
    std::size_t len = 0;
    unsigned char lo = 0x80, hi = 0xBF;  // allowed range of the second byte
    if (c < 0x80) len = 1;
    else if (c >= 0xC2 && c <= 0xDF) len = 2;
    else if (c == 0xE0) { len = 3; lo = 0xA0; }            // no overlong forms
    else if (c >= 0xE1 && c <= 0xEC) len = 3;
    else if (c == 0xED) { len = 3; hi = 0x9F; }            // no surrogates
    else if (c >= 0xEE && c <= 0xEF) len = 3;
    else if (c == 0xF0) { len = 4; lo = 0x90; }            // no overlong forms
    else if (c >= 0xF1 && c <= 0xF3) len = 4;
    else if (c == 0xF4) { len = 4; hi = 0x8F; }            // <= U+10FFFF
    bool ok = len > 0 && i + len <= n;
    for (std::size_t k = 1; ok && k < len; ++k) {
      const unsigned char b = p[i + k];
      ok = k == 1 ? (b >= lo && b <= hi) : (b >= 0x80 && b <= 0xBF);
    }
    if (ok) {
      out.append(s, i, len);
      i += len;
    } else {
      out += "\xEF\xBF\xBD";
      ++i;
    }
  }
  return out;
}

void to_pb(const core::Rect& r, pb::Rect* out) {
  out->set_x0(r.x0);
  out->set_y0(r.y0);
  out->set_w(r.w);
  out->set_h(r.h);
}

pb::Liveness to_pb(Liveness l) {
  switch (l) {
    case Liveness::Alive: return pb::LIVENESS_ALIVE;
    case Liveness::Stale: return pb::LIVENESS_STALE;
    case Liveness::Dead: return pb::LIVENESS_DEAD;
    case Liveness::Finished: return pb::LIVENESS_FINISHED;
  }
  return pb::LIVENESS_DEAD;
}

pb::TargetStatus to_pb(TargetStatus s) {
  switch (s) {
    case TargetStatus::NotFound: return pb::TARGET_STATUS_NOT_FOUND;
    case TargetStatus::Found: return pb::TARGET_STATUS_FOUND;
    case TargetStatus::RevisitDue: return pb::TARGET_STATUS_REVISIT_DUE;
  }
  return pb::TARGET_STATUS_NOT_FOUND;
}

void to_pb(const ConsoleInfo& i, pb::ConsoleInfo* out) {
  out->set_scenario_name(utf8(i.scenario_name));
  out->set_scenario_path(utf8(i.scenario_path));
  out->set_policy(utf8(i.policy));
  out->set_width(i.width);
  out->set_height(i.height);
  out->set_tile_size(i.tile_size);
  for (const auto& r : i.regions) to_pb(r, out->add_regions());
  for (const auto& l : i.layers) out->add_layers(utf8(l));
  out->set_tick_rate_hz(i.tick_rate_hz);
  out->set_ticks(i.ticks);
  out->set_uavs_expected(i.uavs_expected);
  out->set_lease_ms(i.lease_ms);
  out->set_sensor_radius(i.sensor_radius);
  out->set_clock(utf8(i.clock));
  out->set_dds(utf8(i.dds));
  if (i.geo) {
    pb::Geo* g = out->mutable_geo();
    g->set_origin_lat_deg(i.geo->origin_lat_deg);
    g->set_origin_lon_deg(i.geo->origin_lon_deg);
    g->set_origin_alt_m(i.geo->origin_alt_m);
    g->set_cell_size_m(i.geo->cell_size_m);
    g->set_flight_height_m(i.geo->flight_height_m);
  }
}

void to_pb(const Frame& f, pb::Frame* out) {
  out->set_version(f.version);
  out->set_t_s(f.t_s);
  out->set_tick(f.tick);
  out->set_paused(f.paused);
  for (const auto& [layer, scale] : f.scales) {
    auto* s = out->add_scales();
    s->set_layer(layer);
    s->set_scale(scale);
  }
  for (const auto& d : f.tiles) {
    auto* t = out->add_tiles();
    t->set_layer(d.layer);
    t->set_tx(d.tx);
    t->set_ty(d.ty);
    to_pb(d.rect, t->mutable_rect());
    t->set_tick(d.tick);
    t->set_q(d.q.data(), d.q.size());
  }
  for (const auto& u : f.uavs) {
    auto* v = out->add_uavs();
    v->set_id(u.id);
    v->set_x(u.x);
    v->set_y(u.y);
    v->set_heading(u.heading);
    v->set_role(static_cast<pb::Role>(uint32_t{u.role} + 1));  // open enum: roles past FOLLOWER kept as numbers
    v->set_tick(u.tick);
    v->set_liveness(to_pb(u.liveness));
  }
  for (const auto& r : f.regions) {
    auto* v = out->add_regions();
    v->set_id(r.id);
    v->set_liveness(to_pb(r.liveness));
    v->set_tick(r.tick);
    v->set_tick_rate_hz(r.tick_rate_hz);
    v->set_deposits_per_s(r.deposits_per_s);
    v->set_deposits_received(r.deposits_received);
    v->set_deposits_applied(r.deposits_applied);
    v->set_deposits_rejected(r.deposits_rejected);
    v->set_samples_refused(r.samples_refused);
    v->set_replica(r.replica);
    v->set_replicas_alive(r.replicas_alive);
  }
  for (const auto& t : f.targets) {
    auto* v = out->add_targets();
    v->mutable_cell()->set_x(t.cell.x);
    v->mutable_cell()->set_y(t.cell.y);
    v->set_status(to_pb(t.status));
    v->set_found_by(t.found_by);
    v->set_found_tick(t.found_tick);
    v->set_popup(t.popup);
  }
  for (const auto& o : f.obstacles) {
    auto* v = out->add_obstacles();
    to_pb(o.rect, v->mutable_rect());
    v->set_popup(o.popup);
  }
  if (f.series) {
    auto* p = out->mutable_series();
    p->set_version(f.series->version);
    p->set_t_s(f.series->t_s);
    p->set_tick(f.series->tick);
    p->set_coverage(f.series->coverage);
    p->set_targets_found(f.series->targets_found);
    p->set_uncertainty(f.series->uncertainty);
  }
  for (const auto& c : f.commands) {
    auto* v = out->add_commands();
    v->set_version(c.version);
    v->set_t_s(c.t_s);
    v->set_who(utf8(c.who));
    v->set_what(utf8(c.what));
    v->set_ok(c.ok);
    v->set_result(utf8(c.result));
  }
}

// recording.proto and everything it imports, dependencies first (the order
// DescriptorPool::BuildFile needs), as compiled into this program.
void add_file(const google::protobuf::FileDescriptor* f, google::protobuf::FileDescriptorSet& set,
              std::set<std::string>& seen) {
  if (!seen.insert(f->name()).second) return;
  for (int i = 0; i < f->dependency_count(); ++i) add_file(f->dependency(i), set, seen);
  f->CopyTo(set.add_file());
}

const google::protobuf::FileDescriptorSet& schema() {
  static const google::protobuf::FileDescriptorSet set = [] {
    google::protobuf::FileDescriptorSet s;
    std::set<std::string> seen;
    add_file(pb::Header::descriptor()->file(), s, seen);
    return s;
  }();
  return set;
}

std::string now_utc() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

// ---------------------------------------------------------------- decoding --

core::Rect from_pb(const pb::Rect& r) { return {r.x0(), r.y0(), r.w(), r.h()}; }

// Each returns an empty string or what is wrong.
std::string from_pb(int v, Liveness& out) {
  switch (v) {
    case pb::LIVENESS_ALIVE: out = Liveness::Alive; return {};
    case pb::LIVENESS_STALE: out = Liveness::Stale; return {};
    case pb::LIVENESS_DEAD: out = Liveness::Dead; return {};
    case pb::LIVENESS_FINISHED: out = Liveness::Finished; return {};
    default: return "liveness " + std::to_string(v) + " is not a known Liveness";
  }
}

std::string from_pb(int v, TargetStatus& out) {
  switch (v) {
    case pb::TARGET_STATUS_NOT_FOUND: out = TargetStatus::NotFound; return {};
    case pb::TARGET_STATUS_FOUND: out = TargetStatus::Found; return {};
    case pb::TARGET_STATUS_REVISIT_DUE: out = TargetStatus::RevisitDue; return {};
    default: return "status " + std::to_string(v) + " is not a known TargetStatus";
  }
}

ConsoleInfo from_pb(const pb::ConsoleInfo& i) {
  ConsoleInfo out;
  out.scenario_name = i.scenario_name();
  out.scenario_path = i.scenario_path();
  out.policy = i.policy();
  out.width = i.width();
  out.height = i.height();
  out.tile_size = i.tile_size();
  for (const auto& r : i.regions()) out.regions.push_back(from_pb(r));
  out.layers.assign(i.layers().begin(), i.layers().end());
  out.tick_rate_hz = i.tick_rate_hz();
  out.ticks = i.ticks();
  out.uavs_expected = i.uavs_expected();
  out.lease_ms = i.lease_ms();
  out.sensor_radius = i.sensor_radius();
  out.clock = i.clock();
  out.dds = i.dds();
  if (i.has_geo()) {
    const pb::Geo& g = i.geo();
    out.geo =
        core::GeoFrame{g.origin_lat_deg(), g.origin_lon_deg(), g.origin_alt_m(), g.cell_size_m(), g.flight_height_m()};
  }
  return out;
}

std::string from_pb(const pb::Frame& in, Frame& f) {
  constexpr uint32_t kMaxLayer = std::numeric_limits<uint16_t>::max();
  f.version = in.version();
  f.t_s = in.t_s();
  f.tick = in.tick();
  f.paused = in.paused();
  for (const auto& s : in.scales()) {
    if (s.layer() > kMaxLayer) return "scale of layer " + std::to_string(s.layer()) + ": layer past 65535";
    f.scales.emplace_back(static_cast<uint16_t>(s.layer()), s.scale());
  }
  for (const auto& t : in.tiles()) {
    if (t.layer() > kMaxLayer) return "tile of layer " + std::to_string(t.layer()) + ": layer past 65535";
    TileDelta d;
    d.layer = static_cast<uint16_t>(t.layer());
    d.tx = t.tx();
    d.ty = t.ty();
    d.rect = from_pb(t.rect());
    d.tick = t.tick();
    d.q.assign(t.q().begin(), t.q().end());
    f.tiles.push_back(std::move(d));
  }
  for (const auto& u : in.uavs()) {
    const std::string who = "uav " + std::to_string(u.id()) + ": ";
    UavView v;
    v.id = u.id();
    v.x = u.x();
    v.y = u.y();
    if (u.heading() > 0xFF) return who + "heading " + std::to_string(u.heading()) + " past 255";
    v.heading = static_cast<uint8_t>(u.heading());
    if (u.role() < 1 || u.role() > 0x100) return who + "role " + std::to_string(u.role()) + " is not a Role";
    v.role = static_cast<uint8_t>(u.role() - 1);
    v.tick = u.tick();
    if (auto e = from_pb(u.liveness(), v.liveness); !e.empty()) return who + e;
    f.uavs.push_back(v);
  }
  for (const auto& r : in.regions()) {
    RegionView v;
    v.id = r.id();
    if (auto e = from_pb(r.liveness(), v.liveness); !e.empty()) return "region " + std::to_string(r.id()) + ": " + e;
    v.tick = r.tick();
    v.tick_rate_hz = r.tick_rate_hz();
    v.deposits_per_s = r.deposits_per_s();
    v.deposits_received = r.deposits_received();
    v.deposits_applied = r.deposits_applied();
    v.deposits_rejected = r.deposits_rejected();
    v.samples_refused = r.samples_refused();
    if (r.replica() > 0xFFFFU) return "region " + std::to_string(r.id()) + ": replica " + std::to_string(r.replica()) + " out of range";
    v.replica = static_cast<uint16_t>(r.replica());
    v.replicas_alive = r.replicas_alive();
    f.regions.push_back(v);
  }
  for (int k = 0; k < in.targets_size(); ++k) {
    const auto& t = in.targets(k);
    TargetView v;
    v.cell = {t.cell().x(), t.cell().y()};
    if (auto e = from_pb(t.status(), v.status); !e.empty()) return "target " + std::to_string(k) + ": " + e;
    v.found_by = t.found_by();
    v.found_tick = t.found_tick();
    v.popup = t.popup();
    f.targets.push_back(v);
  }
  for (const auto& o : in.obstacles()) f.obstacles.push_back({from_pb(o.rect()), o.popup()});
  if (in.has_series()) {
    const auto& p = in.series();
    f.series = SeriesPoint{p.version(), p.t_s(), p.tick(), p.coverage(), p.targets_found(), p.uncertainty()};
  }
  for (const auto& c : in.commands()) f.commands.push_back({c.version(), c.t_s(), c.who(), c.what(), c.ok(), c.result()});
  return {};
}

// Reads the records of a file one at a time.
class RecordReader {
 public:
  enum class Status { Record, End, Truncated, Error };

  RecordReader(std::ifstream& in, uint64_t file_size, uint64_t offset) : in_(in), size_(file_size), offset_(offset) {}

  // Next record into tag/body; `start` = its byte offset. On Truncated or
  // Error, `what` says why (without file name and offset).
  Status next(uint64_t& start, uint64_t& tag, std::string& body, std::string& what) {
    start = offset_;
    int c = in_.peek();
    if (c == std::char_traits<char>::eof()) return Status::End;
    if (auto s = varint(tag, "tag", what); s != Status::Record) return s;
    uint64_t len = 0;
    if (auto s = varint(len, "length", what); s != Status::Record) return s;
    if (len > kMaxRecordBytes) {
      what = "record length " + std::to_string(len) + " bytes is past the limit of " +
             std::to_string(kMaxRecordBytes) + " (corrupt file)";
      return Status::Error;
    }
    const uint64_t remaining = size_ > offset_ ? size_ - offset_ : 0;
    if (len > remaining) {
      what = "the record declares " + std::to_string(len) + " bytes but the file ends after " +
             std::to_string(remaining);
      return Status::Truncated;
    }
    body.resize(static_cast<std::size_t>(len));
    in_.read(body.data(), static_cast<std::streamsize>(len));
    const auto got = static_cast<uint64_t>(in_.gcount());
    offset_ += got;
    if (got < len) {  // the file shrank while we read it
      what = "the record declares " + std::to_string(len) + " bytes but the file ends after " + std::to_string(got);
      return Status::Truncated;
    }
    return Status::Record;
  }

 private:
  Status varint(uint64_t& v, const char* name, std::string& what) {
    v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      const int c = in_.get();
      if (c == std::char_traits<char>::eof()) {
        what = std::string("the file ends inside the record's ") + name;
        return Status::Truncated;
      }
      ++offset_;
      v |= static_cast<uint64_t>(c & 0x7F) << shift;
      if ((c & 0x80) == 0) return Status::Record;
    }
    what = std::string("the record's ") + name + " is not a valid varint (more than 10 bytes)";
    return Status::Error;
  }

  std::ifstream& in_;
  uint64_t size_;
  uint64_t offset_;
};

std::string at(const std::string& path, uint64_t offset) {
  return path + ": byte " + std::to_string(offset) + ": ";
}

}  // namespace

// ------------------------------------------------------------------ writer --

core::Result<std::unique_ptr<RecordingWriter>> RecordingWriter::open(const std::string& path,
                                                                      const ConsoleInfo& info) {
  if (const auto dir = std::filesystem::path(path).parent_path(); !dir.empty() && !std::filesystem::is_directory(dir)) {
    return Error{path + ": cannot create the recording: no such directory " + dir.string()};
  }
  auto file = core::AtomicFile::create(path);
  if (!file) return Error{path + ": cannot create the recording: " + file.error().message};
  std::unique_ptr<RecordingWriter> w(new RecordingWriter());
  w->path_ = path;
  w->file_.emplace(std::move(file).value());
  pb::Header h;
  h.set_magic(std::string(kHeaderMagic));
  h.set_format_version(kFormatVersion);
  h.set_created_utc(now_utc());
  h.set_writer("pheromesh " PHEROMESH_VERSION);
  to_pb(info, h.mutable_info());
  *h.mutable_schema() = schema();
  std::string bytes(kFileMagic);
  bytes += record(kHeaderTag, h.SerializeAsString());
  if (!w->file_->write(bytes) || !w->file_->flush()) {
    return Error{path + ": cannot write the recording's header: " + std::strerror(errno)};
  }
  w->bytes_ = bytes.size();
  return w;
}

RecordingWriter::~RecordingWriter() { (void)close(); }

core::Result<uint64_t> RecordingWriter::close() {
  if (!file_) return bytes_;
  auto done = file_->commit();
  file_.reset();
  if (!done) return Error{done.error().message};
  return bytes_;
}

const std::string& RecordingWriter::temp_path() const {
  static const std::string none;
  return file_ ? file_->temp_path() : none;
}

bool RecordingWriter::write(const Frame& f) {
  if (!file_) return false;
  // A frame the reader would refuse is not written: versions must increase
  // and a record must stay within the reader's limit.
  if (f.version <= last_version_) return false;
  pb::Frame m;
  to_pb(f, &m);
  if (m.ByteSizeLong() > kMaxRecordBytes) return false;
  const std::string bytes = record(kFrameTag, m.SerializeAsString());
  // Flushed to the OS, so a killed ground station leaves every complete
  // frame in the temporary file.
  if (!file_->write(bytes) || !file_->flush()) return false;
  bytes_ += bytes.size();
  last_version_ = f.version;
  return true;
}

// ------------------------------------------------------------------ reader --

core::Result<Recording> read_recording(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in.is_open()) return Error{path + ": cannot open: " + std::strerror(errno)};
  std::error_code ec;
  const uint64_t size = std::filesystem::file_size(path, ec);
  if (ec) return Error{path + ": cannot get its size: " + ec.message()};

  std::string magic(kFileMagic.size(), '\0');
  in.read(magic.data(), static_cast<std::streamsize>(magic.size()));
  if (static_cast<std::size_t>(in.gcount()) != magic.size() || magic != kFileMagic) {
    return Error{path + ": not a pheromesh recording (it does not start with \"" + std::string(kFileMagic) + "\")"};
  }

  RecordReader reader(in, size, kFileMagic.size());
  uint64_t start = 0, tag = 0;
  std::string body, what;

  // Record 0: the header.
  switch (reader.next(start, tag, body, what)) {
    case RecordReader::Status::Record: break;
    case RecordReader::Status::End: return Error{at(path, start) + "the file ends before the header"};
    case RecordReader::Status::Truncated: return Error{at(path, start) + "the file ends inside the header: " + what};
    case RecordReader::Status::Error: return Error{at(path, start) + "header: " + what};
  }
  if (tag != kHeaderTag) {
    return Error{at(path, start) + "the first record has tag " + std::to_string(tag) + ", expected " +
                 std::to_string(kHeaderTag) + " (the header)"};
  }
  pb::Header h;
  if (!h.ParseFromString(body)) {
    return Error{at(path, start) + "the header (record 0) cannot be parsed as pheromesh.recording.Header"};
  }
  if (h.magic() != kHeaderMagic) {
    return Error{at(path, start) + "header magic is \"" + h.magic() + "\", expected \"" + std::string(kHeaderMagic) +
                 "\": not a pheromesh recording"};
  }
  if (h.format_version() == 0) return Error{at(path, start) + "the header has no format_version"};
  if (h.format_version() > kFormatVersion) {
    return Error{at(path, start) + "recording format version " + std::to_string(h.format_version()) +
                 " is newer than this pheromesh reads (" + std::to_string(kFormatVersion) +
                 "); read it with a newer pheromesh"};
  }

  Recording rec;
  rec.info = from_pb(h.info());
  rec.created_utc = h.created_utc();
  rec.writer = h.writer();

  // Records 1, 2, ...: the frames.
  for (uint64_t n = 1;; ++n) {
    const auto status = reader.next(start, tag, body, what);
    if (status == RecordReader::Status::End) break;
    const std::string where = at(path, start) + "record " + std::to_string(n) + ": ";
    if (status == RecordReader::Status::Truncated) {
      rec.truncated = true;
      rec.warning = where + what + "; the file was cut inside this record (writer killed?), " +
                    std::to_string(rec.frames.size()) + " complete frames read";
      break;
    }
    if (status == RecordReader::Status::Error) return Error{where + what};
    if (tag == kHeaderTag) return Error{where + "a second header"};
    if ((tag & 7) != kWireLengthDelimited) {
      return Error{where + "tag " + std::to_string(tag) + " is not a length-delimited record"};
    }
    if (tag != kFrameTag) continue;  // a record kind added later: skipped, as protobuf skips unknown fields
    pb::Frame m;
    if (!m.ParseFromString(body)) return Error{where + "cannot be parsed as pheromesh.recording.Frame (corrupt)"};
    Frame f;
    if (auto e = from_pb(m, f); !e.empty()) return Error{where + "frame " + std::to_string(m.version()) + ": " + e};
    const uint64_t prev = rec.frames.empty() ? 0 : rec.frames.back().version;
    if (f.version <= prev) {
      return Error{where + "frame version " + std::to_string(f.version) + " does not follow " + std::to_string(prev) +
                   " (versions must increase strictly, from 1)"};
    }
    rec.frames.push_back(std::move(f));
  }
  return rec;
}

// ------------------------------------------------------------------ replay --

namespace {
constexpr std::size_t kCheckpointEvery = 64;  // [frames]
}

ReplayIndex::ReplayIndex(Recording rec) : rec_(std::move(rec)) {
  ConsoleState s = initial_state(rec_.info);
  checkpoints_.emplace_back(0, s);
  for (std::size_t i = 0; i < rec_.frames.size(); ++i) {
    apply(s, rec_.frames[i]);
    if ((i + 1) % kCheckpointEvery == 0) checkpoints_.emplace_back(i + 1, s);
  }
}

double ReplayIndex::t0() const { return rec_.frames.empty() ? 0.0 : rec_.frames.front().t_s; }
double ReplayIndex::t1() const { return rec_.frames.empty() ? 0.0 : rec_.frames.back().t_s; }

ConsoleState ReplayIndex::at(double t_s) const {
  const auto& frames = rec_.frames;
  // Frames to apply: all before the first frame later than t (for times that
  // never go back, the last frame with t_s <= t), at least one.
  const auto later = std::find_if(frames.begin(), frames.end(), [&](const Frame& f) { return f.t_s > t_s; });
  std::size_t n = static_cast<std::size_t>(later - frames.begin());
  if (n == 0 && !frames.empty()) n = 1;
  // The checkpoint with the most frames applied, at most n.
  const auto cp = std::prev(std::upper_bound(checkpoints_.begin(), checkpoints_.end(), n,
                                             [](std::size_t v, const auto& c) { return v < c.first; }));
  ConsoleState s = cp->second;
  for (std::size_t i = cp->first; i < n; ++i) apply(s, frames[i]);
  return s;
}

}  // namespace pheromesh::console
