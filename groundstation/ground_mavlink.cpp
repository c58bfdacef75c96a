// The ground station as a MAVLink system (--mavlink, docs/mavlink.md): the
// stream console::MavlinkFeed builds from the intake, sent from this loop
// over a non-blocking socket, and the signed commands mavlink::CommandGate
// admits, carried out as the web console's.
#include <arpa/inet.h>
#include <spdlog/spdlog.h>

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "ground_app.hpp"
#include "pheromesh/console/commands.hpp"
#include "pheromesh/mavlink/messages.hpp"
#include "pheromesh/report/report.hpp"

namespace pheromesh::groundstation {

using Clock = std::chrono::steady_clock;
namespace ml = pheromesh::mavlink;

namespace {

// The MAVLink key as 64 hex digits in OUT/mavlink.key, readable by its owner
// only: what an operator gives the ground-control station to sign commands.
std::string write_key(const std::string& out_dir, const ml::SecretKey& key) {
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  const std::string path = (std::filesystem::path(out_dir) / "mavlink.key").string();
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (fd < 0) return "";
  std::string hex;
  for (const uint8_t b : key.bytes) hex += fmt::format("{:02x}", b);
  hex += '\n';
  const bool ok = ::write(fd, hex.data(), hex.size()) == static_cast<ssize_t>(hex.size());
  ::close(fd);
  return ok ? path : "";
}

constexpr std::size_t kDatagramsPerService = 64;  // commands taken per pass: bounded work whatever a peer sends
constexpr uint64_t kRefusalsLogged = 5;           // refused commands logged one by one; all are counted
}  // namespace

void GroundApp::start_mavlink() {
  if (cfg_.mavlink.empty()) return;
  const auto target = console::parse_mavlink_target(cfg_.mavlink);
  if (!target) {
    log_->error("{}", target.error().message);  // main() checked it: only a programming error lands here
    return;
  }
  auto link = MavlinkLink::open(target.value());
  if (!link) {
    log_->error("{}; no MAVLink stream", link.error().message);
    return;
  }
  mavlink_ = std::move(link).value();
  if (control_key_) {
    mavlink_key_ = ml::derive_signing_key(*control_key_);
    const std::string path = write_key(cfg_.out_dir, *mavlink_key_);
    if (path.empty()) {
      log_->error(
          "cannot write the MAVLink key to {}/mavlink.key: commands from a ground-control station can be "
          "signed only by whoever derives it from the control key (docs/mavlink.md)",
          cfg_.out_dir);
    } else {
      log_->info("MAVLink signing key (for the ground-control station) in {}", path);
    }
  }
  mavlink_gate_ = std::make_unique<ml::CommandGate>(mavlink_key_);
  mavlink_feed_ = std::make_unique<console::MavlinkFeed>(scenario_, cfg_.mavlink_rate_hz, Clock::now());
  const uint32_t vehicles = std::min(cfg_.expect_uavs, console::kMavlinkMaxVehicles);
  log_->info(
      "MAVLink to udp:{} at {} Hz: UAVs 0..{} as systems 1..{}, all {} as ADS-B traffic, the ground station as system "
      "{}; {}",
      mavlink_->peer(), cfg_.mavlink_rate_hz, vehicles == 0 ? 0 : vehicles - 1, vehicles, cfg_.expect_uavs,
      console::kMavlinkGroundSysid,
      mavlink_key_ ? "commands signed with the swarm's MAVLink key are taken (docs/mavlink.md)"
                   : "no commands are taken (no control key)");
}

void GroundApp::service_mavlink() {
  if (!mavlink_) return;
  const auto now = Clock::now();
  mavlink_feed_->set_paused(paused_);
  for (const auto& d : mavlink_feed_->due(rec_, now)) mavlink_->send(d);
  for (const auto& d : mavlink_->receive(kDatagramsPerService)) {
    const ml::CommandGate::Stats before = mavlink_gate_->stats();
    for (const auto& c : mavlink_gate_->take(d.bytes, std::chrono::system_clock::now())) {
      const uint8_t result = carry_out(c);
      const std::optional<ml::Signing> signing =
          mavlink_key_ ? std::optional<ml::Signing>(
                             ml::Signing{&*mavlink_key_, 0, ml::signing_timestamp(std::chrono::system_clock::now())})
                       : std::nullopt;
      mavlink_->reply(d.from, mavlink_feed_->ack(c, result, signing));
    }
    const ml::CommandGate::Stats& after = mavlink_gate_->stats();
    const uint64_t refused = (after.unsigned_refused - before.unsigned_refused) +
                             (after.bad_signature - before.bad_signature) + (after.replayed - before.replayed);
    if (refused > 0 && mavlink_refusals_logged_ < kRefusalsLogged) {
      ++mavlink_refusals_logged_;
      log_->warn(
          "MAVLink: refused {} command(s) from {}: unsigned {}, badly signed {}, replayed {} so far (counted in "
          "OUT/mavlink.json)",
          refused, inet_ntoa(d.from.sin_addr), after.unsigned_refused, after.bad_signature, after.replayed);
    }
  }
}

uint8_t GroundApp::carry_out(const ml::CommandGate::Command& c) {
  using A = ml::CommandGate::Action;
  const std::string who = "mavlink " + std::to_string(c.from_sysid) + "/" + std::to_string(c.from_compid);
  console::ConsoleSource::Answer a;
  std::string what;
  switch (c.action) {
    case A::Pause:
    case A::Resume: {
      console::ConsoleCommand cc;
      cc.kind = c.action == A::Pause ? console::ConsoleCommand::Kind::Pause : console::ConsoleCommand::Kind::Resume;
      what = c.action == A::Pause ? "pause" : "resume";
      a = apply(cc);
      break;
    }
    case A::Stop:
      // pheromesh run's launcher stops the whole swarm in order; without one
      // (several hosts, containers) the End of --until-done ends the run.
      what = "stop";
      if (cfg_.attach) {
        a = {409, "a monitor ends nothing"};
      } else if (launcher_.connected()) {
        a = launcher_.ask("stop");
      } else {
        end_run();
        a = ended_ ? console::ConsoleSource::Answer{200, "the End went out"}
                   : console::ConsoleSource::Answer{500, "no End"};
      }
      break;
    case A::Unsupported:
      log_->warn("MAVLink command {} (param1 {}) from {} is not one pheromesh carries out (docs/mavlink.md)",
                 c.message.command, c.message.param[0], who);
      return ml::kResultUnsupported;
  }
  if (console_) {
    log_command(who, what, a);
  } else if (a.status == 200) {
    log_->info("command from {}: {} -> {}", who, what, a.message);
  } else {
    log_->warn("command from {}: {} refused ({}): {}", who, what, a.status, a.message);
  }
  return a.status == 200 ? ml::kResultAccepted : ml::kResultDenied;
}

void GroundApp::finish_mavlink() {
  if (!mavlink_) return;
  const auto& f = mavlink_feed_->stats();
  const auto& g = mavlink_gate_->stats();
  const auto& d = mavlink_gate_->frames();
  log_->info(
      "MAVLink: sent {} frames in {} datagrams ({} dropped); commands taken {}, refused unsigned {}, badly signed {}, "
      "replayed {}, malformed input {}",
      f.frames, f.datagrams, mavlink_->dropped(), g.accepted, g.unsigned_refused, g.bad_signature, g.replayed,
      mavlink_gate_->malformed());
  const nlohmann::json j = {{"target", mavlink_->peer()},
                            {"rate_hz", cfg_.mavlink_rate_hz},
                            {"frames_sent", f.frames},
                            {"datagrams_sent", f.datagrams},
                            {"datagrams_dropped", mavlink_->dropped()},
                            {"status_texts_dropped", f.texts_dropped},
                            {"commands",
                             {{"accepted", g.accepted},
                              {"unsigned_refused", g.unsigned_refused},
                              {"bad_signature", g.bad_signature},
                              {"replayed", g.replayed},
                              {"other_messages", g.other_messages}}},
                            {"frames_in",
                             {{"good", d.frames},
                              {"bad_crc", d.bad_crc},
                              {"truncated", d.truncated},
                              {"unknown_msgid", d.unknown_msgid},
                              {"bad_flags", d.bad_flags},
                              {"mavlink1", d.v1_frames},
                              {"skipped_bytes", d.skipped_bytes}}}};
  std::string error;
  if (!report::write_json(cfg_.out_dir, "mavlink.json", j, error)) log_->error("{}", error);
}

}  // namespace pheromesh::groundstation
