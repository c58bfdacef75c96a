#include "replay_command.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <mutex>
#include <thread>

#include "groundstation/mavlink_link.hpp"
#include "pheromesh/console/mavlink_replay.hpp"
#include "pheromesh/console/prometheus.hpp"
#include "pheromesh/console/recording.hpp"
#include "pheromesh/console/server.hpp"
#include "pheromesh/console/view.hpp"
#include "pheromesh/runtime/process.hpp"

namespace pheromesh::cli {

namespace {

class ReplaySource final : public console::ConsoleSource {
 public:
  explicit ReplaySource(console::Recording rec) : index_(std::move(rec)) {}
  [[nodiscard]] const console::Recording& recording() const { return index_.recording(); }

  nlohmann::json info() override {
    const auto& r = index_.recording();
    nlohmann::json j;
    j["mode"] = "replay";
    j["scenario"] = console::info_json(r.info);
    j["control"] = {{"enabled", false}, {"process_control", false}, {"reason", "this is a replay of a recording"}};
    j["replay"] = {{"t0_s", index_.t0()}, {"t1_s", index_.t1()}, {"frames", r.frames.size()},
                   {"created_utc", r.created_utc}, {"writer", r.writer}, {"truncated", r.truncated}};
    return j;
  }

  nlohmann::json frame(uint16_t layer, uint64_t /*since*/, std::optional<double> t, bool /*wait*/) override {
    std::lock_guard lock(mu_);
    const double at = t.value_or(index_.t1());
    if (!cached_ || cached_t_ != at) {
      cached_ = index_.at(at);
      cached_t_ = at;
    }
    return console::frame_json(*cached_, index_.recording().info, layer, 0);
  }

  Answer command(const nlohmann::json& /*body*/, const std::string& who) override {
    spdlog::warn("command from {} refused: this is a replay", who);
    return {503, "this is a replay of a recording; it takes no commands"};
  }

  void refused(console::Refusal reason, int status, const std::string& who, const std::string& what) override {
    std::lock_guard lock(log_mu_);
    const double now = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    if (const auto k = log_limit_.take_suppressed(now)) spdlog::warn("suppressed {} refused requests", *k);
    if (log_limit_.admit(now)) spdlog::warn("request from {} refused ({}, {}): {}", who, status, console::refusal_name(reason), what);
  }

  std::string metrics() override {
    console::Exposition e;
    e.family("pheromesh_replay_frames", "gauge", "Frames in the recording being replayed.");
    e.sample("pheromesh_replay_frames", static_cast<double>(index_.recording().frames.size()));
    e.family("pheromesh_replay_duration_seconds", "gauge", "Time the recording spans.");
    e.sample("pheromesh_replay_duration_seconds", index_.t1() - index_.t0());
    return e.text();
  }

 private:
  console::ReplayIndex index_;
  std::mutex mu_;
  std::optional<console::ConsoleState> cached_;
  double cached_t_ = 0;
  std::mutex log_mu_;
  console::RefusalLimiter log_limit_{5, 10.0};  // as the ground station's
};

// The recording to a MAVLink station (--mavlink, docs/mavlink.md): the
// frames console::MavlinkReplay plays, sent over the ground station's
// non-blocking socket; a station's pause and continue steer the playback.
class ReplayStream {
 public:
  using Clock = console::MavlinkReplay::Clock;
  ReplayStream(const console::Recording& rec, double rate_hz, std::unique_ptr<groundstation::MavlinkLink> link)
      : link_(std::move(link)), replay_(rec, rate_hz, Clock::now()) {}

  void service(Clock::time_point now) {
    for (const auto& d : replay_.due(now)) link_->send(d);
    if (replay_.ended() && !end_logged_) {
      end_logged_ = true;
      spdlog::info("MAVLink: the recording has been played to its end ({:.1f} s); its last state is held",
                   replay_.played_s());
    }
    for (const auto& d : link_->receive(kDatagramsPerService)) {
      for (const auto& c : gate_.take(d.bytes, std::chrono::system_clock::now())) {
        const uint8_t result = replay_.command(c, now);
        log_command(c, result);
        link_->reply(d.from, replay_.ack(c, result));
      }
    }
  }

  void finish() const {
    const auto& f = replay_.stats();
    spdlog::info("MAVLink: sent {} frames in {} datagrams ({} dropped); commands taken {}, malformed input {}",
                 f.frames, f.datagrams, link_->dropped(), gate_.stats().accepted, gate_.malformed());
  }

 private:
  void log_command(const mavlink::CommandGate::Command& c, uint8_t result) const {
    const std::string who = "mavlink " + std::to_string(c.from_sysid) + "/" + std::to_string(c.from_compid);
    if (result == mavlink::kResultAccepted) {
      spdlog::info("command from {}: {} the playback at {:.1f} s of the recording", who,
                   replay_.paused() ? "paused" : "continued", replay_.played_s());
    } else {
      spdlog::warn(
          "command from {}: MAVLink command {} (param1 {}) is unsupported: a replay only pauses and "
          "continues its playback (docs/mavlink.md)",
          who, c.message.command, c.message.param[0]);
    }
  }

  static constexpr std::size_t kDatagramsPerService = 64;  // as the ground station's
  std::unique_ptr<groundstation::MavlinkLink> link_;
  console::MavlinkReplay replay_;
  // A replay holds no key and steers no swarm: unsigned commands are taken.
  mavlink::CommandGate gate_{std::nullopt, mavlink::CommandGate::Signatures::NotChecked};
  bool end_logged_ = false;
};

// The stream of --mavlink, or why not (the flag's value was checked by the parser).
core::Result<std::unique_ptr<ReplayStream>> open_stream(const ReplayOptions& o, const console::Recording& rec) {
  const auto target = console::parse_mavlink_target(o.mavlink);
  if (!target) return target.error();
  auto link = groundstation::MavlinkLink::open(target.value());
  if (!link) return link.error();
  if (!rec.info.geo) {
    spdlog::warn(
        "{} does not say where its map lies (recorded before recordings held the scenario's geo block): "
        "the MAVLink stream puts cell (0, 0) at 0 deg N 0 deg E with 1 m cells",
        o.file);
  }
  const uint32_t uavs = rec.info.uavs_expected, vehicles = std::min(uavs, console::kMavlinkMaxVehicles);
  spdlog::info(
      "MAVLink to udp:{} at {} Hz: the recording at its recorded pace, UAVs 0..{} as systems 1..{}, all {} "
      "as ADS-B traffic; a station's pause and continue pause and continue the playback",
      link.value()->peer(), o.mavlink_rate_hz, vehicles == 0 ? 0 : vehicles - 1, vehicles, uavs);
  return std::make_unique<ReplayStream>(rec, o.mavlink_rate_hz, std::move(link).value());
}

}  // namespace

int run_replay(const ReplayOptions& o) {
  auto rec = console::read_recording(o.file);
  if (!rec) {
    spdlog::error("{}", rec.error().message);
    return 2;
  }
  console::Recording r = std::move(rec).value();
  if (r.truncated) spdlog::warn("{}", r.warning);
  const double t0 = r.frames.empty() ? 0 : r.frames.front().t_s, t1 = r.frames.empty() ? 0 : r.frames.back().t_s;
  spdlog::info("{}: '{}' ({}), {} frames over {:.1f} s, recorded {} by {}", o.file, r.info.scenario_name, r.info.policy,
               r.frames.size(), t1 - t0, r.created_utc, r.writer);
  if (o.check) return 0;
  if (r.frames.empty()) {
    spdlog::error("{} holds no frames: nothing to replay", o.file);
    return 2;
  }
  ReplaySource source(std::move(r));
  console::ServerOptions so;
  so.bind = o.bind;
  so.port = o.port;
  console::ConsoleServer server(source, so);
  auto port = server.start();
  if (!port) {
    spdlog::error("{}", port.error().message);
    return 3;
  }
  std::unique_ptr<ReplayStream> stream;
  if (!o.mavlink.empty()) {
    auto opened = open_stream(o, source.recording());
    if (!opened) {
      spdlog::error("{}", opened.error().message);
      server.stop();
      return 2;
    }
    stream = std::move(opened).value();
  }
  runtime::install_shutdown_handlers();
  spdlog::info("replay at {} (Ctrl-C to stop)", server.url());
  // With a stream, a pass every 10 ms: --mavlink-rate-hz is at most 20 Hz.
  const auto pass = std::chrono::milliseconds(stream ? 10 : 100);
  while (!runtime::shutdown_requested()) {
    if (stream) stream->service(ReplayStream::Clock::now());
    std::this_thread::sleep_for(pass);
  }
  if (stream) stream->finish();
  server.stop();
  return 0;
}

}  // namespace pheromesh::cli
