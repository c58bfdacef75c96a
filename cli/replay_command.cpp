#include "replay_command.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <mutex>
#include <thread>

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
  runtime::install_shutdown_handlers();
  spdlog::info("replay at {} (Ctrl-C to stop)", server.url());
  while (!runtime::shutdown_requested()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  server.stop();
  return 0;
}

}  // namespace pheromesh::cli
